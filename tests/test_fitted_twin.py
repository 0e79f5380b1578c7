"""The fitted twin: the candidate body whose twin explains the first handovers best, and its
optimum proposed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ergohandover.envs.scores import ArrayScores
from ergohandover.errors import ConfigError
from ergohandover.landscape.grid import Grid
from ergohandover.robustness.posture_error import ErrorModel
from ergohandover.search import Budget, make, run
from ergohandover.search.fitted_twin import FIT, TwinLibrary, fit
from ergohandover.search.prior import Prior
from ergohandover.study.personalise.measured import MeasuredScores
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator, evaluate_arrays
from ergohandover.twin.task import Boundary

GRID = Grid(Boundary((-0.1, 0.1), (0.9, 1.3), (0.35, 0.5)), 0.05)  # 5 x 9 x 4 cells
BODIES = [BodySpec.from_percentile(p) for p in ("p5-female", "p50-male", "p95-male")]
EVALUATORS = [Evaluator(body=b) for b in BODIES]
PRIOR = Prior((0.0, 1.1, 0.42), (0.05, 0.05, 0.05))
_VALUES: dict[int, np.ndarray] = {}


def values(i: int) -> np.ndarray:
    if i not in _VALUES:
        found = evaluate_arrays(GRID.coordinates(np.arange(GRID.size)), EVALUATORS[i])
        _VALUES[i] = np.where(found["feasible"], found["paper_postural"], np.inf)
    return _VALUES[i]


def library() -> TwinLibrary:
    return TwinLibrary(GRID, EVALUATORS, values, ["p5-female", "p50-male", "p95-male"])


@pytest.mark.parametrize("worker", [0, 2])
def test_exact_postures_pick_the_workers_own_body_and_its_optimum_comes_next(worker):
    source = MeasuredScores(GRID, EVALUATORS[worker], "paper_postural", ErrorModel(0.0),
                            np.random.default_rng(0), block=3)
    searcher = make("fitted-twin", GRID, 1, PRIOR, twins=library())
    record = run(searcher, source, Budget(evaluations=FIT + 1))
    assert searcher.chosen == worker
    own = values(worker)
    assert own[record.cells[FIT]] == own.min()  # the fitted twin's optimum: the worker's own


def test_with_scores_only_the_fit_uses_the_scores():
    own = values(1)
    searcher = make("fitted-twin", GRID, 2, PRIOR, twins=library())
    run(searcher, ArrayScores(GRID, own), Budget(evaluations=FIT + 2))
    assert searcher.postures[:FIT] == [None] * FIT
    best, misfit = fit(library(), searcher.cells[:FIT], searcher.told_answers[:FIT],
                       [None] * FIT)
    assert searcher.chosen == best and misfit[best] == misfit.min()
    if np.isfinite(searcher.told_answers[:FIT]).any():
        assert misfit[1] == 0  # its own scores explain the handovers exactly


def test_a_fit_needs_a_feasible_handover_and_the_searcher_needs_twins():
    with pytest.raises(ConfigError, match="there is none"):
        fit(library(), [0, 1], [math.inf, math.inf], [None, None])
    with pytest.raises(ConfigError, match="needs candidate twins"):
        make("fitted-twin", GRID, 0, PRIOR)


def test_measured_runs_read_the_fitted_twins_choice_at_every_budget():
    from ergohandover.study.personalise.measured_answers import (
        Answers,
        MeasuredJob,
        run_measured_job,
    )

    job = MeasuredJob("p95-male", "in-model", EVALUATORS[2], GRID, "paper_postural",
                      "fitted-twin", Answers("posture", 2.0), (3, 5, 8), (7,), PRIOR,
                      (("a", EVALUATORS[0]), ("b", EVALUATORS[1]), ("c", EVALUATORS[2])))
    rows = run_measured_job(job)
    assert {r["rule"] for r in rows} == {"lowest", "confirm"}
    assert all(r["regret"] >= 0 for r in rows)
    # The true score of what it recommends is the worker's own (candidate c is its body).
    lowest = {r["budget"]: r for r in rows if r["rule"] == "lowest"}
    for row in lowest.values():
        assert row["true_score"] == values(2)[row["cell"]]


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


@pytest.mark.slow  # each candidate body's solver solves its warm-start lattice first
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
    assert all(h["posture"] is not None for h in saved[:FIT])  # the angles each frame carried
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


def test_the_command_refuses_the_fitted_twin_without_postures_in_the_answers():
    from cli_run import run_cli

    done = run_cli("personalise", "--oracle", "ask", "--searcher", "fitted-twin", "--stature",
                   "1.7", "--sex", "female", *SMALL)
    assert done.returncode == 2 and done.stderr.count("\n") == 1
    assert "--searcher fitted-twin needs the worker's posture in every answer" in done.stderr


@pytest.mark.slow
def test_the_twin_answers_a_fitted_twin_session_with_its_own_angles(tmp_path):
    from cli_run import run_cli

    done = run_cli("personalise", "--oracle", "twin", "--searcher", "fitted-twin", *SMALL,
                   "--trials", "4", "--output", str(tmp_path / "t"))
    assert done.returncode == 0, done.stderr
    # The twin of the session is the first candidate and its angles fit it exactly.
    assert "fitted twin: the given worker" in done.stdout
