"""A sampled workforce: workers drawn from the ANSUR II survey's statistics, each a BodySpec.

Stature and body mass are drawn jointly per sex: stature normal, mass log-normal (the same
mean and SD as the survey's, as the named percentiles are made in
:mod:`~ergohandover.twin.anthropometry`), the two tied by the survey's correlation between
stature and log-mass. A draw outside the body model's valid range (stature 1.40-2.10 m, mass
35-160 kg) is drawn again, so the workforce is the survey's distribution truncated to the
model's range. The sex mix is exact: ``round(size * female_share)`` women, in random order.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import ConfigError
from ..twin.anthropometry import ANSUR2, MASS_RANGE_KG, STATURE_RANGE_M, BodySpec

STATURE_MASS_CORRELATION = {"male": 0.471, "female": 0.539}
"""Pearson correlation of stature and log body weight in ANSUR II, per sex: computed from the
survey's public data files (4,082 men, 1,986 women; columns ``stature``, ``weightkg``); on
plain weight it is 0.469 and 0.533 (``docs/population.md``)."""


@dataclass(frozen=True)
class Workforce:
    """How a workforce is drawn.

    Attributes:
        size: workers, at least 1.
        seed: the draw's seed.
        female_share: share of women, 0-1.
    """

    size: int = 40
    seed: int = 2027
    female_share: float = 0.5

    def __post_init__(self):
        if isinstance(self.size, bool) or not isinstance(self.size, int) or self.size < 1:
            raise ConfigError(f"size = {self.size!r} is outside the valid range (a whole "
                              "number of workers, at least 1)")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ConfigError(f"seed = {self.seed!r} is outside the valid range (a whole "
                              "number, at least 0)")
        share = self.female_share
        if isinstance(share, bool) or not isinstance(share, (int, float)) \
                or not 0.0 <= share <= 1.0:
            raise ConfigError(f"female_share = {share!r} is outside the valid range 0-1")


def _draw(rng: np.random.Generator, sex: str, n: int) -> tuple[np.ndarray, np.ndarray]:
    """``n`` (stature [m], mass [kg]) of one sex, within the body model's range."""
    h_mean, h_sd, m_mean, m_sd = ANSUR2[sex]
    rho = STATURE_MASS_CORRELATION[sex]
    sigma = math.sqrt(math.log(1.0 + (m_sd / m_mean) ** 2))
    mu = math.log(m_mean) - 0.5 * sigma**2
    stature, mass = np.empty(n), np.empty(n)
    missing = np.arange(n)
    while missing.size:
        z = rng.standard_normal((missing.size, 2))
        h = h_mean + h_sd * z[:, 0]
        m = np.exp(mu + sigma * (rho * z[:, 0] + math.sqrt(1.0 - rho**2) * z[:, 1]))
        # The survey's resolution (1 mm, 0.1 kg), as the named percentiles.
        stature[missing], mass[missing] = np.round(h, 3), np.round(m, 1)
        valid = ((stature[missing] >= STATURE_RANGE_M[0]) & (stature[missing] <= STATURE_RANGE_M[1])
                 & (mass[missing] >= MASS_RANGE_KG[0]) & (mass[missing] <= MASS_RANGE_KG[1]))
        missing = missing[~valid]
    return stature, mass


def sample_workforce(workforce: Workforce) -> pd.DataFrame:
    """The workers of ``workforce``: ``worker`` (w001, ...), ``sex``, ``stature_m``,
    ``mass_kg``, in draw order; the same seed gives the same workers."""
    rng = np.random.default_rng(workforce.seed)
    women = round(workforce.size * workforce.female_share)
    sexes = rng.permutation(np.array(["female"] * women + ["male"] * (workforce.size - women)))
    stature, mass = np.empty(workforce.size), np.empty(workforce.size)
    for sex in ("female", "male"):
        rows = np.flatnonzero(sexes == sex)
        stature[rows], mass[rows] = _draw(rng, sex, rows.size)
    width = len(str(workforce.size))
    return pd.DataFrame({"worker": [f"w{i + 1:0{max(width, 3)}d}" for i in range(workforce.size)],
                         "sex": sexes, "stature_m": stature, "mass_kg": mass})


def bodies(workers: pd.DataFrame) -> list[BodySpec]:
    """A BodySpec per row of :func:`sample_workforce`."""
    return [BodySpec(float(r.stature_m), float(r.mass_kg), str(r.sex))
            for r in workers.itertuples()]

