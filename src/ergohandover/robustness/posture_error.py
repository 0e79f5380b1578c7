"""Scores under posture-measurement error: what a location's REBA, RULA and paper score look
like when its posture is measured the way a site would measure it (video or IMUs), to a few
degrees.

The error model: every angle column of the Posture CSV that the scorers read carries zero-mean
Gaussian error of SD ``sd_deg``, independently (``independent``), or with the left and right
sides of each paired angle (knees, each arm angle) sharing one draw (``bilateral``: one
instrument, one bias for both sides). Flags, load and the task factors are taken as known. A
perturbed angle is clipped to the Posture table's ±180°.

Everything is vectorised: ``draws`` perturbed copies of every posture are scored in chunks of
:data:`CHUNK_POSTURES` rows by :func:`~ergohandover.ergonomics.score_postures` (by
 its ``names``, only the scorers needed, where one score ranks locations).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..ergonomics import OBJECTIVES, Posture, ScoringSettings, score_postures
from ..ergonomics.posture import COLUMNS, SIDES
from ..errors import ConfigError

ANGLE_COLUMNS: tuple[str, ...] = tuple(c.name for c in COLUMNS if c.kind == "angle")
"""The measured angles: every angle column of the Posture CSV."""
STRUCTURES = ("independent", "bilateral")
"""How the errors of one posture's angles relate (see the module's text)."""
SCORES = ("paper_postural", "reba", "rula")
"""The scores whose distributions are reported."""
CHUNK_POSTURES = 262_144
"""Perturbed postures scored at once (about 0.2 GB of columns)."""
MAIN = {*OBJECTIVES, "reba_table_a", "reba_table_b", "reba_score_a", "reba_score_b",
        "reba_score_c", "reba_action_level"}


def _paired() -> dict[str, str]:
    """Each right-side angle column and the left-side column it shares a draw with."""
    left, right = SIDES
    return {name: name.replace(right, left, 1) for name in ANGLE_COLUMNS
            if name.startswith(f"{right}_")}


PAIRED = _paired()


@dataclass(frozen=True)
class ErrorModel:
    """Zero-mean Gaussian error on every measured angle.

    Attributes:
        sd_deg: the error's standard deviation [deg], >= 0.
        structure: one of :data:`STRUCTURES`.
    """

    sd_deg: float
    structure: str = "independent"

    def __post_init__(self):
        if not (np.isfinite(self.sd_deg) and self.sd_deg >= 0):
            raise ConfigError(f"angle_sd_deg = {self.sd_deg!r} is not allowed (a finite "
                              "standard deviation in degrees >= 0)")
        if self.structure not in STRUCTURES:
            raise ConfigError(f"structure = {self.structure!r} is not allowed (use "
                              f"{', '.join(STRUCTURES)})")

    def errors(self, n: int, rng: np.random.Generator) -> dict[str, np.ndarray]:
        """(n,) float32 error draws [deg] for every angle column (float32: drawing the normals
        is most of the Monte Carlo's time, and halves with them)."""
        own = [c for c in ANGLE_COLUMNS if not (self.structure == "bilateral" and c in PAIRED)]
        block = rng.standard_normal((len(own), n), dtype=np.float32)
        block *= np.float32(self.sd_deg)
        drawn = dict(zip(own, block, strict=True))
        for right, left in PAIRED.items():
            drawn.setdefault(right, drawn[left])
        return {c: drawn[c] for c in ANGLE_COLUMNS}


def _measured(values: np.ndarray, error: np.ndarray, repeats: int, tile: bool) -> np.ndarray:
    """Each value measured ``repeats`` times: value + error, clipped to the table's ±180°.
    Rows are value-major; with ``tile`` every value takes the same ``repeats`` errors."""
    out = np.repeat(values, repeats)
    out += np.tile(error, len(values)) if tile else error
    return np.clip(out, -180.0, 180.0, out=out)


def perturbed(posture: Posture, model: ErrorModel, draws: int,
              rng: np.random.Generator) -> Posture:
    """``draws`` measured copies of each posture, posture-major (rows ``i*draws .. (i+1)*draws``
    are posture ``i``'s)."""
    error = model.errors(posture.n * draws, rng)
    return Posture({name: _measured(values, error[name], draws, tile=False) if name in error
                    else np.repeat(values, draws) for name, values in posture.items()})


def measured_alike(posture: Posture, errors: dict[str, np.ndarray], draws: int) -> Posture:
    """Each posture measured ``draws`` times with the same ``draws`` errors (common random
    numbers: differences between postures are far more precise than each one's mean),
    posture-major."""
    return Posture({name: _measured(values, errors[name], draws, tile=True) if name in errors
                    else np.repeat(values, draws) for name, values in posture.items()})


def angles_of(columns) -> dict[str, float]:
    """The first row's angles (every angle column of the Posture table) of a Posture or of
    columns of arrays."""
    return {a: float(np.asarray(columns[a]).ravel()[0]) for a in ANGLE_COLUMNS}


def item_columns(scores: dict[str, np.ndarray]) -> list[str]:
    """The item scores of a score table: every column but the totals and table look-ups."""
    return [c for c in scores if c not in MAIN]


@dataclass
class MonteCarlo:
    """Per posture and score: the nominal score and the measured scores' summaries.

    Attributes:
        nominal: score -> (N,) the error-free score.
        mean, p_nominal_or_better, q05, q95, sd: score -> (N,).
        flips: item -> (N,) the share of draws in which the item differs from its nominal.
        draws: draws per posture.
        values: score -> (N, draws) the measured scores themselves, when asked to keep them.
    """

    nominal: dict[str, np.ndarray]
    mean: dict[str, np.ndarray]
    p_nominal_or_better: dict[str, np.ndarray]
    q05: dict[str, np.ndarray]
    q95: dict[str, np.ndarray]
    sd: dict[str, np.ndarray]
    flips: dict[str, np.ndarray]
    draws: int
    values: dict[str, np.ndarray] | None = None

    def table(self, names: Sequence[str]) -> pd.DataFrame:
        """One row per posture and score (``location`` from ``names``)."""
        rows = []
        for score in self.nominal:
            rows.append(pd.DataFrame({
                "location": list(names), "score": score, "nominal": self.nominal[score],
                "mean": self.mean[score], "mean_se": self.sd[score] / np.sqrt(self.draws),
                "p_nominal_or_better": self.p_nominal_or_better[score],
                "q05": self.q05[score], "q95": self.q95[score], "draws": self.draws}))
        return pd.concat(rows, ignore_index=True)


def _quantile(values: np.ndarray, q: float) -> np.ndarray:
    """The observed score that a share ``q`` of each row's draws is at or below."""
    return np.quantile(values, q, axis=1, method="inverted_cdf")


def monte_carlo(posture: Posture, model: ErrorModel, draws: int, rng: np.random.Generator,
                scores: Sequence[str] = SCORES, keep: bool = False,
                settings: ScoringSettings | None = None) -> MonteCarlo:
    """The distribution of each score of each posture under the error model.

    Args:
        posture: N error-free postures.
        model: the measurement error.
        draws: measured copies per posture (>= 1).
        rng: the generator of the errors (the caller owns the seed).
        scores: the scores to summarise.
        keep: keep every measured score (``values``; N x draws each) for comparisons.
        settings: the scoring settings (the evaluator's, where the postures are a twin's).
    """
    if draws < 1:
        raise ConfigError(f"draws = {draws!r} is not allowed (an integer >= 1)")
    nominal = score_postures(posture, settings)
    items = item_columns(nominal)
    per_chunk = max(1, CHUNK_POSTURES // draws)
    parts: dict[str, list[np.ndarray]] = {s: [] for s in scores}
    flips: dict[str, list[np.ndarray]] = {i: [] for i in items}
    for start in range(0, posture.n, per_chunk):
        index = np.arange(start, min(start + per_chunk, posture.n))
        measured = score_postures(perturbed(posture.take(index), model, draws, rng), settings)
        for s in scores:
            parts[s].append(measured[s].reshape(len(index), draws))
        for i in items:
            flips[i].append((measured[i].reshape(len(index), draws)
                             != nominal[i][index, None]).mean(axis=1))
    values = {s: np.concatenate(parts[s]) for s in scores}
    return MonteCarlo(
        nominal={s: nominal[s].astype(int) for s in scores},
        mean={s: values[s].mean(axis=1) for s in scores},
        p_nominal_or_better={s: (values[s] <= nominal[s][:, None]).mean(axis=1)
                             for s in scores},
        q05={s: _quantile(values[s], 0.05) for s in scores},
        q95={s: _quantile(values[s], 0.95) for s in scores},
        sd={s: values[s].std(axis=1) for s in scores},
        flips={i: np.concatenate(flips[i]) for i in items},
        draws=draws, values=values if keep else None)


def expected_scores(posture: Posture, model: ErrorModel, draws: int, seed: int,
                    score: str = "paper_postural",
                    settings: ScoringSettings | None = None) -> np.ndarray:
    """Each posture's expected ``score`` under the error model, every posture measured with
    the same ``draws`` errors (common random numbers: differences between postures are far
    more precise than each mean), for ranking many locations."""
    errors = model.errors(draws, np.random.default_rng(seed))
    per_chunk = max(1, CHUNK_POSTURES // draws)
    out = np.empty(posture.n)
    for start in range(0, posture.n, per_chunk):
        index = np.arange(start, min(start + per_chunk, posture.n))
        measured = score_postures(measured_alike(posture.take(index), errors, draws), settings,
                                  names=(score,))[score]
        out[index] = measured.reshape(len(index), draws).mean(axis=1)
    return out
