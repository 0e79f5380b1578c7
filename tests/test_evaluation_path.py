"""One evaluation path that keeps the evaluator: a pelvis-referenced twin gives the same trunk
angles and scores through every public entry point — the Python API, the command line, the
landscape door (the sweep) and the study's parts — and they differ from the vertical reference,
so no entry point can drop the setting unnoticed."""

from __future__ import annotations

import io
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from ergohandover.landscape.grid import Grid
from ergohandover.landscape.store import landscape_of
from ergohandover.study.participants.simulated import participant_study
from ergohandover.twin.evaluate import Evaluator, evaluate, evaluate_arrays
from ergohandover.twin.task import Boundary

LOW = Boundary((-0.05, 0.05), (0.55, 0.85), (0.35, 0.45))  # low boxes: the hips flex
PELVIS = Evaluator(trunk_reference="pelvis")
TRUNK = ("trunk_flexion", "reba", "paper_postural")


@pytest.mark.slow
def test_every_entry_point_scores_the_trunk_from_the_pelvis_when_asked(tmp_path):
    grid = Grid(LOW, 0.05)
    points = grid.points()
    api = evaluate(points, PELVIS)
    vertical = evaluate(points, Evaluator())
    feasible = api["feasible"].to_numpy() == 1
    assert feasible.sum() >= 5
    # The two references differ here (else the test could not tell them apart).
    assert (api["trunk_flexion"] < vertical["trunk_flexion"] - 5)[feasible].any()
    assert (api["reba"] != vertical["reba"])[feasible].any()
    # Python: the arrays path.
    arrays = evaluate_arrays(points, PELVIS, columns=TRUNK)
    np.testing.assert_allclose(arrays["trunk_flexion"], api["trunk_flexion"])
    # The landscape door (a sweep into the cache).
    landscape = landscape_of(PELVIS, grid, progress=False)
    np.testing.assert_allclose(landscape.arrays["trunk_flexion"][feasible],
                               api["trunk_flexion"][feasible], atol=1e-4)
    np.testing.assert_array_equal(landscape.arrays["reba"][feasible],
                                  api["reba"][feasible].to_numpy(dtype=int))
    # The command line.
    csv = tmp_path / "points.csv"
    pd.DataFrame(points, columns=["x", "y", "z"]).to_csv(csv, index=False)
    out = subprocess.run([sys.executable, "-m", "ergohandover.cli", "evaluate", "--points",
                          str(csv), "--trunk-reference", "pelvis", "--workers", "1",
                          "--output", "-"], capture_output=True, text=True, timeout=300,
                         check=True)
    cli = pd.read_csv(io.StringIO(out.stdout))
    np.testing.assert_allclose(cli["trunk_flexion"], api["trunk_flexion"], atol=1e-6)
    np.testing.assert_array_equal(cli["reba"].fillna(-1), api["reba"].fillna(-1).astype(float))
    # A study part: the simulated participants score with the evaluator they are given.
    table = participant_study({"p50-male": landscape}, {"p50-male": PELVIS})
    at = evaluate(table[["x", "y", "z"]].to_numpy(), PELVIS)
    np.testing.assert_array_equal(table["reba"].fillna(-1), at["reba"].fillna(-1))
