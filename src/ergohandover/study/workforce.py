"""A sampled workforce: people drawn from the body model fitted to the ANSUR II survey.

Each worker is a whole body: stature, mass and every landmark the survey measures, drawn
jointly per sex from the fitted multivariate normal (:meth:`BodySpec.sample`), so proportions
(elbow height or arm length for a given stature) vary between people as they do in the survey.
A draw outside the body model's valid range (stature 1.40-2.10 m, mass 35-160 kg) or whose
landmarks are out of anatomical order is drawn again. The sex mix is exact:
``round(size * female_share)`` women, in random order.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import ConfigError
from ..twin.anthropometry import BodySpec
from ..twin.body_model import MEASUREMENTS


@dataclass(frozen=True)
class Workforce:
    """How a workforce is drawn.

    Attributes:
        size: workers, at least 1.
        seed: the draw's seed.
        female_share: share of women, 0-1.
    """

    size: int = 100
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


LANDMARKS = ("elbow_height_m", "elbow_joint_height_m", "shoulder_height_m", "arm_length_m",
             "hip_height_m", "knee_height_m")
"""The landmarks written beside each worker, with ``elbow_ratio`` and ``arm_ratio`` (elbow
height and arm length over stature): the proportions the penalty is analysed against."""


def sample_workforce(workforce: Workforce) -> pd.DataFrame:
    """The workers of ``workforce``: ``worker`` (w001, ...), ``sex``, ``stature_m``,
    ``mass_kg`` and every measurement of the body model, in draw order; the same seed gives
    the same workers."""
    rng = np.random.default_rng(workforce.seed)
    women = round(workforce.size * workforce.female_share)
    sexes = rng.permutation(np.array(["female"] * women + ["male"] * (workforce.size - women)))
    people: list = [None] * workforce.size
    for sex in ("female", "male"):
        rows = np.flatnonzero(sexes == sex)
        for row, body in zip(rows, BodySpec.sample(rows.size, sex, rng), strict=True):
            people[row] = body
    width = len(str(workforce.size))
    table = pd.DataFrame([{"stature_m": b.stature_m, "mass_kg": b.mass_kg,
                           **dict(b.measurements)} for b in people])
    table.insert(0, "sex", sexes)
    table.insert(0, "worker", [f"w{i + 1:0{max(width, 3)}d}" for i in range(workforce.size)])
    return table


def landmark_columns(people: list[BodySpec]) -> pd.DataFrame:
    """Each body's :data:`LANDMARKS` and proportions [m, 1], rounded to 0.1 mm and 1e-5."""
    marks = pd.DataFrame([b.landmarks() for b in people], columns=list(LANDMARKS))
    stature = np.array([b.stature_m for b in people])
    return pd.concat([marks.round(4), pd.DataFrame({
        "elbow_ratio": (marks["elbow_height_m"] / stature).round(5),
        "arm_ratio": (marks["arm_length_m"] / stature).round(5)})], axis=1)


def bodies(workers: pd.DataFrame) -> list[BodySpec]:
    """A BodySpec per row of :func:`sample_workforce`: its own measurements where the row has
    them; the reference worker (``reference`` = 1) is sized by the body model from stature and
    mass."""
    names = [n for n in MEASUREMENTS if n not in ("stature_m", "mass_kg") and n in workers]
    out = []
    for row in workers.to_dict("records"):
        given = {} if row.get("reference", 0) == 1 else \
            {n: float(row[n]) for n in names if pd.notna(row[n])}
        out.append(BodySpec(float(row["stature_m"]), float(row["mass_kg"]), str(row["sex"]),
                            tuple(sorted(given.items()))))
    return out


def workforce_of(workforce: Workforce, reference_worker: str) -> pd.DataFrame:
    """The sampled workers (their measurements) and, last, the reference worker (a named
    percentile, sized by the body model from stature and mass), with their landmarks and
    proportions."""
    table = sample_workforce(workforce)
    table["reference"] = 0
    reference = BodySpec.from_percentile(reference_worker)
    # The reference's measurements are the body model's means given his stature and mass.
    marks = reference.landmarks()
    table.loc[len(table)] = {**{c: round(marks[c], 4) for c in table.columns if c in marks},
                             "worker": reference_worker, "sex": reference.sex,
                             "stature_m": reference.stature_m, "mass_kg": reference.mass_kg,
                             "reference": 1}
    derived = landmark_columns(bodies(table))
    return pd.concat([table, derived.drop(columns=[c for c in derived if c in table])], axis=1)
