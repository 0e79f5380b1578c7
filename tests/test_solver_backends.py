"""The compiled posture solver (numba) computes what the numpy reference computes, and every
location's result is bit-identical whatever else is solved with it."""

from __future__ import annotations

import multiprocessing

import numpy as np
import pytest

from ergohandover.twin.solver import STRATEGY_TIE, PostureSolver, StartLattice
from ergohandover.twin.task import Boundary

Q_TOLERANCE_RAD = 1e-6  # rounding differences amplified by the iteration, far below 0.01°


@pytest.fixture(scope="module")
def solvers():
    fast, reference = PostureSolver(), PostureSolver(backend="numpy")
    return fast, reference


@pytest.fixture(scope="module")
def points():
    return Boundary.paper_code().sample(300, np.random.default_rng(11))


@pytest.mark.slow
def test_the_lattices_agree(solvers):
    fast, reference = solvers
    model = fast.model
    q = fast.lattice.q.reshape(-1, model.nq)
    q_ref = reference.lattice.q.reshape(-1, model.nq)
    dq = np.abs(q - q_ref).max(axis=-1)
    _, nodes = StartLattice.nodes(fast.body.stature_m)
    # Both backends' postures priced by one cost function: where rounding made them part,
    # they must be equally good (a tie, as the strategy choice itself defines one).
    cost_gap = np.abs(fast.cost(nodes, q) - fast.cost(nodes, q_ref))
    flipped = (fast.lattice.strategy != reference.lattice.strategy).reshape(-1)
    # A node whose two best strategies cost within STRATEGY_TIE of each other sits on the
    # choice's threshold, so a rounding difference can pick the other one: only at a tie.
    assert flipped.mean() <= 0.005
    assert (cost_gap[flipped] < 10 * STRATEGY_TIE).all()
    # A node whose posture rides the hamstrings' line (the floor rows, below every boundary)
    # sits on a hinge: there a rounding difference between the two sums flips accept/reject
    # decisions of the 100 lattice iterations, so the backends part by up to a few degrees
    # (measured: 2.0 deg at one node, the postures' costs 0.02 % apart). Everywhere else they
    # agree to rounding (near the effort hinge a rare node flips too).
    hip0, slope, _ = fast.hamstring
    on_line = np.degrees(q[:, model.index("hip_flexion")] - hip0
                         - slope * q[:, model.index("knee_flexion")]) > -0.5
    assert (dq[~on_line] < Q_TOLERANCE_RAD).mean() >= 0.99
    assert np.median(dq) < 1e-10
    apart = on_line & (dq >= np.radians(1.0))
    assert apart.mean() <= 0.005
    assert (cost_gap[apart] < 10 * STRATEGY_TIE).all()


@pytest.mark.slow
def test_the_backends_agree_from_the_same_start(solvers, points):
    fast, reference = solvers
    start = fast.lattice.start(points)
    a = fast.iterate(points, start, fast.settings.iterations)
    b = reference.iterate_numpy(points, start, reference.settings.iterations)
    dq = np.abs(a.q - b.q).max(axis=1)
    # Rounding can flip an accept/reject decision of a location still far from converged;
    # all but a rare few agree to far below a thousandth of a degree.
    assert (dq < Q_TOLERANCE_RAD).mean() >= 0.99
    assert np.median(dq) < 1e-12
    close = dq < Q_TOLERANCE_RAD
    np.testing.assert_allclose(a.hand_error[close], b.hand_error[close], rtol=0, atol=1e-8)
    np.testing.assert_allclose(a.com[close], b.com[close], rtol=0, atol=1e-8)
    np.testing.assert_allclose(a.state.positions, b.state.positions, rtol=0, atol=1e-3)
    np.testing.assert_allclose(a.state.rotations, b.state.rotations, rtol=0, atol=1e-3)
    feasible_a, feasible_b = a.hand_error <= 0.01, b.hand_error <= 0.01
    assert (feasible_a == feasible_b).mean() >= 0.99


@pytest.mark.slow
def test_the_backends_agree_end_to_end(solvers, points):
    fast, reference = solvers
    a, b = fast.solve(points), reference.solve(points)  # each from its own lattice
    dq = np.abs(a.q - b.q).max(axis=1)
    assert (dq < Q_TOLERANCE_RAD).mean() >= 0.99
    assert ((a.hand_error <= 0.01) == (b.hand_error <= 0.01)).mean() >= 0.99


@pytest.mark.slow
def test_the_fast_path_is_order_and_batch_independent_bit_for_bit(solvers, points):
    fast, _ = solvers
    whole = fast.solve(points)
    order = np.random.default_rng(12).permutation(len(points))
    shuffled = fast.solve(points[order])
    np.testing.assert_array_equal(shuffled.q, whole.q[order])
    np.testing.assert_array_equal(shuffled.hand_error, whole.hand_error[order])
    np.testing.assert_array_equal(shuffled.com, whole.com[order])
    np.testing.assert_array_equal(shuffled.state.positions, whole.state.positions[order])
    np.testing.assert_array_equal(shuffled.state.rotations, whole.state.rotations[order])
    for size in (1, 7, 64):
        q = np.concatenate([fast.solve(points[a:a + size]).q
                            for a in range(0, len(points), size)])
        np.testing.assert_array_equal(q, whole.q)
    np.testing.assert_array_equal(fast.solve(points).q, whole.q)  # repeated calls


def test_a_lattice_solved_as_locations_need_it_equals_one_solved_whole(points):
    lazy, whole = PostureSolver(), PostureSolver()
    asked = []
    solve_nodes = lazy.lattice_postures
    lazy.lattice_postures = lambda nodes: asked.append(len(nodes)) or solve_nodes(nodes)
    first = lazy.solve(points[:20])
    _, nodes = StartLattice.nodes(lazy.body.stature_m)
    assert 0 < asked[0] < 0.25 * len(nodes)  # only the nodes of their cells
    lazy.solve(points[:20])
    assert len(asked) == 1  # and each node once
    np.testing.assert_array_equal(lazy.solve(points).q, whole.solve(points).q)
    np.testing.assert_array_equal(first.q, whole.solve(points[:20]).q)
    # Reading the whole lattice solves the rest: the same postures and strategies.
    np.testing.assert_array_equal(lazy.lattice.q, whole.lattice.q)
    np.testing.assert_array_equal(lazy.lattice.strategy, whole.lattice.strategy)


def _solve_q(chunk: np.ndarray) -> np.ndarray:
    return _FORK_SOLVER.solve(chunk).q


_FORK_SOLVER: PostureSolver | None = None


def test_forked_workers_give_the_same_bits(solvers, points):
    global _FORK_SOLVER
    _FORK_SOLVER = solvers[0]  # compiled and its lattice solved before the fork
    chunks = [points[a:a + 50] for a in range(0, len(points), 50)]
    with multiprocessing.get_context("fork").Pool(2) as pool:
        forked = np.concatenate(pool.map(_solve_q, chunks))
    np.testing.assert_array_equal(forked, solvers[0].solve(points).q)


def test_an_unknown_backend_is_refused():
    with pytest.raises(ValueError, match="backend"):
        PostureSolver(backend="torch")


def test_the_compiled_collision_test_equals_the_numpy_one(solvers):
    from ergohandover.twin.collision import BodyProbes
    from ergohandover.twin.task import TaskSpec

    fast, _ = solvers
    task = TaskSpec()
    half = np.array([task.box_depth, task.box_width, task.box_height]) / 2.0
    # A wide boundary, close to the body too, so that many boxes hit it.
    locations = Boundary((-0.3, 0.3), (0.2, 1.9), (0.0, 0.7)).sample(
        3000, np.random.default_rng(13))
    solution = fast.solve(locations)
    centre = fast.targets(locations).box
    probes = BodyProbes.of(fast.model.skeleton)
    compiled = probes.box_hits_body(solution.state, centre, half)
    reference = probes.box_hits_body_numpy(solution.state, centre, half)
    assert 0.1 < compiled.mean() < 0.9  # both outcomes are exercised
    np.testing.assert_array_equal(compiled, reference)
