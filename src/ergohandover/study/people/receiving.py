"""Where people receive, predicted rather than given, and whether the twin's landscape ranks
people's postures as their measured scores do.

* **Where** (:func:`where_table`): without the person's hand, the twin predicts that they take
  the object at its one-handed optimum (the most symmetric minimiser of a score, for the twin
  sized to the median receiver); the baseline is the training split's mean receiving point. Per
  score and group: the 3-D error's RMSE and median [cm] and the skill against the mean point
  with its 95 % bootstrap interval over handovers.
* **Ranking** (:func:`ranking_table`): per score and group, Spearman's rank correlation between
  the twin's score where each person received (the twin sized to them, its hand at theirs) and
  the person's measured score (the middle of its interval), with its bootstrap interval.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...landscape.stats import optimum
from .beside_people import SCORES
from .skill import GROUPS, bootstrap_weights


def where_table(landscape, people: np.ndarray, groups: np.ndarray, rng: np.random.Generator,
                resamples: int = 2000) -> pd.DataFrame:
    """Per score and group: the twin's optimum as everyone's receiving point against the
    training split's mean point (``people``: (N, 3) receiving hands, worker frame [m])."""
    mean_point = people[groups == "train"].mean(axis=0)
    rows = []
    for score in SCORES:
        best = optimum(landscape, score)[1]
        for group in GROUPS:
            at = people[groups == group]
            twin = np.linalg.norm(at - best, axis=1)
            base = np.linalg.norm(at - mean_point, axis=1)
            weights = bootstrap_weights(len(at), rng, resamples)
            boot = 1.0 - (weights @ twin ** 2) / (weights @ base ** 2)
            rows.append({
                "score": score, "group": group, "n": len(at),
                "twin_x": round(float(best[0]), 3), "twin_y": round(float(best[1]), 3),
                "twin_z": round(float(best[2]), 3),
                "mean_x": round(float(mean_point[0]), 3),
                "mean_y": round(float(mean_point[1]), 3),
                "mean_z": round(float(mean_point[2]), 3),
                "twin_rmse_cm": round(100 * float(np.sqrt(np.mean(twin ** 2))), 1),
                "twin_median_cm": round(100 * float(np.median(twin)), 1),
                "mean_rmse_cm": round(100 * float(np.sqrt(np.mean(base ** 2))), 1),
                "mean_median_cm": round(100 * float(np.median(base)), 1),
                "skill": round(float(1.0 - np.sum(twin ** 2) / np.sum(base ** 2)), 3),
                "skill_low": round(float(np.percentile(boot, 2.5)), 3),
                "skill_high": round(float(np.percentile(boot, 97.5)), 3)})
    return pd.DataFrame(rows)


def ranking_table(twin_scores: pd.DataFrame, used: pd.DataFrame, groups: np.ndarray,
                  rng: np.random.Generator, resamples: int = 2000) -> pd.DataFrame:
    """Per score and group: Spearman's rank correlation between the twin's score where each
    person received and the middle of the person's measured score interval, with its 95 %
    percentile-bootstrap interval over handovers."""
    from scipy.stats import rankdata  # the study's, not the command line's

    def spearman(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        ra, rb = rankdata(a, axis=-1), rankdata(b, axis=-1)
        ra -= ra.mean(axis=-1, keepdims=True)
        rb -= rb.mean(axis=-1, keepdims=True)
        return (ra * rb).sum(axis=-1) / np.sqrt((ra ** 2).sum(axis=-1) * (rb ** 2).sum(axis=-1))

    rows = []
    for score in SCORES:
        twin = twin_scores[score].to_numpy(float)
        person = (used[f"{score}_lo"].to_numpy(float) + used[f"{score}_hi"].to_numpy(float)) / 2
        for group in GROUPS:
            where = np.flatnonzero(groups == group)
            draws = rng.integers(0, len(where), size=(resamples, len(where)))
            boot = spearman(twin[where][draws], person[where][draws])
            rows.append({"score": score, "group": group, "n": len(where),
                         "spearman": round(float(spearman(twin[where], person[where])), 3),
                         "low": round(float(np.nanpercentile(boot, 2.5)), 3),
                         "high": round(float(np.nanpercentile(boot, 97.5)), 3)})
    return pd.DataFrame(rows)
