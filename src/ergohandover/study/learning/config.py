"""The study's section ``learning``: the targets, budgets and agents of the learning study, and
the run whose location the baselines carry the box to."""

from __future__ import annotations

import dataclasses

from ...envs.handover_env import EPISODE_ENDS
from ...envs.scores import LEXICOGRAPHIC, OBJECTIVES
from ...errors import ConfigError
from ...search.registry import SEARCHERS
from ...search.targets import GOALS
from ..choices import BOUNDARIES, DEFAULT_WORKER, GAZES, WORKERS
from ..typed_json import setting


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
