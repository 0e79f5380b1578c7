"""The checked fine warm start (``SolverSettings(warm_start="fine")``): today's solves at the
nodes of a fine lattice, interpolated and scored, and today's solve wherever the cell's check
cannot vouch for the interpolation."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from test_stance import run_cli, sweep_each

from ergohandover.twin import evaluate as evaluation
from ergohandover.twin.evaluate import EvaluationError, Evaluator, evaluate
from ergohandover.twin.solver import SolverSettings
from ergohandover.twin.warm_start import OFFSETS, FineLattice

FINE = Evaluator(settings=SolverSettings(warm_start="fine"))
SCORES = ("flags", "paper_postural", "reba", "rula")


def corner_postures(value) -> np.ndarray:
    """(1, 8, 2) postures of a cell's corners: joint 0 = ``value(x, y, z)`` at the corner (0 or
    1 along each axis), joint 1 = twice that."""
    return np.array([[[value(*c), 2 * value(*c)] for c in OFFSETS]], dtype=float)


def test_the_check_trusts_a_cell_whose_corners_all_score_as_the_location():
    rough = corner_postures(lambda x, y, z: 0.3 * x * y * z + (x > 0.5))  # a jump inside
    assert not FineLattice.unsure(rough, np.full((1, 8), 7), np.array([7]), 1e-3)[0]


def test_the_check_re_solves_a_location_scoring_unlike_every_corner():
    smooth = corner_postures(lambda x, y, z: 0.01 * x + 0.02 * y)
    assert FineLattice.unsure(smooth, np.full((1, 8), 7), np.array([8]), 1.0)[0]


def test_a_mixed_cell_is_trusted_only_where_it_is_smooth():
    codes = np.array([[7, 7, 7, 7, 8, 8, 8, 8]])
    # A linear change of posture (however steep) and a curved one within the threshold are
    # smooth; a corner that jumped to another posture is not.
    linear = corner_postures(lambda x, y, z: 0.3 * x - 0.2 * y + 0.1 * z)
    curved = corner_postures(lambda x, y, z: 0.3 * x + 0.004 * x * y)
    jumped = corner_postures(lambda x, y, z: 0.3 * x + 0.05 * (x == y == z == 1))
    found = np.array([7])
    assert not FineLattice.unsure(linear, codes, found, 1e-9)[0]
    assert not FineLattice.unsure(curved, codes, found, 0.005)[0]
    assert FineLattice.unsure(curved, codes, found, 0.003)[0]
    assert FineLattice.unsure(jumped, codes, found, 0.01)[0]


@pytest.mark.slow
def test_the_fine_warm_start_depends_on_the_location_alone():
    # Nodes are solved on first use: a location's row must not depend on which other
    # locations came first, in this process or another.
    points = np.array([[0.0, 1.0, 0.42], [0.1, 1.2, 0.55], [-0.15, 0.8, 0.33]])
    together = evaluate(points, FINE, joints=True)
    assert together["feasible"].tolist() == [1, 1, 0]  # an infeasible one too
    for i in reversed(range(len(points))):
        evaluation._SOLVERS.pop(FINE)  # a new solver and lattice: no node solved yet
        evaluation._FINE.pop(FINE)
        alone = evaluate(points[i:i + 1], FINE, joints=True)
        pd.testing.assert_frame_equal(alone, together.iloc[i:i + 1].reset_index(drop=True))


@pytest.mark.slow
def test_the_fine_lattice_nodes_are_todays_solves():
    # At a node the interpolation puts (all but rounding of) its whole weight on that node, and
    # the node was solved exactly as today's warm start solves a location.
    nodes = np.array([[0.0, 1.002, 0.42], [0.102, 1.2, 0.552], [-0.15, 0.9, 0.33]])
    today, found = evaluate(nodes, joints=True), evaluate(nodes, FINE, joints=True)
    joints = [c for c in today.columns if c.startswith("q_")]
    assert np.abs(found[joints].to_numpy() - today[joints].to_numpy()).max() < 1e-9
    assert found["reba"].tolist() == today["reba"].tolist()


@pytest.mark.slow
def test_unsure_locations_get_todays_rows_and_the_rest_their_cells_interpolation():
    rng = np.random.default_rng(3)
    points = np.column_stack([rng.uniform(-0.2, 0.2, 400), rng.uniform(0.7, 1.3, 400),
                              rng.uniform(0.3, 0.6, 400)])
    today = evaluation.evaluate_batch(Evaluator(), points)
    found = evaluation.evaluate_batch(FINE, points)
    solver, lattice = evaluation.posture_solver(FINE), evaluation._FINE[FINE]
    q, code, weight = lattice.corners(points)
    start = FineLattice.interpolate(q, weight)
    interpolated = evaluation._rows(FINE, points, solver.iterate(points, start, 0))
    redo = FineLattice.unsure(q, code, evaluation._score_code(interpolated),
                              np.radians(FINE.settings.fine_check_deg))
    assert 0 < redo.sum() < len(points) / 2  # both kinds occur, most locations interpolated
    joints = [c for c in today if c.startswith("q_")]
    for column in (*SCORES, *joints, "hand_error_m"):
        np.testing.assert_array_equal(found[column][redo], today[column][redo])
        np.testing.assert_array_equal(found[column][~redo], interpolated[column][~redo])
    same = np.all([found[c] == today[c] for c in SCORES], axis=0)
    assert same.mean() >= 0.98  # the check's purpose: scores as today's almost everywhere


def test_the_fine_warm_start_needs_the_whole_body_solver():
    with pytest.raises(EvaluationError, match="warm_start = 'fine' is not allowed with solver"):
        Evaluator(solver="pybullet", settings=SolverSettings(warm_start="fine"))


@pytest.mark.slow
def test_sweep_takes_the_fine_warm_start_into_a_landscape_of_its_own(tmp_path, monkeypatch,
                                                                     capsys):
    found = sweep_each(tmp_path, monkeypatch, capsys, "-0.1,0.1,0.9,1.2,0.35,0.55", "0.02",
                       "--warm-start", ("lattice", "fine"))
    assert found["lattice"].path != found["fine"].path
    today, fine = found["lattice"].arrays, found["fine"].arrays
    same = np.all([today[c] == fine[c] for c in SCORES], axis=0)
    assert len(same) > 500 and same.mean() >= 0.98


def test_sweep_refuses_a_bad_warm_start_in_one_line():
    for flags, words in ((["--warm-start", "coarse"], ("coarse", "lattice", "fine")),
                         (["--warm-start", "fine", "--solver", "pybullet"], ("pybullet",))):
        bad = run_cli("sweep", "--boundary", "-0.1,0.1,0.9,1.2,0.35,0.55", "--step", "0.1",
                      *flags)
        assert bad.returncode == 2 and bad.stdout == ""
        assert len(bad.stderr.strip().splitlines()) == 1 and "--warm-start" in bad.stderr
        assert all(w in bad.stderr for w in words)
