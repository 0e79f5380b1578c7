"""The population prior: where a worker's optimum is expected before any trial.

The population study sweeps a landscape per sampled worker and records each one's own optimum.
Across workers the optimum moves with the body (higher for taller workers, further forward for
men of the same stature), so a linear model of the optimum on stature and sex predicts where a
new worker's optimum lies, with the model's residual spread as the uncertainty. That is a
prior no learner of the paper uses: a searcher can propose it first and search around it.

The shipped model (``population_prior.json``) is fitted to the committed population study's
workers by ``experiments/tools/fit_population_prior.py``; the personalisation study fits it
again without the worker it personalises for (leave-one-out), so no worker's own optimum
informs its prior.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import ConfigError

AXES = ("x", "y", "z")
FEATURES = ("stature_m", "male")
"""The prior's inputs: stature [m] and 1 for a man, 0 for a woman."""
SHIPPED = "population_prior.json"


@dataclass(frozen=True)
class Prior:
    """Where a worker's optimum is expected.

    Attributes:
        location: (3,) the expected optimum (x, y, z), worker frame [m].
        sd: (3,) the spread of workers' optima about that expectation, per axis [m].
        per_metre: (3,) how far the expected optimum moves per metre of stature, per axis
            [m/m] (None: not known), for a searcher that compares the worker with bodies of
            other statures.
    """

    location: tuple[float, float, float]
    sd: tuple[float, float, float]
    per_metre: tuple[float, float, float] | None = None

    def __post_init__(self):
        if not all(math.isfinite(v) for v in self.location):
            raise ConfigError(f"prior location = {self.location} is not finite")
        if not all(math.isfinite(v) and v > 0 for v in self.sd):
            raise ConfigError(f"prior sd = {self.sd} is outside the valid range (> 0 m)")


def design(stature_m, male) -> np.ndarray:
    """(n, 3) rows of 1, stature [m] and the male indicator."""
    stature = np.atleast_1d(np.asarray(stature_m, dtype=float))
    male = np.broadcast_to(np.atleast_1d(np.asarray(male, dtype=float)), stature.shape)
    return np.column_stack([np.ones_like(stature), stature, male])


@dataclass(frozen=True)
class PopulationPrior:
    """A linear model of the optimum on stature and sex, fitted by least squares per axis.

    Attributes:
        coefficients: (3 axes, 3) intercept [m], per metre of stature, man minus woman [m].
        residual_sd: (3,) residual SD per axis [m] (floored at ``floor_m``).
        n_workers: how many workers it was fitted on.
        objective: the objective whose optimum it predicts.
        floor_m: the least SD it reports (one grid step: a zero spread on an axis where every
            optimum sits on the midline would make a searcher refuse to move along it).
    """

    coefficients: tuple[tuple[float, ...], ...]
    residual_sd: tuple[float, float, float]
    n_workers: int
    objective: str = "paper_postural"
    floor_m: float = 0.01

    @classmethod
    def fit(cls, workers: pd.DataFrame, objective: str = "paper_postural",
            floor_m: float = 0.01) -> PopulationPrior:
        """Fit to a table with ``stature_m``, ``sex`` and ``{objective}_x/_y/_z`` columns (the
        population study's ``workers.csv``; its reference worker, if marked, is left out)."""
        table = workers
        if "reference" in table.columns:
            table = table[table["reference"].astype(int) == 0]
        needed = ["stature_m", "sex", *(f"{objective}_{a}" for a in AXES)]
        missing = [c for c in needed if c not in table.columns]
        if missing:
            raise ConfigError(f"workers table: missing column(s) {', '.join(missing)}")
        if len(table) < 4:
            raise ConfigError(f"workers table: {len(table)} workers, at least 4 are needed to "
                              "fit the prior")
        X = design(table["stature_m"], (table["sex"] == "male").to_numpy())
        Y = table[[f"{objective}_{a}" for a in AXES]].to_numpy(dtype=float)
        beta, *_ = np.linalg.lstsq(X, Y, rcond=None)  # (3 features, 3 axes)
        residual = Y - X @ beta
        dof = max(len(table) - X.shape[1], 1)
        sd = np.maximum(np.sqrt((residual ** 2).sum(axis=0) / dof), floor_m)
        return cls(tuple(tuple(float(v) for v in row) for row in beta.T),
                   tuple(float(v) for v in sd), len(table), objective, floor_m)

    def predict(self, stature_m: float, sex: str) -> Prior:
        """The prior of a worker of ``stature_m`` and ``sex`` (``female`` or ``male``)."""
        if sex not in ("female", "male"):
            raise ConfigError(f"sex = {sex!r} is not allowed (use female or male)")
        if not (math.isfinite(stature_m) and 1.0 <= stature_m <= 2.5):
            raise ConfigError(f"stature = {stature_m!r} m is outside the valid range 1.0-2.5 m")
        row = design(stature_m, sex == "male")[0]
        location = np.asarray(self.coefficients) @ row
        slope = tuple(float(axis[FEATURES.index("stature_m") + 1]) for axis in self.coefficients)
        return Prior(tuple(float(v) for v in location), self.residual_sd, slope)

    def to_dict(self) -> dict:
        return {"objective": self.objective, "features": ["intercept", *FEATURES],
                "axes": list(AXES), "coefficients": [list(r) for r in self.coefficients],
                "residual_sd_m": list(self.residual_sd), "n_workers": self.n_workers,
                "floor_m": self.floor_m}

    @classmethod
    def from_dict(cls, data: dict) -> PopulationPrior:
        return cls(tuple(tuple(float(v) for v in r) for r in data["coefficients"]),
                   tuple(float(v) for v in data["residual_sd_m"]), int(data["n_workers"]),
                   data["objective"], float(data["floor_m"]))


def shipped_prior() -> PopulationPrior:
    """The model fitted to the committed population study (package data)."""
    text = resources.files(__package__).joinpath(SHIPPED).read_text(encoding="utf-8")
    return PopulationPrior.from_dict(json.loads(text)["model"])


def load_prior(path: Path) -> PopulationPrior:
    """A prior file written by ``experiments/tools/fit_population_prior.py``."""
    return PopulationPrior.from_dict(json.loads(Path(path).read_text(encoding="utf-8"))["model"])
