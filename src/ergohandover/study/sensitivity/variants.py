"""Which modelling choices move the result? One landscape per variant of the twin, the task or
the angle convention, and what each does to the minima, the optimum and the study's conclusion.

A variant changes one thing of the default :class:`~ergohandover.twin.evaluate.Evaluator`:
a solver cost weight (×0.5, ×2), the joint preferences, the knee strategy (one whole-body
strategy alone, no effort task, no hamstrings' limit), the gaze task, the joint limits, the
trunk-angle convention, or the box. :func:`sensitivity_row` summarises its landscape: the
minimum of each objective and the share of feasible points at it, the optimum (the most
symmetric minimiser of the paper score, the study's rule), its shift from the default's optimum
on the same grid, and whether the paper's conclusion — the optimised location scores lower than
the shortest-distance location from every one of its five starts — still holds.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from ...landscape import Landscape
from ...landscape.stats import minimisers, optimum
from ...twin.evaluate import Evaluator, evaluate_arrays
from ...twin.solver import STRATEGY_DEG
from ..baselines.comparison import PAPER_STARTS, shortest_distance

OBJECTIVES = ("paper_postural", "reba", "rula")
SOLVER_WEIGHTS = ("hand", "palm", "gaze", "balance", "effort", "hamstring_stiffness")
SUSTAINED_FREE_SHARE = 0.079  # endurance limit of sustained static holds (Björkstén & Jonsson 1977)
FACTORS = (0.5, 2.0)
LEGS = ("ankle_flexion", "knee_flexion", "hip_flexion")


@dataclasses.dataclass(frozen=True)
class Variant:
    """One modelling choice changed from the default.

    ``settings``, ``task`` and ``scoring``: field -> value overrides of the evaluator's
    SolverSettings, TaskSpec and ScoringSettings; ``evaluation``: of the Evaluator's own fields
    (``trunk_reference``).
    """

    group: str
    name: str
    settings: dict[str, Any] = dataclasses.field(default_factory=dict)
    task: dict[str, Any] = dataclasses.field(default_factory=dict)
    scoring: dict[str, Any] = dataclasses.field(default_factory=dict)
    evaluation: dict[str, Any] = dataclasses.field(default_factory=dict)

    def evaluator(self, base: Evaluator) -> Evaluator:
        """``base`` with this variant's changes."""
        return dataclasses.replace(
            base, settings=dataclasses.replace(base.settings, **self.settings),
            task=dataclasses.replace(base.task, **self.task),
            scoring=dataclasses.replace(base.scoring, **self.scoring), **self.evaluation)


def variants(base: Evaluator) -> list[Variant]:
    """The default and every variant of the sensitivity study, in table order."""
    out = [Variant("default", "default")]
    for weight in SOLVER_WEIGHTS:
        value = getattr(base.settings, weight)
        out += [Variant("solver weight", f"{weight} x{f:g}", {weight: value * f}) for f in FACTORS]
    margin = base.settings.balance_margin
    out += [Variant("solver weight", f"balance margin x{f:g}", {"balance_margin": margin * f})
            for f in FACTORS]
    out.append(Variant("solver weight", "effort free share 7.9% (sustained holds)",
                       {"effort_free": SUSTAINED_FREE_SHARE}))
    out += [Variant("knee strategy", f"{name} start only", {"strategies": (name,)})
            for name in STRATEGY_DEG]
    out.append(Variant("knee strategy", "no effort task (the straight-legged twin)",
                       {"effort": 0.0}))
    out.append(Variant("knee strategy", "no hamstrings' limit", {"hamstring_stiffness": 0.0}))
    out += [Variant("joint preference", f"all joints x{f:g}", {"preference_scale": f})
            for f in FACTORS]
    out += [Variant("joint preference", f"ankle+knee+hip x{f:g}",
                    {"joint_preference_scales": tuple((j, f) for j in LEGS)}) for f in FACTORS]
    other = "off" if base.task.gaze == "on" else "on"
    out.append(Variant("gaze", f"gaze {other}", task={"gaze": other}))
    out.append(Variant("joint limits", "range of motion x0.75", {"range_of_motion": 0.75}))
    out.append(Variant("trunk angle", "trunk relative to the pelvis",
                       evaluation={"trunk_reference": "pelvis"}))
    mass = base.task.box_mass_kg
    out += [Variant("box", f"box mass x{f:g}", task={"box_mass_kg": mass * f})
            for f in (0.5, 1.5)]
    span, width = base.task.handle_span, base.task.box_width
    # Half the span does not fit the default box: the box narrows with it, keeping their gap.
    out.append(Variant("box", "handle span x0.5",
                       task={"handle_span": span * 0.5, "box_width": width - span * 0.5}))
    out.append(Variant("box", "handle span x1.5", task={"handle_span": span * 1.5}))
    return out


def conclusion_holds(landscape: Landscape, evaluator: Evaluator,
                     score: str = "paper_postural") -> tuple[bool, int, int]:
    """Does the landscape's optimum score lower than the shortest-distance location from each of
    the paper's five starts? An infeasible shortest-distance location counts as a win.

    Returns:
        (holds, the optimum's score, the best score among the shortest-distance locations).
    """
    _, best = optimum(landscape, score)
    naive = shortest_distance(PAPER_STARTS, landscape.grid.boundary)
    rows = evaluate_arrays(np.vstack([best, naive]), evaluator, columns=("flags", score))
    ours = int(rows[score][0])
    theirs = rows[score][1:][rows["flags"][1:] == 0].astype(int)
    closest = int(theirs.min()) if len(theirs) else -1
    return bool((theirs > ours).all()), ours, closest


def sensitivity_row(variant: Variant, landscape: Landscape, evaluator: Evaluator,
                    reference: np.ndarray | None) -> dict[str, Any]:
    """The table row of one variant's landscape.

    Args:
        variant: the choice it changes.
        landscape: its landscape.
        evaluator: the evaluator it was swept with.
        reference: the default's optimum on the same grid (worker frame [m]); None: no
            reference (the shift is NaN).
    """
    row: dict[str, Any] = {"group": variant.group, "variant": variant.name,
                           "grid": landscape.grid.describe(),
                           "feasible_fraction": float(landscape.feasible.mean())}
    feasible = landscape.feasible.sum()
    for score in OBJECTIVES:
        cells = minimisers(landscape, score)
        row[f"{score}_min"] = int(landscape.arrays[score][cells[0]])
        row[f"{score}_fraction_at_min"] = len(cells) / feasible
    _, best = optimum(landscape, "paper_postural")
    row.update(optimum_x=best[0], optimum_y=best[1], optimum_z=best[2])
    row["shift_cm"] = (float("nan") if reference is None
                       else float(np.linalg.norm(best - reference) * 100))
    holds, ours, closest = conclusion_holds(landscape, evaluator)
    row.update(optimum_paper_postural=ours, best_shortest_distance_paper_postural=closest,
               conclusion_holds=holds)
    return row
