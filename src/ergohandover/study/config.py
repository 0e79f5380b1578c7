"""The study's one typed configuration: a frozen dataclass per part, the defaults here and only
here, parsed once from ``experiments/configs/*.json`` (which list what differs from the
defaults) and checked at start-up.

Every unknown key and every bad value is refused with one line naming its key path, the value and
what is allowed (:mod:`.typed_json`); the cross-references between parts (a target that a
budget or the baselines name, a worker name) are checked here. What a part's results depend on
(:meth:`StudyConfig.part_inputs`) is hashed from this typed form, defaults included, so a
configuration file that spells a default out and one that leaves it out are the same study.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Any

from ..envs.handover_env import EPISODE_ENDS
from ..envs.scores import LEXICOGRAPHIC, OBJECTIVES
from ..errors import ConfigError
from ..landscape.grid import BOUNDARY_NAMES, DEFAULT_STEP
from ..search.registry import SEARCHERS
from ..search.targets import GOALS
from ..twin.anthropometry import PERCENTILES, BodySpec
from ..twin.evaluate import Evaluator
from ..twin.task import TaskSpec
from .config_measured import (
    CaptureConfig,
    PeopleConfig,
    capture_code_version,
    measured_data_version,
)
from .config_personalise import PersonaliseConfig
from .config_workplace import AccommodationConfig, ManikinsConfig
from .typed_json import from_json, setting, short
from .workforce import Workforce

BOUNDARIES = BOUNDARY_NAMES
GAZES = ("on", "off")
WORKERS = tuple(sorted(PERCENTILES))
DEFAULT_WORKER = "p50-male"
"""The study's worker (the paper's is a 50th-percentile man), and the population's reference."""


@dataclasses.dataclass(frozen=True)
class LandscapeVariants:
    """The landscape's statistics under each boundary and gaze setting, on a coarser grid."""

    boundaries: tuple[str, ...] = setting(("paper-code", "body"), choices=BOUNDARIES)
    gaze: tuple[str, ...] = setting(("on", "off"), choices=GAZES)
    step: float = setting(0.01, positive=True, unit="m")


@dataclasses.dataclass(frozen=True)
class LandscapeConfig:
    """The default worker's exhaustive landscape: the paper's grid (paper-code boundary, 3 mm)."""

    boundary: str = setting("paper-code", choices=BOUNDARIES)
    step: float = setting(DEFAULT_STEP, positive=True, unit="m")
    gaze: str = setting("on", choices=GAZES)
    variants: LandscapeVariants = setting(LandscapeVariants())


@dataclasses.dataclass(frozen=True)
class GridOverride:
    """A target's own boundary or step (null: the landscape's)."""

    boundary: str | None = setting(None, choices=BOUNDARIES)
    step: float | None = setting(None, positive=True, unit="m")


@dataclasses.dataclass(frozen=True)
class Target:
    """A landscape, the objective the agents minimise on it and which cells count as found."""

    name: str = setting()
    objective: str = setting("paper_postural", choices=(*OBJECTIVES, LEXICOGRAPHIC))
    goal: str = setting("minimum", choices=GOALS)
    worker: str = setting(DEFAULT_WORKER, choices=WORKERS)
    gaze: str | None = setting(None, choices=GAZES)
    grid: GridOverride = setting(GridOverride())


DEFAULT_TARGETS = (
    Target("paper", goal="minimum"), Target("paper-reward", goal="reward"),
    Target("reba", "reba"), Target("reba_ab", "reba_ab"), Target("rula", "rula"),
    Target("gaze-off", gaze="off", grid=GridOverride(step=0.01)),
    Target("body", grid=GridOverride("body", 0.01)),
    Target("p5-female", worker="p5-female", grid=GridOverride(step=0.006)),
    Target("lexicographic", LEXICOGRAPHIC, "reward"))


@dataclasses.dataclass(frozen=True)
class StepBudget:
    """One budget of the learning study in score evaluations: one of the paper's caps under one
    mapping of wall clock to evaluations.

    Attributes:
        name: ``paper-5min`` at the paper's rate, ``paper-5min@3150`` at another.
        rate: the mapping [evaluations/s].
        cap_s: the paper's cap it stands for [s].
        steps: evaluations (env steps).
    """

    name: str
    rate: float
    cap_s: float
    steps: int


@dataclasses.dataclass(frozen=True)
class LearningConfig:
    """Every agent on every target at the paper's 2- and 5-minute caps, counted in evaluations
    under three rates, in paired runs (run r of a target has one seed for every agent).

    ``budgets`` are the caps in evaluations at the paper's rate (its Unity scored ~315 locations per
    second); ``rates`` map them to evaluations per second: 315, a tenth and ten times. Each
    agent but DQN runs ``runs`` times per target at the largest budget, stopped at its first
    target cell (``oracle_stop``), and every smaller budget is read from that run; DQN (a
    network update a step) runs ``dqn_runs`` times on ``dqn_targets`` at the paper's rate only.
    ``full_runs`` runs per paper-rate budget go to the cap: the best location each agent keeps
    (the baselines carry the box there) and ``rollouts`` greedy walks of its policy.
    ``wall_caps_s`` of wall clock on the ``wall_targets``: the paper's own protocol
    (configs/paper.json). ``margin``: the equivalence margin on success rates; ``alpha``: every
    test's level after Holm's correction (docs/learning.md)."""

    PAPER_RATE = 315.0
    """The paper's evaluations per second (3.4 M locations in ~3 h): the rate of ``budgets``."""

    seed: int = setting(2024, lo=0)
    runs: int = setting(100, lo=1)
    dqn_runs: int = setting(20, lo=1)
    agents: tuple[str, ...] = setting(("qlearning", "qlearning-adaptive", "dqn", "randomwalk",
                                       "random-draws", "hillclimb"), choices=SEARCHERS)
    budgets: dict[str, int] = setting({"paper-2min": 37_800, "paper-5min": 94_500}, lo=1)
    rates: tuple[float, ...] = setting((315.0, 31.5, 3150.0), positive=True,
                                       unit="evaluations/s")
    wall_caps_s: tuple[float, ...] = setting((), positive=True, unit="s")
    wall_targets: tuple[str, ...] = setting(())
    dqn_targets: tuple[str, ...] = setting(("paper",))
    full_runs: int = setting(10, lo=0)
    rollouts: int = setting(20, lo=0)
    oracle_stop: bool = setting(True)
    episode_end: str = setting("none", choices=EPISODE_ENDS)
    margin: float = setting(0.10, lo=0.01, hi=0.5)
    alpha: float = setting(0.05, lo=0.001, hi=0.2)
    targets: tuple[Target, ...] = setting(DEFAULT_TARGETS)

    def __post_init__(self):
        if self.budgets and self.PAPER_RATE not in self.rates:
            raise ConfigError(f"learning.rates = {list(self.rates)} is not allowed without "
                              f"{self.PAPER_RATE:g} (the paper's rate: DQN, the full runs and "
                              "the budgets other parts name are at it)")
        names = [b.name for b in self.step_budgets()]
        if len(set(names)) < len(names):
            twice = next(n for n in names if names.count(n) > 1)
            raise ConfigError(f"learning.budgets: {twice!r} is named twice (a budget and a "
                              "rate give it; rename the budget)")

    def step_budgets(self, rate: float | None = None) -> list[StepBudget]:
        """Every step budget (or those at ``rate``), fewest evaluations first: each of
        ``budgets`` at each of ``rates``, named as in ``budgets`` at the paper's rate and with
        ``@<rate>`` appended at another."""
        out = [StepBudget(name if r == self.PAPER_RATE else f"{name}@{r:g}", r,
                          steps / self.PAPER_RATE, round(steps * r / self.PAPER_RATE))
               for r in self.rates for name, steps in self.budgets.items()
               if rate is None or r == rate]
        return sorted(out, key=lambda b: (b.steps, b.rate))


@dataclasses.dataclass(frozen=True)
class LearnedLocation:
    """The learning part's run whose best location the baselines carry the box to."""

    target: str = setting("paper")
    agent: str = setting("qlearning", choices=SEARCHERS)
    budget: str = setting("paper-5min")


@dataclasses.dataclass(frozen=True)
class BaselinesConfig:
    render: bool = setting(True)
    seed: int = setting(0, lo=0)
    other_starts: int = setting(5, lo=0)
    starts_seed: int = setting(2026, lo=0)
    reach: dict[str, float] = setting({"paper-code": 0.04, "body": 0.05}, positive=True,
                                      unit="m")
    location: LearnedLocation = setting(LearnedLocation())


@dataclasses.dataclass(frozen=True)
class AblationsConfig:
    ik_boundary: str = setting("paper-code", choices=BOUNDARIES)
    ik_step: float = setting(0.015, positive=True, unit="m")


@dataclasses.dataclass(frozen=True)
class ParticipantsConfig:
    workers: tuple[str, ...] = setting(("p5-female", "p50-female", "p95-female", "p5-male",
                                        "p50-male", "p95-male"), choices=WORKERS)
    step: float = setting(0.006, positive=True, unit="m")


@dataclasses.dataclass(frozen=True)
class PopulationConfig:
    size: int = setting(Workforce.size, lo=1)
    seed: int = setting(Workforce.seed, lo=0)
    female_share: float = setting(Workforce.female_share, lo=0, hi=1)
    reference: str = setting(DEFAULT_WORKER, choices=WORKERS)
    boundary: str = setting("paper-code", choices=BOUNDARIES)
    step: float = setting(0.01, positive=True, unit="m")
    bootstrap: int = setting(2000, lo=1)
    bootstrap_seed: int = setting(7, lo=0)


@dataclasses.dataclass(frozen=True)
class SensitivityConfig:
    step: float = setting(0.01, positive=True, unit="m")


@dataclasses.dataclass(frozen=True)
class ValidationConfig:
    optimum_of: str = setting("paper_postural", choices=OBJECTIVES)


@dataclasses.dataclass(frozen=True)
class RobustnessConfig:
    draws: int = setting(4000, lo=1)
    seed: int = setting(11, lo=0)
    angle_sds: tuple[float, ...] = setting((0.0, 1.0, 2.0, 5.0, 10.0), lo=0, unit="deg")
    robust_sd: float = setting(5.0, positive=True, unit="deg")
    # How far above the error-free optimum a location may score and still be a candidate for
    # the robust location "among optima" (the one that does not trade the worker's posture).
    robust_tolerance: int = setting(0, lo=0)
    structure: str = setting("independent", choices=("independent", "bilateral"))
    placement_radii_cm: tuple[float, ...] = setting((0.57, 1.0, 2.0, 5.0), positive=True,
                                                    unit="cm")
    stride: int = setting(3, lo=1)
    screen_draws: int = setting(128, lo=1)
    keep: int = setting(32, lo=1)
    radius: int = setting(2, lo=0)
    worker_draws: int = setting(1000, lo=1)
    worker_stride: int = setting(2, lo=1)
    # Each resample and split re-chooses the one-size cells over every worker's grid (0.1 s).
    resamples: int = setting(300, lo=1)
    splits: int = setting(150, lo=1)


@dataclasses.dataclass(frozen=True)
class StanceConfig:
    """The headline comparisons for a worker who may step toward the box (the task's stance
    ``step``) beside the planted one: the stepping worker's own landscape every ``step`` on the
    landscape's boundary, and the comparisons under posture error (``angle_sds``, ``draws``
    measurements each, seeded)."""

    step: float = setting(0.01, positive=True, unit="m")
    angle_sds: tuple[float, ...] = setting((0.0, 5.0), lo=0, unit="deg")
    draws: int = setting(4000, lo=1)
    seed: int = setting(27, lo=0)


READS = {"baselines": ("learning",),
         "robustness": ("learning", "baselines", "participants", "population", "sensitivity"),
         "personalise": ("population",),
         "stance": ("learning", "baselines", "participants"),
         "manikins": ("learning", "baselines", "participants", "population", "sensitivity",
                      "robustness"),
         "accommodation": ("learning", "baselines", "participants", "population",
                           "sensitivity", "robustness")}
"""Parts that read another part's results besides the landscape's: the baselines carry the box
to the location the learner found; the robustness part reads the baselines' locations, the
population's one-size locations and the landscapes of the participants, workers and variants;
the personalisation part reads the population's workers and their optima (the prior); the
manikins and accommodation parts read the robustness part's headline locations."""


@dataclasses.dataclass(frozen=True)
class StudyConfig:
    """The whole study: one section per part."""

    landscape: LandscapeConfig = setting(LandscapeConfig())
    learning: LearningConfig = setting(LearningConfig())
    baselines: BaselinesConfig = setting(BaselinesConfig())
    ablations: AblationsConfig = setting(AblationsConfig())
    participants: ParticipantsConfig = setting(ParticipantsConfig())
    population: PopulationConfig = setting(PopulationConfig())
    sensitivity: SensitivityConfig = setting(SensitivityConfig())
    validation: ValidationConfig = setting(ValidationConfig())
    robustness: RobustnessConfig = setting(RobustnessConfig())
    personalise: PersonaliseConfig = setting(PersonaliseConfig())
    stance: StanceConfig = setting(StanceConfig())
    capture: CaptureConfig = setting(CaptureConfig())
    people: PeopleConfig = setting(PeopleConfig())
    manikins: ManikinsConfig = setting(ManikinsConfig())
    accommodation: AccommodationConfig = setting(AccommodationConfig())

    def __post_init__(self):
        learning = self.learning
        names = [t.name for t in learning.targets]
        if not names:
            raise ConfigError("learning.targets = [] is not allowed (expected at least one "
                              "target)")
        if len(set(names)) < len(names):
            twice = next(n for n in names if names.count(n) > 1)
            raise ConfigError(f"learning.targets: name = {twice!r} is given twice (a target's "
                              "name is its key)")
        for key in ("wall_targets", "dqn_targets"):
            for name in getattr(learning, key):
                if name not in names:
                    raise ConfigError(f"learning.{key} = {name!r} names no target (use "
                                      f"{', '.join(names)})")
        if not learning.budgets and not (learning.wall_caps_s and learning.wall_targets):
            raise ConfigError("learning.budgets = {} is not allowed without wall_caps_s and "
                              "wall_targets (every run needs a budget)")
        spec = self.baselines.location
        budgets = self.budget_names(spec.target)
        for key, value, allowed in (("target", spec.target, names),
                                    ("agent", spec.agent, learning.agents),
                                    ("budget", spec.budget, budgets)):
            if value not in allowed:
                raise ConfigError(f"baselines.location.{key} = {value!r} names no run of the "
                                  f"learning part (use {', '.join(allowed) or 'none'})")

    @classmethod
    def from_dict(cls, data: Any) -> StudyConfig:
        """The study of a parsed JSON object (ConfigError for any bad key or value)."""
        return from_json(cls, data)

    @classmethod
    def load(cls, path: Path, overrides: tuple[str, ...] = ()) -> StudyConfig:
        """The study of a configuration file, with ``KEY=VALUE`` overrides (``--set``)."""
        try:
            data = json.loads(Path(path).read_text())
        except (OSError, ValueError) as exc:
            raise ConfigError(f"config = '{path}' is not a readable JSON file "
                              f"({type(exc).__name__})") from None
        for item in overrides:
            apply_override(data, item)
        return cls.from_dict(data)

    def budget_names(self, target: str) -> list[str]:
        """The names of every budget a target's runs get: the step budgets, and the wall-clock
        caps (``wall-<s>s``) on a wall target."""
        learning = self.learning
        names = list(learning.budgets)
        if target in learning.wall_targets:
            names += [wall_budget_name(cap) for cap in learning.wall_caps_s]
        return names

    def part_inputs(self, part: str) -> dict[str, Any]:
        """What a part's results depend on (hashed into its manifest): its own section and, for
        every part after it, the landscape's (they all read the landscape) and those of the
        parts whose results it reads (:data:`READS`); for the capture part also the capture
        layer's code, for the people part the measured handovers' derived figures."""
        sections = (part,) if part == "landscape" else (part, "landscape", *READS.get(part, ()))
        inputs = {name: dataclasses.asdict(getattr(self, name)) for name in sections}
        if part == "capture":  # its results are the capture layer's arithmetic
            inputs["capture_code"] = capture_code_version()
        if part == "people":  # its results are the derived figures' comparison with the twin
            inputs["measured_data"] = measured_data_version()
        return inputs

    def task(self, gaze: str | None = None, stance: str = "fixed") -> TaskSpec:
        """The study's task: the default box, with the landscape's gaze (or ``gaze``), the
        feet planted (or ``stance``)."""
        return TaskSpec(gaze=gaze or self.landscape.gaze, stance=stance)

    def evaluator(self, worker: str = DEFAULT_WORKER, gaze: str | None = None,
                  stance: str = "fixed") -> Evaluator:
        """The study's evaluator of a named worker: the default model with the study's task."""
        return Evaluator(BodySpec.from_percentile(worker), self.task(gaze, stance))


def wall_budget_name(cap_s: float) -> str:
    """The budget name of a wall-clock cap: ``wall-120s``."""
    return f"wall-{cap_s:g}s"


def apply_override(data: dict, item: str) -> None:
    """Set ``KEY.PATH=VALUE`` in ``data`` (VALUE as JSON, else as a string)."""
    key, sep, text = item.partition("=")
    if not sep or not key:
        raise ConfigError(f"set = {short(item)} is not allowed (expected KEY=VALUE, e.g. "
                          "learning.runs=20)")
    try:
        value = json.loads(text)
    except ValueError:
        value = text
    *parents, last = key.split(".")
    node = data
    for name in parents:
        child = node.get(name, {}) if isinstance(node, dict) else None
        if not isinstance(child, dict):
            raise ConfigError(f"set = {short(item)}: {key} does not name a setting")
        node[name] = child
        node = child
    node[last] = value
