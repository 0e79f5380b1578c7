"""Workers the population prior does not know: what personalising is for.

The prior was fitted to twins of the survey's bodies, standing where they stand, with every
joint's full range. Three kinds of worker break that, and each is a change of the twin:

- **impaired** (:data:`~ergohandover.twin.joint_limits.IMPAIRMENTS`): a joint of the right arm
  whose range is restricted (a shoulder that cannot flex past 90°, an elbow that lacks 30° of
  extension, a wrist that cannot flex), the twin's joint limit narrowed;
- **a worker who steps** toward the box before taking it, where the prior's workers stand still
  (the twin's ``step`` stance);
- **a body of other proportions**: every length a fixed fraction of stature (Drillis &
  Contini's), where the prior's bodies are the survey's.

The fitted twin's candidates include the impaired bodies of the other workers
(:func:`impaired_candidates`), so that a restriction can be found from the angles.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

from ...twin.evaluate import Evaluator
from ...twin.joint_limits import IMPAIRMENTS, impaired

IMPAIRED, STEPS_OR_PROPORTIONS = "impaired", "steps or other proportions"
"""The groups these workers are reported in (beside in-model and out-of-model)."""
IN_MODEL, OUT_OF_MODEL = "in-model", "out-of-model"
"""The population's own workers (the prior was fitted to twins like theirs), and the same
workers with a modelling choice of the sensitivity study changed."""


def _impaired(name: str) -> Callable[[Evaluator], Evaluator]:
    def change(evaluator: Evaluator) -> Evaluator:
        return dataclasses.replace(evaluator, body=impaired(evaluator.body, name))
    return change


def _stepping(evaluator: Evaluator) -> Evaluator:
    return dataclasses.replace(evaluator, task=dataclasses.replace(evaluator.task,
                                                                   stance="step"))


def _fixed_ratio(evaluator: Evaluator) -> Evaluator:
    body = dataclasses.replace(evaluator.body, proportions="drillis-contini", measurements=())
    return dataclasses.replace(evaluator, body=body)


UNKNOWN_WORKERS: dict[str, tuple[str, Callable[[Evaluator], Evaluator]]] = {
    **{name: (IMPAIRED, _impaired(name)) for name in IMPAIRMENTS},
    "steps toward the box": (STEPS_OR_PROPORTIONS, _stepping),
    "fixed-ratio proportions": (STEPS_OR_PROPORTIONS, _fixed_ratio),
}
"""Each kind of worker the prior does not know: its group and the change of a worker's twin."""


def unknown_twin(name: str, evaluator: Evaluator) -> Evaluator:
    """The worker's twin changed into the kind ``name`` (:data:`UNKNOWN_WORKERS`)."""
    return UNKNOWN_WORKERS[name][1](evaluator)


def group_of(name: str) -> str | None:
    """The group a twin's name is reported in, or None if it is not one of these."""
    found = UNKNOWN_WORKERS.get(name)
    return None if found is None else found[0]


def twin_name(worker: str, kind: str) -> str:
    """A changed twin's name among the fitted twin's candidates."""
    return f"{worker}|{kind}"


def impaired_candidates(twins) -> list[tuple[str, Evaluator]]:
    """(name, evaluator) of the impaired twins among ``twins`` ((worker, kind, evaluator)),
    as candidates of a fitted twin."""
    return [(twin_name(w, kind), e) for w, kind, e in twins if group_of(kind) == IMPAIRED]


def own_candidate(name: str, worker: str) -> bool:
    """Whether the candidate ``name`` is ``worker`` (their own twin, or one of its changes),
    never a candidate of their own fitted twin."""
    return name == worker or name.startswith(f"{worker}|")
