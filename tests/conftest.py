"""Shared fixtures: a landscape cache of the test session's own, and a neutral posture to
perturb one column at a time."""

from __future__ import annotations

import os

import numpy as np
import pytest

from ergohandover.ergonomics import REQUIRED_COLUMNS, Posture


def neutral_columns(**overrides: float) -> dict[str, np.ndarray]:
    """One upright posture (elbows at 80°) with ``overrides``, as length-1 columns."""
    values = {name: 0.0 for name in REQUIRED_COLUMNS}
    values.update(left_elbow_flexion=80.0, right_elbow_flexion=80.0)
    values.update(overrides)
    return {name: np.array([value], dtype=float) for name, value in values.items()}


@pytest.fixture
def neutral():
    """Factory: ``neutral(trunk_flexion=30)`` -> a one-row Posture."""
    return lambda **overrides: Posture(neutral_columns(**overrides))


@pytest.fixture(autouse=True, scope="session")
def landscape_cache(tmp_path_factory):
    """Every landscape the tests sweep (in-process or in a subprocess) goes to a cache of the
    session's own: nothing is read from, or left in, the user's cache."""
    path = tmp_path_factory.mktemp("landscape_cache")
    before = os.environ.get("ERGOHANDOVER_CACHE")
    os.environ["ERGOHANDOVER_CACHE"] = str(path)
    yield path
    if before is None:
        del os.environ["ERGOHANDOVER_CACHE"]
    else:
        os.environ["ERGOHANDOVER_CACHE"] = before


@pytest.fixture(scope="module")
def small_landscape():
    """A 2 cm landscape of the default worker around the study's optimum (a few hundred
    points: seconds to sweep)."""
    from ergohandover.landscape.grid import Grid
    from ergohandover.landscape.store import landscape_of
    from ergohandover.twin.evaluate import Evaluator
    from ergohandover.twin.task import Boundary

    evaluator = Evaluator()
    grid = Grid(Boundary((-0.06, 0.06), (0.94, 1.08), (0.36, 0.46), "test"), 0.02)
    return evaluator, landscape_of(evaluator, grid)
