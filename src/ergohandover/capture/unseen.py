"""What a capture cannot see, as uncertainty in the scores: the interval every score can take
over the unseen columns' plausible ranges, or its distribution under a stated prior.

The plausible range of each angle column is the worker twin's joint range
(:meth:`~ergohandover.twin.anthropometry.BodySpec.joint_limits_deg`, AAOS and Kapandji ranges of
motion; trunk flexion from vertical: the lumbar and hip ranges added); a flag may be 0 or 1.

**Intervals** are exact, not sampled. Every item score of REBA, RULA and the paper's score is a
fixed function of a few columns, constant between band edges; so each column's range is cut at
the edges where any item changes (found by scanning it), and each piece is represented by one
value. The columns unseen in a row are grouped by the items they share; within a group every
combination of representatives is scored, which gives each item's lowest and highest value.
Tables A, B and C are non-decreasing in every item (``tests/test_capture.py`` checks it), and
the paper's score adds its items, so the tables of the lowest items give the lowest score and
those of the highest the highest.

**Probabilities** (the ``prior`` mode) take each unseen angle uniform over its plausible range and
each unseen flag 0 or 1 with equal chance, independently: a stated prior of ignorance within
the ranges of motion, not a model of where people hold their wrists.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from functools import lru_cache

import numpy as np

from ..ergonomics import Posture, ScoringSettings
from ..ergonomics.paper_score import items as paper_items
from ..ergonomics.paper_score import paper_from_items
from ..ergonomics.posture import COLUMN_BY_NAME, POSTURE_COLUMNS
from ..ergonomics.reba import items as reba_items
from ..ergonomics.reba import reba_from_items
from ..ergonomics.rula import items as rula_items
from ..ergonomics.rula import rula_from_items
from ..twin.anthropometry import BodySpec

SCORES = ("reba", "rula", "paper_postural")
"""The scores given as intervals or distributions."""
BASELINES = 8
"""Postures each column is scanned against: an upright one and random ones."""
SCAN_STEP_DEG = 0.25
"""How finely a column's range is scanned for band edges [deg] (no band is narrower: the
narrowest, an upright tolerance, is at least this wide or exactly 0, which is tried)."""
_JOINT_OF = {
    "trunk_side_bend": "lumbar_side_bend", "trunk_twist": "lumbar_twist",
    "neck_flexion": "neck_flexion", "neck_side_bend": "neck_side_bend",
    "neck_twist": "neck_twist", "knee_flexion": "knee_flexion",
    "upper_arm_flexion": "shoulder_flexion", "upper_arm_abduction": "shoulder_abduction",
    "upper_arm_rotation": "shoulder_rotation", "shoulder_raise": "clavicle_elevation",
    "elbow_flexion": "elbow_flexion", "wrist_flexion": "wrist_flexion",
    "wrist_deviation": "wrist_deviation", "wrist_twist": "forearm_pronation",
}


@lru_cache(maxsize=1)
def plausible_ranges() -> dict[str, tuple[float, float]]:
    """Each Posture column that can be unseen -> its (lowest, highest) plausible value."""
    limits = BodySpec().joint_limits_deg()
    out = {}
    for name in POSTURE_COLUMNS:
        column = COLUMN_BY_NAME[name]
        if column.kind == "flag":
            out[name] = (0.0, 1.0)
        elif column.kind == "angle":
            part = name.removeprefix("left_").removeprefix("right_")
            if name == "trunk_flexion":
                lumbar, hip = limits["lumbar_flexion"], limits["hip_flexion"]
                out[name] = (lumbar[0] + hip[0], min(lumbar[1] + hip[1], 180.0))
            else:
                side = name[: len(name) - len(part)]
                joint = _JOINT_OF[part]
                out[name] = limits.get(f"{side}{joint}", limits.get(joint))
    return out


def _items(posture: Posture, settings: ScoringSettings) -> dict[str, np.ndarray]:
    return {**reba_items(posture, settings), **rula_items(posture, settings),
            **paper_items(posture)}


def _totals(items: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    return {"reba": reba_from_items(items)["reba"],
            "rula": rula_from_items(items)["rula"],
            "paper_postural": paper_from_items(
                {k: v for k, v in items.items() if k.startswith("paper_")})["paper_postural"]}


def _neutral(n: int) -> dict[str, np.ndarray]:
    """N upright postures (elbows at 80°), every other column at its default."""
    return {name: np.full(n, 80.0 if name.endswith("elbow_flexion") else 0.0)
            for name in POSTURE_COLUMNS if COLUMN_BY_NAME[name].kind == "angle"}


@lru_cache(maxsize=16)
def _pieces(settings: ScoringSettings) -> tuple[dict[str, np.ndarray], dict[str, frozenset]]:
    """Per column: one value of every piece of its range between item changes, and the items
    it changes."""
    values, changes = {}, {}
    ranges = plausible_ranges()
    baselines = {name: np.r_[v, Posture.random(BASELINES - 1, np.random.default_rng(0))[name]]
                 for name, v in _neutral(1).items()}
    baselines |= {name: np.r_[COLUMN_BY_NAME[name].default or 0.0,
                              Posture.random(BASELINES - 1, np.random.default_rng(0))[name]]
                  for name in POSTURE_COLUMNS if name not in baselines}
    for name in POSTURE_COLUMNS:
        kind = COLUMN_BY_NAME[name].kind
        if kind == "angle":
            lo, hi = ranges[name]
            grid = np.unique(np.r_[np.arange(lo, hi, SCAN_STEP_DEG), hi,
                                   0.0 if lo <= 0.0 <= hi else lo])
        else:  # flags, levels and loads: enough values to cross every band
            grid = {"flag": np.array([0.0, 1.0]), "level": np.arange(4.0),
                    "load": np.array([0.0, 2.0, 5.0, 10.0, 10.5, 25.0])}[kind]
            lo, hi = grid[0], grid[-1]
        # Against several other postures, so that no item hides behind another column's value
        # (an arm's support does not lower an upper-arm score already at its minimum of 1).
        columns = {other: np.repeat(v, len(grid)) for other, v in baselines.items()}
        columns[name] = np.tile(grid, BASELINES)
        items = _items(Posture(columns), settings)
        table = np.stack(list(items.values()), axis=1).reshape(BASELINES, len(grid), -1)
        new = np.r_[True, (np.diff(table, axis=1) != 0).any(axis=(0, 2))]
        keep = new | (grid == 0.0) | (grid == lo) | (grid == hi)
        values[name] = grid[keep]
        changes[name] = frozenset(item for i, item in enumerate(items)
                                  if (np.ptp(table[:, :, i], axis=1) > 0).any())
    return values, changes


def items_read(settings: ScoringSettings | None = None) -> dict[str, frozenset[str]]:
    """Each item score of REBA, RULA and the paper's score -> the Posture columns it reads."""
    _, changes = _pieces(settings or ScoringSettings())
    out: dict[str, set[str]] = {}
    for column, items in changes.items():
        for item in items:
            out.setdefault(item, set()).add(column)
    return {item: frozenset(columns) for item, columns in out.items()}


def _groups(unseen: list[str], changes: dict[str, frozenset]) -> list[list[str]]:
    """The unseen columns joined where they change a common item."""
    groups: list[tuple[set[str], set[str]]] = []
    for name in unseen:
        cols, items = {name}, set(changes[name])
        for group in [g for g in groups if g[1] & items]:
            groups.remove(group)
            cols |= group[0]
            items |= group[1]
        groups.append((cols, items))
    return [sorted(cols) for cols, _ in groups]


def score_intervals(columns: Mapping[str, np.ndarray], unseen: np.ndarray,
                    settings: ScoringSettings | None = None) -> dict[str, np.ndarray]:
    """The lowest and highest value of each of :data:`SCORES` over the unseen columns.

    Args:
        columns: every Posture column, (N,) each (unseen values are ignored).
        unseen: (N, len(POSTURE_COLUMNS)) bool, True where a column was not measured.
        settings: the scoring settings.

    Returns:
        ``{score}_lo`` and ``{score}_hi`` -> (N,) int8 for every score of :data:`SCORES`.
    """
    settings = settings or ScoringSettings()
    values, changes = _pieces(settings)
    filled = {name: np.where(unseen[:, i], 0.0, columns[name])
              for i, name in enumerate(POSTURE_COLUMNS)}
    base = _items(Posture(filled), settings)
    low = {k: v.copy() for k, v in base.items()}
    high = {k: v.copy() for k, v in base.items()}
    # Rows by the set of columns they miss (a bit each: 1-D keys sort far faster than rows).
    codes = unseen.astype(np.uint64) @ (np.uint64(1) << np.arange(unseen.shape[1],
                                                                  dtype=np.uint64))
    keys, first, which = np.unique(codes, return_index=True, return_inverse=True)
    # Each group of columns that change common items is bounded once, over every row in
    # whose unseen set it is a group: its items do not depend on the row's other unseen ones.
    rows_of: dict[tuple[str, ...], list[np.ndarray]] = {}
    for p in range(len(keys)):
        missing = [POSTURE_COLUMNS[i] for i in np.flatnonzero(unseen[first[p]])]
        for group in _groups(missing, changes):
            rows_of.setdefault(tuple(group), []).append(np.flatnonzero(which == p))
    for group, rows in rows_of.items():
        _bound(list(group), np.concatenate(rows), filled, values, changes, settings, low, high)
    out = {}
    for name, lo, hi in zip(SCORES, _totals(low).values(), _totals(high).values(), strict=True):
        out[f"{name}_lo"], out[f"{name}_hi"] = lo, hi
    return out


def _bound(group, rows, filled, values, changes, settings, low, high) -> None:
    """Lower ``low`` and raise ``high`` at ``rows`` to the items ``group``'s columns reach."""
    combos = np.array(list(itertools.product(*(values[c] for c in group))))  # (K, G)
    items = set().union(*(changes[c] for c in group))
    # Items that depend on no column outside the group are the same in every row: one will do.
    others = [c for c in changes if c not in group and not changes[c].isdisjoint(items)]
    at = rows if others else rows[:1]
    k = len(combos)
    # Only the columns these items read take the rows' values; the rest do not matter here.
    blank = np.zeros(len(at) * k)
    expanded = {name: np.repeat(v[at], k) if name in others else blank
                for name, v in filled.items()}
    for j, name in enumerate(group):
        expanded[name] = np.tile(combos[:, j], len(at))
    scored = _items(Posture(expanded), settings)
    for item in items:
        table = scored[item].reshape(len(at), k)
        low[item][rows] = table.min(axis=1)  # one value when alone: broadcast to every row
        high[item][rows] = table.max(axis=1)


def draw_block(draws: int) -> int:
    """Rows whose values :func:`score_distributions` draws at once (about 200,000 values): a
    caller that scores a file part by part hands it whole blocks, so that the generator gives
    every row the values it gives when the file is scored whole."""
    return max(1, 200_000 // draws)


def score_distributions(columns: Mapping[str, np.ndarray], unseen: np.ndarray,
                        rng: np.random.Generator, draws: int = 400,
                        settings: ScoringSettings | None = None) -> dict[str, np.ndarray]:
    """Each score's distribution over the unseen columns under the uniform prior.

    Args:
        columns, unseen, settings: as :func:`score_intervals`.
        rng: the generator the unseen values are drawn from (the caller owns the seed).
        draws: values drawn per row.

    Returns:
        ``{score}_probabilities`` -> (N, top + 1) float: the share of draws at each score value
        (column v: the score v), for every score of :data:`SCORES`.
    """
    settings = settings or ScoringSettings()
    ranges = plausible_ranges()
    n = unseen.shape[0]
    chunk = draw_block(draws)
    out = {f"{s}_probabilities": np.zeros((n, 25)) for s in SCORES}
    for start in range(0, n, chunk):
        index = np.arange(start, min(start + chunk, n))
        expanded = {}
        for i, name in enumerate(POSTURE_COLUMNS):
            value = np.repeat(columns[name][index], draws)
            hidden = np.repeat(unseen[index, i], draws)
            if hidden.any():
                lo, hi = ranges[name]
                drawn = (rng.integers(0, 2, hidden.sum()).astype(float)
                         if COLUMN_BY_NAME[name].kind == "flag"
                         else rng.uniform(lo, hi, hidden.sum()))
                value = value.copy()
                value[hidden] = drawn
            expanded[name] = np.nan_to_num(value)
        totals = _totals(_items(Posture(expanded), settings))
        for score, total in totals.items():
            counts = np.zeros((len(index), 25))
            np.add.at(counts, (np.repeat(np.arange(len(index)), draws), total.astype(int)), 1)
            out[f"{score}_probabilities"][index] = counts / draws
    return out
