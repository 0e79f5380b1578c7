"""The one-size choices of :func:`.one_size.one_size_cells` for many resamples of one
workforce, without copying the workforce's score matrix for each.

A resample (a bootstrap draw with repeats, or a split half) is a multiset of the workforce's
workers: their multiplicities ``m`` (W,). The mean score of a cell over the resample is
``m @ scores / m.sum()``; its 95th percentile (numpy's ``inverted_cdf``: the K-th smallest
observed score, K fixed by the resample's size) is the smallest score value ``v`` whose count
``m @ (scores <= v)`` reaches K. Scores are whole numbers of a few values, so the lowest 95th
percentile of the grid is found by counting up from the lowest value and stopping at the first
value some cell reaches: a few products of the multiplicities with a (W, C) mask instead of a
sort of the resample's (W', C) copy. The choice among them is ``one_size_cells``'s own rule
(:func:`.one_size.chosen_cells`), so the cells are those of ``one_size_cells`` on the copied
resample (tested); only the time differs (in the robustness part's 1,350 resamples of
100 workers over the 1 cm grid, minutes).
"""

from __future__ import annotations

import numpy as np

from .one_size import chosen_cells, common_cells

QUANTILE = 0.95


class OneSizeResampler:
    """One workforce's scores, ready for the one-size choices of many resamples.

    Args:
        scores: (W, C) every worker's score at every cell, NaN where infeasible (whole
            numbers elsewhere).
        points: (C, 3) the cells' locations, worker frame [m] (for the symmetric tie-break).
        reference_cell: the reference worker's optimum (the ``reference`` choice).
    """

    def __init__(self, scores: np.ndarray, points: np.ndarray, reference_cell: int):
        infeasible = np.isnan(scores)
        finite = scores[~infeasible]
        if finite.size and not np.array_equal(finite, np.round(finite)):
            raise ValueError("one-size resampling needs whole-number scores")
        self.points, self.reference_cell = points, int(reference_cell)
        self.infeasible = infeasible.astype(np.float32)  # (W, C): a worker who cannot there
        self.filled = np.where(infeasible, 0.0, scores)  # (W, C)
        self.values = np.unique(finite)  # ascending
        self._at_most: dict[float, np.ndarray] = {}

    def at_most(self, value: float) -> np.ndarray:
        """(W, C) float32: 1 where a worker scores ``value`` or less (or cannot take the box:
        such cells are left out by the caller). Kept: every resample counts up the same few
        lowest values."""
        if value not in self._at_most:
            self._at_most[value] = (self.filled <= value).astype(np.float32)
        return self._at_most[value]

    def cells(self, multiplicity: np.ndarray) -> dict[str, int]:
        """The cell of each one-size choice for the resample of ``multiplicity`` (W,) copies of
        each worker: what :func:`.one_size.one_size_cells` returns on that resample."""
        m = np.asarray(multiplicity, dtype=np.float64)
        m32 = m.astype(np.float32)  # counts of at most a few hundred: exact in float32
        n = round(float(m.sum()))
        common = common_cells((m32 > 0).astype(np.float32) @ self.infeasible == 0)
        # Sums of whole numbers are exact in float64: the same means as the copy's mean().
        mean = (m @ self.filled)[common] / n
        # numpy's inverted_cdf quantile is the sample's k-th smallest value (k from n alone).
        k = int(np.quantile(np.arange(n), QUANTILE, method="inverted_cdf")) + 1
        lowest_p95 = None
        for v in self.values:
            reached = (m32 @ self.at_most(v))[common] >= k
            if reached.any():
                lowest_p95 = reached
                break
        assert lowest_p95 is not None  # the highest value is reached by every common cell
        return chosen_cells(common, mean, lowest_p95, self.points, self.reference_cell)
