"""The one registry of searchers: every name ``train``, ``personalise``, the study and the
benchmarks accept, what it is called in figures, what kind it is and how it is made.

Adding a searcher is one file and one line here: a module with an
:class:`~.protocol.AskTellSearcher` (or a runner of the environment, :mod:`.env_agent`) and an
:class:`Entry` naming it (docs/architecture.md, "Adding a searcher"). Nothing is imported until
a searcher is made, so naming the registry loads neither Optuna nor torch.

Kinds: ``learner`` (learns a policy that :mod:`.rollouts` can follow), ``walk`` (moves through
the environment without learning), ``searcher`` (ask/tell). Learners and walks count env steps
unless given evaluations; ask/tell searchers count evaluations.

Priors: ``none`` (a worker's prior is not used), ``optional`` (a warm start when one is given:
the personalise command gives the shipped population prior unless ``--no-prior``), ``needs``
(the population prior alone, and the ``+prior`` entries: the same searcher always warm-started,
so the study can run both).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from ..errors import ConfigError
from ..landscape.grid import Grid
from .env_agent import EnvAgent, attribute
from .prior import Prior
from .protocol import Searcher

KINDS = ("learner", "walk", "searcher")
PRIORS = ("none", "optional", "needs")
ANSWERS = ("scores", "preferences")


@dataclass(frozen=True)
class Entry:
    """One searcher of the registry.

    Attributes:
        name: its name on the command line and in every table.
        label: its name in figures and the report.
        kind: one of :data:`KINDS`.
        make: ``module:Class`` of an ask/tell searcher, or ``module:function`` of an agent's
            run (:mod:`.env_agent`); ``.module``: a module of this package.
        prior: one of :data:`PRIORS`.
        config: an agent's settings class, ``module:Class`` (None: none).
        options: settings of this entry beyond its class's defaults.
        observation: what the env shows an agent (``indices``, ``position``, ``continuous``).
        policy: what a learner's run leaves to roll out greedily: ``table``, ``network``,
            ``actor`` (SAC: no rollout over the discrete moves) or ``random`` (the random walk's
            uniform moves); None for the others.
        variant_of: the entry this one is a variant of (``bo`` for ``bo+prior``), or None.
        answers: what it is told: ``scores``, or ``preferences`` (which of the last two
            handovers was better: :mod:`.pairwise`).
        twins: it needs candidate twins of the worker (:mod:`.fitted_twin`).
        model: it recommends from a model of the worker (``recommend()``: the fitted twin's
            posterior, the preference GP), not from the lowest answer heard.
    """

    name: str
    label: str
    kind: str
    make: str
    prior: str = "none"
    config: str | None = None
    options: dict = field(default_factory=dict)
    observation: str = "indices"
    policy: str | None = None
    variant_of: str | None = None
    answers: str = "scores"
    twins: bool = False
    model: bool = False

    def __post_init__(self):
        if self.kind not in KINDS or self.prior not in PRIORS or self.answers not in ANSWERS:
            raise ConfigError(f"registry entry {self.name!r}: kind {self.kind!r} (use "
                              f"{', '.join(KINDS)}), prior {self.prior!r} (use "
                              f"{', '.join(PRIORS)}), answers {self.answers!r} (use "
                              f"{', '.join(ANSWERS)})")

    @property
    def unit(self) -> str:
        """What a bare number of its budget counts (``train --steps``)."""
        return "evaluations" if self.kind == "searcher" else "steps"

    @property
    def learns(self) -> bool:
        return self.kind == "learner"


def with_prior_variant(base: Entry) -> tuple[Entry, Entry]:
    """An entry that takes a prior, and its entry always given the worker's prior
    (``X+prior``): an ask/tell searcher starts from it, an agent of the environment starts
    every episode at its cell (:mod:`.env_agent`)."""
    return (replace(base, prior="optional"),
            replace(base, name=f"{base.name}+prior", label=f"{base.label} + prior",
                    prior="needs", variant_of=base.name))


SEARCHERS: dict[str, Entry] = {e.name: e for e in (
    *with_prior_variant(Entry("qlearning", "Q-learning (τ 0.7)", "learner",
                            ".qlearning:run_qlearning", config=".qlearning:QLearningConfig",
                            options={"temperature": "fixed"}, policy="table")),
    Entry("qlearning-adaptive", "Q-learning (adaptive τ)", "learner", ".qlearning:run_qlearning",
          config=".qlearning:QLearningConfig", options={"temperature": "adaptive"},
          policy="table"),
    Entry("dqn", "DQN", "learner", ".dqn:run_dqn", config=".dqn:DQNConfig",
          observation="position", policy="network"),
    *with_prior_variant(Entry("sac", "SAC", "learner", ".sac:run_sac", config=".sac:SACConfig",
                            observation="continuous", policy="actor")),
    *with_prior_variant(Entry("randomwalk", "random walk", "walk", ".walks:run_randomwalk",
                            config=".walks:WalkConfig", policy="random")),
    Entry("random-draws", "random draws", "walk", ".walks:run_random_draws"),
    Entry("hillclimb", "hill-climbing", "walk", ".walks:run_hillclimb"),
    Entry("random-order", "random order", "searcher", ".random_order:RandomOrderSearcher"),
    Entry("prior", "population prior", "searcher", ".prior_search:PriorSearcher", prior="needs"),
    *with_prior_variant(Entry("bo", "Bayesian optimisation (GP)", "searcher",
                              ".optuna_searchers:GPSearcher")),
    *with_prior_variant(Entry("tpe", "TPE", "searcher", ".optuna_searchers:TPESearcher")),
    *with_prior_variant(Entry("cmaes", "CMA-ES", "searcher", ".cmaes_search:CMAESSearcher")),
    *with_prior_variant(Entry("pso", "particle swarm", "searcher", ".pso:PSOSearcher")),
    *with_prior_variant(Entry("pairwise", "pairwise preferences (GP)", "searcher",
                              ".pairwise:PairwiseSearcher", answers="preferences",
                              model=True)),
    *with_prior_variant(Entry("pairwise-botorch", "pairwise preferences (BoTorch)", "searcher",
                              ".pairwise_botorch:BotorchPairwiseSearcher",
                              answers="preferences", model=True)),
    Entry("fitted-twin", "fitted twin", "searcher", ".fitted_twin:FittedTwinSearcher",
          prior="needs", twins=True, model=True),
)}
"""Tabular Q-learning (the paper's; under the published code's fixed temperature and the text's
adaptive one), DQN and SAC (stable-baselines3; SAC on the continuous-action env), a random walk
with the learner's moves and restarts (Q-learning, SAC and the walk also with every episode
started at the worker's prior: ``+prior``), random draws (uniform, with replacement: one score read
a step), hill-climbing with random restarts, and the ask/tell searchers: random order (uniform
without replacement), the population prior alone, Bayesian optimisation (Optuna's GP sampler),
TPE, CMA-ES, particle-swarm optimisation and a preference GP told only which of the last two
handovers was better (hand-written, and BoTorch's ``PairwiseGP`` with EUBO: the ``preferences``
extra), each also warm-started (``+prior``), and the twin fitted to the worker's first handovers
(it needs candidate twins)."""
LEARNERS = tuple(name for name, e in SEARCHERS.items() if e.learns)


def entry(name: str) -> Entry:
    """The registry's entry of ``name``; a one-line ConfigError for any other name."""
    if name not in SEARCHERS:
        raise ConfigError(f"searcher = {name!r} is not allowed (use {', '.join(SEARCHERS)})")
    return SEARCHERS[name]


def names(kind: str | None = None, variants: bool = True) -> tuple[str, ...]:
    """Every name of the registry, or those of one kind; ``variants`` False leaves out the
    variants of another entry."""
    return tuple(n for n, e in SEARCHERS.items() if (kind is None or e.kind == kind)
                 and (variants or e.variant_of is None))


def make(name: str, grid: Grid, seed: int, prior: Prior | None = None, twins=None,
         **env) -> Searcher:
    """The searcher ``name`` over ``grid``.

    Args:
        name: an entry of :data:`SEARCHERS`.
        grid: the cells it may evaluate.
        seed: its seed.
        prior: the worker's prior: given to the entries that take one, left out of the others;
            an entry that needs one is refused (one line) without it.
        twins: candidate twins of the worker (a :class:`~.fitted_twin.TwinLibrary`), for an
            entry that needs them (refused without; left out of the others).
        env: an agent's env settings (``episode_end``, ``target``, ``episode_steps``); an
            ask/tell searcher has no env and ignores them.
    """
    spec = entry(name)
    if spec.prior == "needs" and prior is None:
        raise ConfigError(f"searcher {name} needs a worker's prior (a population prior's "
                          "location and SD; use another searcher without one)")
    given = None if spec.prior == "none" else prior
    if spec.twins and twins is None:
        raise ConfigError(f"searcher {name} needs candidate twins of the worker (the "
                          "personalisation study's; use another searcher without them)")
    if spec.kind == "searcher":
        extra = {"twins": twins} if spec.twins else {}
        searcher = attribute(spec.make)(grid, seed, given, **extra)
        searcher.name = name
        return searcher
    return EnvAgent(grid, seed, given, name=name, runner=spec.make, config=spec.config,
                    observation=spec.observation, options=spec.options, **env)
