"""The paper's participant study, in simulation: workers of different sizes at three locations.

The paper deployed one optimised location (found for one Unity model) to five VR participants
and compared it with the shortest-distance location from two start points, aligned with the
worker and offset 1 m to the left. Here each simulated worker — a 5th-percentile woman to a
95th-percentile man — is scored at (a) the location optimised for the default worker (what the
paper deploys to everyone), (b) the location optimised for that worker, and (c) the
shortest-distance location from each start point.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...ergonomics import OBJECTIVES
from ...landscape import Landscape
from ...twin.evaluate import Evaluator, evaluate
from ..baselines.comparison import optimised, shortest_distance
from ..choices import DEFAULT_WORKER

# The VR study's start points (worker frame, m): aligned with the worker, and 1 m to its left.
VR_STARTS = {"aligned": (0.0, 1.122, 1.354), "offset-left": (-1.0, 1.122, 1.354)}



def participant_study(landscapes: dict[str, Landscape], evaluators: dict[str, Evaluator],
                      score: str = "paper_postural",
                      default: str = DEFAULT_WORKER) -> pd.DataFrame:
    """Score every worker at the default's optimum, its own optimum and the shortest-distance
    locations.

    Args:
        landscapes: worker percentile name -> that worker's landscape (one boundary for all,
            as the paper deploys one); must include ``default``.
        evaluators: worker percentile name -> the evaluator its landscape was swept with.
        score: the objective the optima minimise.
        default: the worker whose optimum is deployed to everyone.

    Returns:
        One row per worker and location: ``worker, stature_m, location, start, x, y, z,
        feasible, reason`` and the scores of :data:`OBJECTIVES` (<NA> where infeasible).
    """
    deployed = optimised(landscapes[default], score)
    rows = []
    for name, landscape in landscapes.items():
        body = evaluators[name].body
        boundary = landscape.grid.boundary
        places = [("default-optimised", "", deployed),
                  ("own-optimised", "", optimised(landscape, score))]
        places += [("shortest-distance", start, shortest_distance(np.array(point), boundary))
                   for start, point in VR_STARTS.items()]
        table = evaluate(np.array([p for _, _, p in places]), evaluators[name])
        for (location, start, point), (_, row) in zip(places, table.iterrows(), strict=True):
            rows.append({"worker": name, "stature_m": body.stature_m, "location": location,
                         "start": start, "x": point[0], "y": point[1], "z": point[2],
                         "feasible": int(row["feasible"]), "reason": row["reason"],
                         **{s: row[s] for s in OBJECTIVES}})
    frame = pd.DataFrame(rows)
    for s in OBJECTIVES:
        frame[s] = frame[s].astype("Int8")
    return frame
