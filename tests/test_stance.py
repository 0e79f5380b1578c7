"""A worker who may step toward the box: where the feet go, which step is taken, and what it does
to the posture and the scores."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from cli_run import run_cli

import ergohandover.landscape.cache as cache_module
from ergohandover.cli import main
from ergohandover.landscape.cache import Landscape
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import EvaluationError, Evaluator, evaluate
from ergohandover.twin.stance import (
    STEP_FRACTIONS,
    chosen_step,
    step_length_m,
    step_offsets,
)
from ergohandover.twin.task import TaskSpec

PLANTED, STEPPING = Evaluator(), Evaluator(task=TaskSpec(stance="step"))
SCORES = ("paper_postural", "reba", "rula")


def test_the_step_length_is_the_cited_share_of_leg_length():
    body = BodySpec()
    assert step_length_m(body) == pytest.approx(0.856 * body.segments().hip_height)
    assert 0.70 < step_length_m(body) < 0.85  # the default man's hip height is about 0.9 m


def test_the_feet_move_along_the_floor_toward_the_box_and_never_past_it():
    locations = np.array([[0.0, 1.0, 0.60], [0.20, 0.9, 0.30], [-0.1, 1.3, 1.50]])
    offsets = step_offsets(locations, BodySpec())
    assert offsets.shape == (len(STEP_FRACTIONS), 3, 3)
    assert np.all(offsets[:, :, 1] == 0)  # on the floor
    assert np.all(offsets[0] == 0)  # the first candidate is no step
    lengths = np.linalg.norm(offsets, axis=2)
    horizontal = np.linalg.norm(locations[:, [0, 2]], axis=1)
    assert np.all(lengths <= np.minimum(step_length_m(BodySpec()), horizontal) + 1e-12)
    # Toward the box: the step is a positive multiple of the box's horizontal direction.
    toward = np.einsum("knc,nc->kn", offsets, locations * [1, 0, 1])
    assert np.allclose(toward, lengths * horizontal)
    assert lengths[-1, 2] == pytest.approx(step_length_m(BodySpec()))  # a far box: a whole step


def test_the_cheapest_feasible_candidate_is_taken_and_ties_keep_the_shorter_step():
    cost = np.array([[5.0, 1.0, 2.0, 3.0], [4.0, 1.0, 2.0, 3.0], [3.0, 1.0, 9.0, 3.0]])
    feasible = np.array([[True, True, False, False], [True, True, True, False],
                         [True, False, True, False]])
    # Location 0: the cheapest feasible is the last candidate; 1: equal costs, the shorter step;
    # 2: the cheapest is infeasible, so the next; 3: none feasible, no step.
    assert chosen_step(cost, feasible).tolist() == [2, 0, 1, 0]


@pytest.mark.slow
def test_a_far_box_taken_with_a_step_scores_no_worse_and_the_feet_stay_within_a_step():
    # The paper-code grid's far edge in front of the body (full reach, 0.60 m), at three heights.
    far = np.array([[0.0, 0.95, 0.60], [0.0, 1.10, 0.60], [0.0, 1.25, 0.60]])
    planted, stepping = evaluate(far, PLANTED), evaluate(far, STEPPING)
    assert (stepping["feasible"] == 1).all()
    assert (stepping["step_m"] > 0).all()
    assert (stepping["step_m"] <= step_length_m(BodySpec()) + 1e-12).all()
    for score in SCORES:
        assert (stepping[score].astype(int) <= planted[score].astype(int)).all(), score
    # Planted, the arms reach out nearly straight; a step closer lowers the upper arms and bends
    # the elbows toward their neutral angle.
    for side in ("left", "right"):
        assert (stepping[f"{side}_upper_arm_flexion"] < planted[f"{side}_upper_arm_flexion"]
                - 10).all()
        assert (stepping[f"{side}_elbow_flexion"] > planted[f"{side}_elbow_flexion"] + 10).all()


def test_a_box_beyond_reach_is_taken_after_a_step():
    beyond = np.array([[0.0, 1.10, 1.15]])  # planted: hands short of the handles, unbalanced
    assert evaluate(beyond, PLANTED)["feasible"].iloc[0] == 0
    row = evaluate(beyond, STEPPING).iloc[0]
    assert row["feasible"] == 1 and row["step_m"] > 0.2 and row["reason"] == ""


def test_a_stepping_worker_is_evaluated_the_same_in_any_batch():
    points = np.array([[0.0, 1.0, 0.60], [0.1, 1.2, 0.40], [-0.2, 0.8, 0.50], [0.0, 1.1, 0.95]])
    together = evaluate(points, STEPPING)
    alone = [evaluate(points[i:i + 1], STEPPING).iloc[0] for i in range(len(points))]
    for i, row in enumerate(alone):
        assert row.equals(together.iloc[i]), i


def test_the_planted_worker_has_no_step_column_and_the_paper_solver_cannot_step():
    assert "step_m" not in evaluate(np.array([[0.0, 1.0, 0.4]]), PLANTED).columns
    with pytest.raises(EvaluationError, match="stance = 'step' is not allowed with solver"):
        Evaluator(task=TaskSpec(stance="step"), solver="pybullet")




def test_evaluate_takes_the_stance_and_refuses_a_bad_one_in_one_line():
    done = run_cli("evaluate", "--points", "-", "--output", "-", "--stance", "step",
                   stdin="x,y,z\n0,1.1,1.15\n")
    assert done.returncode == 0, done.stderr
    header, row = done.stdout.splitlines()
    values = dict(zip(header.split(","), row.split(","), strict=True))
    assert values["feasible"] == "1" and float(values["step_m"]) > 0.2
    bad = run_cli("evaluate", "--points", "-", "--output", "-", "--stance", "walk",
                  stdin="x,y,z\n0,1.1,0.5\n")
    assert bad.returncode == 2 and bad.stdout == ""
    assert len(bad.stderr.strip().splitlines()) == 1 and "--stance" in bad.stderr
    assert "walk" in bad.stderr and "fixed" in bad.stderr and "step" in bad.stderr


def sweep_each(tmp_path, monkeypatch, capsys, boundary: str, step: str, flag: str,
               values: tuple[str, ...]) -> dict:
    """``ergohandover sweep`` once per value of ``flag`` into an empty cache: value ->
    Landscape."""
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(tmp_path / "cache"))
    cache_module.twin_code_version.cache_clear()
    found = {}
    for value in values:
        out = tmp_path / value
        assert main(["sweep", "--boundary", boundary, "--step", step, "--workers", "1", flag,
                     value, "--output", str(out)]) == 0
        manifest = json.loads((out / "manifest.json").read_text())
        found[value] = Landscape.load(Path(manifest["landscape"]))
    capsys.readouterr()
    return found


@pytest.mark.slow
def test_sweep_keeps_the_stepping_landscape_apart_and_it_takes_every_planted_location(
        tmp_path, monkeypatch, capsys):
    found = sweep_each(tmp_path, monkeypatch, capsys, "-0.1,0.1,0.9,1.2,0.7,1.1", "0.1",
                       "--stance", ("fixed", "step"))
    assert found["fixed"].path != found["step"].path
    planted, stepping = found["fixed"].feasible, found["step"].feasible
    # No step is one of the candidates: wherever the planted worker takes the box, so can the
    # stepping one; beyond reach (z up to 1.1 m) only the stepping one can.
    assert np.all(stepping[planted]) and stepping.sum() > planted.sum()
