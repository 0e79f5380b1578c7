"""The study's one typed configuration: a frozen dataclass per question (in the question's
``config.py``, its defaults there and only there), parsed once from
``experiments/configs/*.json`` (which list what differs from the defaults) and checked at
start-up.

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

from ..errors import ConfigError
from ..twin.anthropometry import BodySpec
from ..twin.evaluate import Evaluator
from ..twin.task import TaskSpec
from .ablations.config import AblationsConfig
from .accommodation.config import AccommodationConfig
from .baselines.config import BaselinesConfig
from .capture.config import CaptureConfig, capture_code_version
from .choices import DEFAULT_WORKER
from .landscape.config import LandscapeConfig
from .learning.config import LearningConfig
from .manikins.config import ManikinsConfig
from .participants.config import ParticipantsConfig
from .people.config import PeopleConfig, measured_data_version
from .personalise.config import PersonaliseConfig
from .population.config import PopulationConfig
from .registry import needed
from .robustness.config import RobustnessConfig
from .sensitivity.config import SensitivityConfig
from .shift.config import ShiftConfig, fatigue_code_version
from .stance.config import StanceConfig
from .typed_json import from_json, setting, short
from .validation.config import ValidationConfig


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
    shift: ShiftConfig = setting(ShiftConfig())

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
        questions it needs, directly or through another (:func:`.registry.needed`); for the
        capture part also the capture layer's code, for the shift part and the accommodation part
        (its workforce's shifts) the shift's section and the fatigue models' code,
        for the people part the measured handovers' derived figures."""
        sections = (part,) if part == "landscape" else (
            part, *dict.fromkeys(("landscape", *needed(part))))
        inputs = {name: dataclasses.asdict(getattr(self, name)) for name in sections}
        if part == "capture":  # its results are the capture layer's arithmetic
            inputs["capture_code"] = capture_code_version()
        if part in ("shift", "accommodation"):  # the fatigue models' arithmetic (the
            # accommodation part's workforce over the shift's plans)
            inputs["shift"] = dataclasses.asdict(self.shift)
            inputs["fatigue_code"] = fatigue_code_version()
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
