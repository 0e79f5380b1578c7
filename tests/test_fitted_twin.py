"""The fitted twin: a posterior over candidate bodies (displaced a little) weighed by every
measured angle, and the cell it most probably holds the worker's optimum recommended."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ergohandover.envs.scores import Answer, ArrayScores, objective_values
from ergohandover.errors import ConfigError
from ergohandover.landscape.grid import Grid
from ergohandover.landscape.store import landscape_of
from ergohandover.robustness.posture_error import ErrorModel
from ergohandover.search import Budget, make, run
from ergohandover.search.fitted_twin import (
    BODY_SD_DEG,
    FIELD_ANGLES,
    SHIFT_RANGE_M,
    BodyPosterior,
    TwinLibrary,
    angle_error,
)
from ergohandover.search.prior import Prior
from ergohandover.study.personalise.measured import MeasuredScores
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.task import Boundary

GRID = Grid(Boundary((-0.1, 0.1), (0.9, 1.3), (0.35, 0.5)), 0.05)  # 5 x 9 x 4 cells
BODIES = [BodySpec.from_percentile(p) for p in ("p5-female", "p50-male", "p95-male")]
EVALUATORS = [Evaluator(body=b) for b in BODIES]
PRIOR = Prior((0.0, 1.1, 0.42), (0.05, 0.05, 0.05), (0.0, 0.5, 0.3))
NAMES = ["p5-female", "p50-male", "p95-male"]


def landscape(i: int):
    return landscape_of(EVALUATORS[i], GRID, progress=False)


def values(i: int) -> np.ndarray:
    return objective_values(landscape(i), "paper_postural")


def library(worker: int = 1, sd: float = 2.0) -> TwinLibrary:
    body = BODIES[worker]
    return TwinLibrary(GRID, EVALUATORS, landscape, "paper_postural", NAMES,
                       worker=(body.stature_m, body.sex), angle_sd_deg=sd)


def answer_at(worker: int, cell: int, score: float | None = None) -> Answer:
    """The worker's exact answer at ``cell`` (its score replaced by ``score`` if given), with
    the angles its landscape holds."""
    found = landscape(worker)
    if not found.feasible[cell]:
        return Answer(math.inf, "infeasible")
    angles = {a: float(found.arrays[a][cell]) for a in FIELD_ANGLES}
    return Answer(values(worker)[cell] if score is None else score, "posture", posture=angles)


@pytest.mark.parametrize("worker", [1, 2])
def test_exact_postures_find_the_workers_own_body_and_recommend_its_optimum(worker):
    source = MeasuredScores(GRID, EVALUATORS[worker], "paper_postural", ErrorModel(0.0),
                            np.random.default_rng(0), block=3)
    # The worker's sex only: every man of the library is a candidate.
    twins = TwinLibrary(GRID, EVALUATORS, landscape, "paper_postural", NAMES,
                        worker=(1.80, "male"), angle_sd_deg=0.5)
    searcher = make("fitted-twin", GRID, 1, PRIOR, twins=twins)
    record = run(searcher, source, Budget(evaluations=6), recommend_at=[6])
    assert searcher.chosen == worker
    best = record.info["recommendations"][6]
    assert values(worker)[best.cell] == values(worker).min()  # the worker's own optimum
    assert 0.5 < best.p_optimal <= 1
    assert best == searcher.recommend()  # kept after the sixth answer was told, not before


def test_one_lucky_low_reading_among_higher_ones_is_not_what_it_recommends():
    own = values(1)
    feasible = np.flatnonzero(np.isfinite(own))
    lucky = int(feasible[np.argmax(own[feasible])])  # the worst cell the worker can take
    others = [int(c) for c in feasible if own[c] > own.min() and c != lucky][:5]
    cells = [*others, lucky]
    told = [answer_at(1, c) for c in others] + [answer_at(1, lucky, score=1.0)]
    fitted = make("fitted-twin", GRID, 0, PRIOR, twins=library(1))
    answers_only = make("prior", GRID, 0, PRIOR)  # a model of its answers alone
    for searcher in (fitted, answers_only):
        for cell, answer in zip(cells, told, strict=True):
            searcher._pending = cell  # these handovers, whatever it would have proposed
            searcher.tell(cell, answer)
    # Far from every other reading, a model of the answers alone takes it at its word.
    assert answers_only.recommend().cell == lucky
    assert fitted.recommend().cell != lucky
    assert own[fitted.recommend().cell] < own[lucky]


def test_scores_alone_weigh_the_candidates_by_their_scores():
    between = (BODIES[1].stature_m + BODIES[2].stature_m) / 2  # both men are candidates
    posterior = BodyPosterior(TwinLibrary(GRID, EVALUATORS, landscape, "paper_postural", NAMES,
                                          worker=(between, "male")), PRIOR)
    truth = values(2)
    before = posterior.candidate_weights()
    cells = [c for c in np.flatnonzero(np.isfinite(truth))
             if values(1)[c] != truth[c]][:4]
    for cell in cells:
        posterior.update(int(cell), Answer(float(truth[cell])))
    after = posterior.candidate_weights()
    assert after[0] == 0  # a woman is no candidate for a man
    assert after[2] / after[1] > before[2] / before[1]


def test_a_handover_the_worker_could_not_take_counts_against_candidates_who_could():
    wide = Grid(Boundary((-0.1, 0.1), (0.5, 2.1), (0.3, 0.9)), 0.1)  # beyond a short man's reach
    lib = TwinLibrary(wide, EVALUATORS, lambda i: landscape_of(EVALUATORS[i], wide,
                                                               progress=False),
                      "paper_postural", NAMES,
                      worker=((BODIES[1].stature_m + BODIES[2].stature_m) / 2, "male"))
    posterior = BodyPosterior(lib, PRIOR)
    reachable = [np.isfinite(lib.values(i)) for i in (1, 2)]
    cell = int(np.flatnonzero(reachable[0] != reachable[1])[0])  # one man reaches it
    unable = 1 if not reachable[0][cell] else 2  # the man who cannot take the box there
    other = 3 - unable
    before = posterior.candidate_weights()
    posterior.update(cell, Answer(math.inf, "infeasible"))
    after = posterior.candidate_weights()
    assert after[unable] / after[other] > before[unable] / before[other]


def test_displacements_follow_the_grid_and_the_optimum_probability_is_a_probability():
    coarse = BodyPosterior(library(1), PRIOR)
    assert len(coarse.shifts) == 1  # 5 cm cells: no displacement fits within 3 cm
    fine = Grid(Boundary((-0.02, 0.02), (1.0, 1.1), (0.4, 0.46)), 0.01)
    lib = TwinLibrary(fine, EVALUATORS, lambda i: landscape_of(EVALUATORS[i], fine,
                                                               progress=False),
                      "paper_postural", NAMES, worker=(1.75, "male"))
    posterior = BodyPosterior(lib, PRIOR)
    side = 2 * round(SHIFT_RANGE_M / 0.01) + 1  # up and forward, never sideways
    assert len(posterior.shifts) == side ** 2 and set(posterior.shifts[:, 0]) == {0}
    p = posterior.p_optimal()
    assert ((p >= 0) & (p <= 1 + 1e-12)).all() and p.max() > 0
    assert posterior.weights.sum() == pytest.approx(1.0)
    # Each cell's probability is the weight of the hypotheses whose moved optimum holds it.
    feasible = np.flatnonzero(np.isfinite(lib.values(2)))
    for cell in feasible[::7][:3]:
        posterior.update(int(cell), Answer(float(lib.values(2)[cell])))
    weights, shape, expected = posterior.weights, np.array(fine.shape), np.zeros(fine.size)
    for k, d in zip(*np.nonzero(weights), strict=True):
        for cell in lib.optimum(int(k)):
            moved = np.array(np.unravel_index(cell, fine.shape)) + posterior.shifts[d]
            if ((moved >= 0) & (moved < shape)).all():
                expected[np.ravel_multi_index(tuple(moved), fine.shape)] += weights[k, d]
    assert posterior._p_optimal is None  # the update forgot the old answer
    assert np.allclose(posterior.p_optimal(), np.minimum(expected, 1.0), atol=1e-12)


def test_the_searcher_needs_twins_and_a_prior():
    with pytest.raises(ConfigError, match="needs candidate twins"):
        make("fitted-twin", GRID, 0, PRIOR)
    with pytest.raises(ConfigError, match="needs a worker's prior"):
        make("fitted-twin", GRID, 0, None, twins=library())


def test_proposals_are_new_cells_and_the_runs_read_the_model_at_every_budget():
    from ergohandover.study.personalise.measured_answers import (
        Answers,
        MeasuredJob,
        run_measured_job,
    )

    searcher = make("fitted-twin", GRID, 3, PRIOR, twins=library(2))
    record = run(searcher, ArrayScores(GRID, values(2)), Budget(evaluations=8))
    assert len(set(record.cells)) == 8

    job = MeasuredJob("p95-male", "in-model", EVALUATORS[2], GRID, "paper_postural",
                      "fitted-twin", Answers("posture", 2.0), (3, 5, 8), (7,), PRIOR,
                      tuple(zip(NAMES, EVALUATORS, strict=True)), stop_level=0.5)
    rows = run_measured_job(job)
    assert {r["rule"] for r in rows} == {"model", "model, stopped"}
    assert all(r["regret"] >= 0 and 0 <= r["p_optimal"] <= 1 for r in rows)
    for r in rows:
        assert r["true_score"] == values(2)[r["cell"]]
        assert r["handovers"] <= r["budget"]
        if r["rule"] == "model, stopped" and r["handovers"] < r["budget"]:
            assert r["p_optimal"] >= 0.5  # it stopped because its model was that sure


def test_train_does_not_offer_it_without_candidate_twins():
    from cli_run import run_cli

    done = run_cli("train", "--agent", "fitted-twin", "--steps", "5")
    assert done.returncode == 2 and "--agent fitted-twin needs candidate twins" in done.stderr
    assert done.stderr.count("\n") == 1


# The command ----------------------------------------------------------------------------------

SMALL = ["--boundary", "-0.1,0.1,1.0,1.2,0.35,0.5", "--step", "0.05"]  # 5 x 5 x 4 cells


def zed34_frames() -> list[str]:
    """The example zed34 frames (the twin taking the box at six locations) as answers."""
    from pathlib import Path

    from ergohandover.capture import keypoint_format
    from ergohandover.capture.readers import read_keypoints

    root = Path(__file__).resolve().parents[1] / "examples" / "keypoints"
    kp = read_keypoints(root / "zed34.npz", keypoint_format("zed34"))
    return [",".join(repr(float(v)) for v in points.ravel()) for points in kp.points]


@pytest.mark.slow  # each candidate body's landscape is swept first
def test_the_command_fits_a_twin_to_captured_frames_and_resumes_it(tmp_path):
    import json

    from cli_run import run_cli

    frames = zed34_frames()
    argv = ["personalise", "--oracle", "ask", "--searcher", "fitted-twin", "--stature", "1.756",
            "--sex", "male", *SMALL, "--answer-format", "keypoints:zed34", "--trials", "5"]
    whole = run_cli(*argv, "--output", str(tmp_path / "whole"),
                    stdin="\n".join(frames[:5]) + "\n")
    assert whole.returncode == 0, whole.stderr
    assert "fitted twin: " in whole.stdout
    saved = json.loads((tmp_path / "whole" / "state.json").read_text())["history"]
    assert all(h["posture"] is not None for h in saved[:3])  # the angles each frame carried
    # Stopped after two answers, then resumed: the same proposals and the same fit.
    first = run_cli(*argv, "--output", str(tmp_path / "split"), stdin="\n".join(frames[:2]) + "\n")
    assert first.returncode == 3, first.stderr
    again = run_cli(*argv, "--output", str(tmp_path / "split"),
                    stdin="\n".join(frames[2:5]) + "\n")
    assert again.returncode == 0, again.stderr
    cells = [h["cell"] for h in json.loads((tmp_path / "split" / "state.json").read_text())[
        "history"]]
    assert cells == [h["cell"] for h in saved]
    assert [ln for ln in again.stdout.splitlines() if ln.startswith("fitted twin: ")] == \
        [ln for ln in whole.stdout.splitlines() if ln.startswith("fitted twin: ")]


@pytest.mark.slow
def test_the_twin_answers_a_fitted_twin_session_with_its_own_angles(tmp_path):
    from cli_run import run_cli

    done = run_cli("personalise", "--oracle", "twin", "--searcher", "fitted-twin", *SMALL,
                   "--trials", "4", "--output", str(tmp_path / "t"))
    assert done.returncode == 0, done.stderr
    # The twin of the session is the first candidate and its angles fit it exactly.
    assert "fitted twin: the given worker" in done.stdout


def test_an_angle_measured_worse_weighs_less_and_a_restricted_body_starts_less_likely():
    from ergohandover.search import fitted_twin
    from ergohandover.twin.joint_limits import impaired

    worse = {a: (12.0 if a == "right_upper_arm_flexion" else 2.0) for a in FIELD_ANGLES}
    twins = TwinLibrary(GRID, EVALUATORS, landscape, "paper_postural", NAMES,
                        worker=(BODIES[1].stature_m, "male"), angle_sd_deg=worse)
    variance = np.diag(twins.angle_covariance)
    assert variance[FIELD_ANGLES.index("right_upper_arm_flexion")] == 144.0
    assert variance[FIELD_ANGLES.index("trunk_flexion")] == 4.0
    cell = int(np.flatnonzero(landscape(2).feasible & landscape(1).feasible)[0])
    # The same residual on the badly measured angle costs a body less than on a good one.
    costs = []
    for angle in ("right_upper_arm_flexion", "trunk_flexion"):
        posterior = BodyPosterior(twins, PRIOR)
        told = answer_at(1, cell)
        told.posture[angle] += 10.0
        before = posterior.log_weight.copy()
        posterior.update(cell, told)
        costs.append(float((before - posterior.log_weight)[1].min()))
    assert costs[0] < costs[1]
    # A candidate with a restricted joint starts with RESTRICTED_PRIOR of its unrestricted
    # self's weight.
    pair = [EVALUATORS[1], Evaluator(body=impaired(BODIES[1], "wrist cannot flex"))]
    both = TwinLibrary(GRID, pair, lambda i: landscape_of(pair[i], GRID, progress=False),
                       "paper_postural", ["free", "restricted"],
                       worker=(BODIES[1].stature_m, "male"))
    weights = BodyPosterior(both, PRIOR).candidate_weights()
    assert weights[1] / weights[0] == pytest.approx(fitted_twin.RESTRICTED_PRIOR)


def test_the_expected_score_is_the_posteriors_mean_of_the_hypotheses_scores():
    twins = library(worker=1, sd=0.5)
    posterior = BodyPosterior(twins, PRIOR)
    cells = np.flatnonzero(landscape(1).feasible)[:4]
    for cell in cells[:3]:
        posterior.update(int(cell), answer_at(1, int(cell)))
    weights = posterior.weights
    for cell, expected in zip(cells, posterior.expected_scores(cells), strict=True):
        sources, inside = posterior.sources(int(cell))
        values = np.array([twins.values(k)[sources] for k in range(len(twins))])
        feasible = np.isfinite(values) & inside[None, :]
        share = np.where(feasible, weights, 0.0)
        assert expected == pytest.approx((share * np.where(feasible, values, 0)).sum()
                                         / share.sum())
    # Told exactly, the posterior sits on the worker's own body: its scores are expected.
    assert posterior.expected_scores(cells[:1])[0] == pytest.approx(values_at(1, cells[0]),
                                                                     abs=0.05)


def values_at(worker: int, cell: int) -> float:
    return float(values(worker)[cell])


def test_a_searcher_without_a_model_recommends_from_the_workers_model_not_a_lucky_reading():
    from ergohandover.study.personalise.measured_answers import worker_model_recommendations

    own = values(1)
    feasible = np.flatnonzero(np.isfinite(own))
    best = int(feasible[np.argmin(own[feasible])])
    lucky = int(feasible[np.argmax(own[feasible])])  # the worst cell the worker can take
    others = [int(c) for c in feasible if c not in (best, lucky)][:6]
    # Tried: some cells, the worker's optimum, then the worst one read lucky and low once.
    heard = [(c, answer_at(1, c)) for c in (*others, best)] + [(lucky,
                                                                answer_at(1, lucky, 1.0))]
    found = worker_model_recommendations(library(1), PRIOR, heard, [3, len(heard)])
    assert found[len(heard)] == best  # every angle weighed: the optimum, not the lucky reading
    assert found[3] in others[:3]  # after 3 handovers: one of the 3 tried
    # A cell tried again counts once towards the budget: its answers are two measurements.
    again = worker_model_recommendations(library(1), PRIOR,
                                         [heard[0], heard[0], *heard[1:]], [3, len(heard)])
    assert again[len(heard)] == best


def test_an_instruments_bias_and_correlated_errors_weigh_the_bodies_as_its_density_does():
    from scipy.stats import multivariate_normal

    from ergohandover.robustness.measured_error import MEASURED_ERROR

    bias, covariance = angle_error(MEASURED_ERROR)
    flexion, bend = FIELD_ANGLES.index("trunk_flexion"), FIELD_ANGLES.index("trunk_side_bend")
    assert covariance[flexion, bend] == pytest.approx(0.5 * 6.6 ** 2)  # one sensor, one error
    between = (BODIES[1].stature_m + BODIES[2].stature_m) / 2  # both men stay likely
    twins = TwinLibrary(GRID, EVALUATORS, landscape, "paper_postural", NAMES,
                        worker=(between, "male"), error=MEASURED_ERROR)
    cell = int(np.flatnonzero(landscape(1).feasible & landscape(2).feasible)[0])
    told = answer_at(1, cell)
    for angle in ("trunk_flexion", "trunk_side_bend", "right_upper_arm_flexion"):
        told.posture[angle] += 6.0  # an error shared by the trunk's sensor, and the arm's
    posterior = BodyPosterior(twins, PRIOR)
    before = posterior.log_weight.copy()
    posterior.update(cell, told)
    still = int(np.flatnonzero((posterior.shifts == 0).all(axis=1))[0])  # no displacement
    step = (posterior.log_weight - before)[[1, 2], still]
    measured = np.array([told.posture[a] for a in FIELD_ANGLES]) - bias
    joint = covariance + np.eye(len(FIELD_ANGLES)) * BODY_SD_DEG ** 2
    density = [multivariate_normal(twins.angles([cell], [k])[0, 0], joint).logpdf(measured)
               for k in (1, 2)]
    # The two bodies' odds move as the instrument's density says, correlations included.
    assert step[1] - step[0] == pytest.approx(density[1] - density[0], abs=1e-6)
    alone = [multivariate_normal(twins.angles([cell], [k])[0, 0],
                                 np.diag(np.diag(joint))).logpdf(measured) for k in (1, 2)]
    assert abs((alone[1] - alone[0]) - (density[1] - density[0])) > 1e-3


def test_a_bilateral_error_is_one_draw_for_both_sides_of_an_angle():
    bias, covariance = angle_error(ErrorModel(4.0, "bilateral"))
    right, left = (FIELD_ANGLES.index(f"{side}_elbow_flexion") for side in ("right", "left"))
    assert covariance[right, left] == covariance[right, right] == 16.0 and not bias.any()
    _, independent = angle_error(ErrorModel(4.0))
    assert independent[right, left] == 0.0
    assert np.array_equal(np.diag(covariance), np.diag(independent))
