"""Banded scores and score-table look-ups over arrays: the one place band-edge inclusivity is
decided."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import ConfigError

SCORE_DTYPE = np.int8


def banded(values: np.ndarray, edges: Sequence[float], scores: Sequence[int],
           severe_on_edge: bool) -> np.ndarray:
    """Score each value by the band it falls in.

    ``scores[i]`` applies between ``edges[i-1]`` and ``edges[i]`` (``scores[0]`` below the
    first edge, ``scores[-1]`` above the last). A value exactly on an edge takes the less
    severe of the two neighbouring bands, or the more severe one when ``severe_on_edge``.

    Args:
        values: (N,) angles or magnitudes.
        edges: ascending band edges, ``len(scores) - 1`` of them.
        scores: the score of each band.
        severe_on_edge: which neighbour an on-edge value joins.

    Returns:
        (N,) int8 scores.
    """
    if len(edges) != len(scores) - 1 or list(edges) != sorted(edges):
        raise ConfigError(f"need ascending edges, one fewer than scores: {edges}, {scores}")
    edges, scores, on_edge = _without_empty_bands(edges, scores, severe_on_edge)
    out = np.full(values.shape, scores[0], dtype=SCORE_DTYPE)
    for edge, below, above in zip(edges, scores[:-1], scores[1:], strict=True):
        if below == above:
            continue
        # The edge value joins the band above when that band is the one the rule picks.
        edge_joins_above = (above > below) == severe_on_edge
        crossed = values >= edge if edge_joins_above else values > edge
        step = crossed.view(SCORE_DTYPE)  # 0/1 without a copy
        out += step if above - below == 1 else step * SCORE_DTYPE(above - below)
    for edge, score in on_edge.items():
        out[values == edge] = score
    return out


def _without_empty_bands(edges, scores, severe_on_edge):
    """Merge equal edges (a zero-width band, e.g. a 0° upright tolerance) into one edge.

    Returns the merged edges and scores, and for each merged edge the score of a value exactly
    on it: the least (or, with ``severe_on_edge``, the most) severe of every band touching it.
    """
    pick = max if severe_on_edge else min
    kept_edges, kept_scores, on_edge = [edges[0]], [scores[0], scores[1]], {}
    for edge, score in zip(edges[1:], scores[2:], strict=True):
        if edge == kept_edges[-1]:
            on_edge[edge] = pick(on_edge.get(edge, kept_scores[-2]), kept_scores[-1], score)
            kept_scores[-1] = score
        else:
            kept_edges.append(edge)
            kept_scores.append(score)
    return kept_edges, kept_scores, on_edge


def exceeds(values: np.ndarray, threshold: float, severe_on_edge: bool) -> np.ndarray:
    """1 where ``|values|`` is beyond ``threshold`` (on the threshold: per ``severe_on_edge``).

    Returns:
        (N,) int8 array of 0/1.
    """
    return banded(np.abs(values), (threshold,), (0, 1), severe_on_edge)


def elevated(values: np.ndarray, threshold: float, severe_on_edge: bool) -> np.ndarray:
    """1 where signed ``values`` rise beyond ``threshold`` (a shoulder raised above its neutral):
    a value below the neutral (a depressed shoulder) never counts, whatever its size.

    Returns:
        (N,) int8 array of 0/1.
    """
    return banded(values, (threshold,), (0, 1), severe_on_edge)


def lookup(table: np.ndarray, *indices: np.ndarray) -> np.ndarray:
    """``table[i0 - 1, i1 - 1, ...]`` for 1-based score arrays, via one flat gather."""
    flat = np.zeros(indices[0].shape, dtype=np.intp)
    for size, index in zip(table.shape, indices, strict=True):
        flat *= size
        flat += index
        flat -= 1
    return table.ravel().take(flat)
