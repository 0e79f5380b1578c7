"""The body model fitted to the ANSUR II survey: per sex, a multivariate normal distribution of
the measurements that size the twin.

The table of figures (``ansur2_body_model.json``: per sex the number of people, each
measurement's mean and SD, and their correlations) is computed from the survey's public data
files by ``experiments/tools/fit_body_model.py``; the data files are not part of the package.

Two things are done with it:

* **fill in** a person's missing measurements: the conditional mean of the normal distribution
  given the ones that are known (exact observations of linear functions of the measurements, so
  a derived quantity such as elbow height can be given in place of the two it is made of);
* **draw** people: samples of the whole vector, so every measurement agrees with the others as
  it does in the survey.

Measurements are named in the twin's words, in metres (mass in kilograms); each maps to one
survey column (``MEASUREMENTS``). Derived quantities are fixed linear combinations
(``DERIVED``).
"""

from __future__ import annotations

import functools
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

TABLE_PATH = Path(__file__).with_name("ansur2_body_model.json")

MEASUREMENTS = {
    "stature_m": "stature",
    "mass_kg": "weightkg",
    "ankle_height_m": "lateralmalleolusheight",  # the ankle joint's level
    "knee_height_m": "lateralfemoralepicondyleheight",  # the knee's flexion axis
    "hip_height_m": "trochanterionheight",  # greater trochanter, taken as the hip joint
    "crotch_height_m": "crotchheight",
    "iliac_crest_height_m": "iliocristaleheight",
    "cervicale_height_m": "cervicaleheight",  # C7 spinous process
    "ear_to_vertex_m": "tragiontopofhead",
    "shoulder_height_m": "acromialheight",  # acromion, taken as the shoulder joint
    "upper_arm_length_m": "acromionradialelength",  # acromion to the elbow joint (radiale)
    "shoulder_elbow_length_m": "shoulderelbowlength",  # acromion to the bent elbow's underside
    "wrist_height_m": "wristheight",  # stylion, arm hanging
    "hand_length_m": "handlength",
    "shoulder_breadth_m": "biacromialbreadth",
    "hip_breadth_m": "hipbreadth",
    "foot_length_m": "footlength",
    "foot_breadth_m": "footbreadthhorizontal",
}
"""The model's measurements: the twin's name -> the survey's column."""

SURVEY_SCALE = {column: 10.0 if column == "weightkg" else 1000.0
                for column in MEASUREMENTS.values()}
"""Divide a survey value by this to get metres (kilograms for weight, given in 0.1 kg)."""

DERIVED = {
    # Standing elbow height as ergonomics uses it (the underside of the elbow, forearm
    # horizontal): the reference of standing working heights.
    "elbow_height_m": {"shoulder_height_m": 1.0, "shoulder_elbow_length_m": -1.0},
    "elbow_joint_height_m": {"shoulder_height_m": 1.0, "upper_arm_length_m": -1.0},
    "forearm_length_m": {"shoulder_height_m": 1.0, "upper_arm_length_m": -1.0,
                         "wrist_height_m": -1.0},
    "arm_length_m": {"shoulder_height_m": 1.0, "wrist_height_m": -1.0},  # acromion to wrist
}
"""Quantities that are linear combinations of the measurements, accepted as inputs too."""

SEXES = ("male", "female")


@dataclass(frozen=True)
class SexModel:
    """One sex's fitted distribution: ``mean`` and ``sd`` per name of ``names``, and their
    Pearson ``correlation``; ``n`` people."""

    names: tuple[str, ...]
    n: int
    mean: np.ndarray
    sd: np.ndarray
    correlation: np.ndarray

    @functools.cached_property
    def covariance(self) -> np.ndarray:
        return self.correlation * np.outer(self.sd, self.sd)

    def row(self, name: str) -> np.ndarray:
        """The weights that make ``name`` (a measurement or a derived quantity) from the
        measurement vector."""
        weights = np.zeros(len(self.names))
        for part, weight in DERIVED.get(name, {name: 1.0}).items():
            weights[self.names.index(part)] = weight
        return weights

    def value_range(self, name: str, spread: float) -> tuple[float, float]:
        """The mean of ``name`` ± ``spread`` SDs."""
        row = self.row(name)
        mean, sd = row @ self.mean, float(np.sqrt(row @ self.covariance @ row))
        return mean - spread * sd, mean + spread * sd

    def conditional(self, given: dict[str, float]) -> np.ndarray:
        """The whole measurement vector: the given values and, for the rest, their mean given
        those (the normal distribution conditioned on exact observations)."""
        if not given:
            return self.mean.copy()
        rows = np.array([self.row(name) for name in given])
        observed = np.array(list(given.values()), dtype=float)
        gain = self.covariance @ rows.T @ np.linalg.pinv(rows @ self.covariance @ rows.T)
        return self.mean + gain @ (observed - rows @ self.mean)

    def sample(self, n: int, rng: np.random.Generator) -> np.ndarray:
        """``n`` draws of the measurement vector, one per row."""
        return rng.multivariate_normal(self.mean, self.covariance, size=n, method="cholesky")


@functools.cache
def body_model() -> dict[str, SexModel]:
    """The fitted model of each sex, read once from the shipped table."""
    document = json.loads(TABLE_PATH.read_text())
    names = tuple(document["measurements"])
    return {sex: SexModel(names, fit["n"], np.array(fit["mean"]), np.array(fit["sd"]),
                          np.array(fit["correlation"]))
            for sex, fit in document["sexes"].items()}


def survey_rounding(values: np.ndarray, names: tuple[str, ...]) -> np.ndarray:
    """Measurements rounded to the survey's resolution: 1 mm, 0.1 kg for mass."""
    scale = np.where(np.array(names) == "mass_kg", 10.0, 1000.0)
    return np.round(values * scale) / scale


def known_names() -> tuple[str, ...]:
    """Every name a measurement can be given under."""
    return (*MEASUREMENTS, *DERIVED)
