"""The study's section ``personalise``: which searcher finds one worker's own optimum in the
fewest handovers, with exact answers (the ceiling) and with answers as a site gets them."""

from __future__ import annotations

import dataclasses

from ...envs.scores import OBJECTIVES
from ...errors import ConfigError
from ...search.registry import SEARCHERS
from ...twin.anthropometry import BodySpec
from ...twin.evaluate import Evaluator
from ...twin.task import TaskSpec
from ..typed_json import setting
from .unknown_workers import IN_MODEL, UNKNOWN_WORKERS

MEASURED_VARIANTS = ("gaze off", "effort free share 7.9% (sustained holds)",
                     "ankle+knee+hip x0.5")
"""The sensitivity variants a worker's twin differs by out of model (the personalisation
study's measured answers): the gaze task, the effort task's free share and the legs' joint
preferences, three of the choices that move the optimum most."""

PERSONALISE_SEARCHERS = ("random-order", "prior", "cmaes", "cmaes+prior", "pso", "pso+prior",
                         "qlearning", "qlearning+prior", "randomwalk")
"""The personalisation study's searchers by default (``+prior``: warm-started by the worker's
prior; a learner's every episode starts at it). Those whose proposals cost the most (Bayesian
optimisation, TPE, SAC: experiments/bench_searchers.py) run in
configs/personalise_full.json (on Ray if wanted), so that the default study keeps its time
budget."""


@dataclasses.dataclass(frozen=True)
class PersonaliseConfig:
    """How many handovers each searcher needs to find one worker's optimum: the population's
    first ``workers`` workers, ``runs`` paired runs each, stopped at the optimum or at the
    largest budget (``budget_caps``: a lower largest budget for a searcher whose proposals cost
    seconds each, measured by experiments/bench_searchers.py)."""

    workers: int = setting(30, lo=1)
    runs: int = setting(10, lo=1)
    seed: int = setting(28, lo=0)
    objective: str = setting("paper_postural", choices=OBJECTIVES)
    searchers: tuple[str, ...] = setting(PERSONALISE_SEARCHERS, choices=SEARCHERS)
    budgets: tuple[int, ...] = setting((10, 25, 50, 100, 250, 1000), lo=1)
    # Bayesian optimisation's proposals cost most (the GP's refit and acquisition search grow
    # with the trials), then TPE's and SAC's (a gradient step per env step):
    # experiments/bench_searchers.py measures them. The default study caps them so that it
    # stays within 45 minutes on 2 cores, and configs/personalise_full.json runs them further
    # (and Bayesian optimisation without the prior).
    budget_caps: dict[str, int] = setting({"bo+prior": 25, "tpe": 250, "tpe+prior": 250,
                                           "sac": 100, "sac+prior": 100}, lo=1)
    # Answers as a site gets them (measured_answers.py): equal budgets, a model's stop, the
    # recommendation's true regret; posture errors of each SD [deg], raters of each ICC (the
    # intra-rater ICC of the final REBA score of an expert, 0.89 (0.78-0.95), and a novice, 0.51
    # (0.25-0.74): Balogh et al. 2025, PLOS One 20(5):e0323262, 21 videos rated twice), and
    # out of model the first `measured_variant_workers` workers with each sensitivity variant;
    # each searcher up to its budget cap; Bayesian optimisation, whose proposals cost the
    # most, and budgets beyond 25 in configs/personalise_full.json.
    measured_searchers: tuple[str, ...] = setting(
        ("random-order", "prior", "cmaes+prior", "pso+prior", "pairwise+prior",
         "qlearning+prior", "fitted-twin"),
        choices=SEARCHERS)
    measured_sds: tuple[float, ...] = setting((0.0, 2.0, 5.0, 10.0), lo=0, unit="deg")
    measured_iccs: tuple[float, ...] = setting((0.89, 0.51), lo=0, hi=1)
    # An IMU suit's error (the robustness part's measured error model, Schall et al. 2016),
    # its SDs times each factor.
    measured_imu: tuple[float, ...] = setting((1.0,), lo=0)
    measured_budgets: tuple[int, ...] = setting((5, 10, 25), lo=2)
    # Runs per worker: `headline_runs` under the headline's answers (postures measured with
    # `headline_sd` of error; for the population's own workers also the IMU suit's error at its
    # published SDs, the other answers a target is set for), `measured_runs` under the others
    # (configs/personalise_full.json: 5 under every answer model).
    measured_runs: int = setting(1, lo=0)
    headline_sd: float = setting(5.0, lo=0, unit="deg")
    headline_runs: int = setting(5, lo=0)
    measured_variants: tuple[str, ...] = setting(MEASURED_VARIANTS)
    measured_variant_workers: int = setting(5, lo=0)
    # Workers the prior does not know (unknown_workers.py): the first `measured_unknown_workers`
    # workers changed into each kind, answered as the headline's answers only.
    measured_unknown: tuple[str, ...] = setting(tuple(UNKNOWN_WORKERS),
                                                 choices=tuple(UNKNOWN_WORKERS))
    measured_unknown_workers: int = setting(5, lo=0)
    # The stopping rule's level: stop once the searcher's model gives its recommendation this
    # probability of being the worker's optimum (the target share of workers handed over at
    # their optimum: a calibrated model stopped here meets it).
    stop_level: float = setting(0.8, lo=0, hi=1)

    def __post_init__(self):
        from ..sensitivity.variants import variants  # the variants' names, of the default twin

        known = [v.name for v in variants(Evaluator(BodySpec(), TaskSpec()))]
        for name in self.measured_variants:
            if name not in known:
                raise ConfigError(f"personalise.measured_variants: {name!r} is not a "
                                  f"sensitivity variant (use {', '.join(known)})")
        for name in self.budget_caps:
            if name not in SEARCHERS:
                raise ConfigError(f"personalise.budget_caps: {name!r} names no searcher (use "
                                  f"{', '.join(SEARCHERS)})")
        for name in self.searchers:
            if SEARCHERS[name].twins:
                raise ConfigError(f"personalise.searchers: {name!r} needs candidate twins, "
                                  "which only the runs with answers as a site gets them give "
                                  "(use it in measured_searchers)")
            if SEARCHERS[name].answers != "scores":
                raise ConfigError(f"personalise.searchers: {name!r} is told preferences, and "
                                  "these runs stop at the worker's optimum score (use it in "
                                  "measured_searchers)")

    def runs_of(self, answers, twin: str | None = None) -> int:
        """Runs per worker under an answer model (:class:`.measured_answers.Answers`); a worker
        the prior does not know (``twin``: its kind) runs under the headline's only, and the
        population's own (``in-model``) also under the IMU suit's published error."""
        headline = answers.kind == "posture" and answers.level == self.headline_sd
        if twin in UNKNOWN_WORKERS:
            return self.headline_runs if headline else 0
        published_imu = answers.kind == "imu" and answers.level == 1 and twin == IN_MODEL
        return self.headline_runs if headline or published_imu else self.measured_runs

    def budgets_of(self, searcher: str, measured: bool = False) -> list[int]:
        """The budgets a searcher is reported at (``measured``: with answers as a site gets
        them): those up to its cap."""
        budgets = self.measured_budgets if measured else self.budgets
        cap = self.budget_caps.get(searcher, max(budgets))
        return [b for b in sorted(budgets) if b <= cap]
