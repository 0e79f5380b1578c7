"""A keypoint file that does not fit its format, and a capture's scores read back: a file whose
bones are not a person's in the declared format is refused naming the format they fit (before
any hint of an up axis or a unit), and the output of ``score --keypoints`` read by ``score
--input`` gives the same scores and intervals, while ``robustness`` refuses it naming the
unseen columns and ``--assume``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from test_cli_capture import EXAMPLES, KEYPOINTS
from twin_postures import random_twin_postures

from ergohandover.capture.bones import bone_lengths, misfit
from ergohandover.capture.formats import FORMATS
from ergohandover.capture.placement import place
from ergohandover.capture.readers import read_keypoints
from ergohandover.cli import main
from ergohandover.ergonomics.posture import POSTURE_COLUMNS
from ergohandover.twin.anthropometry import BodySpec

SCORES = [f"{s}{end}" for s in ("reba", "rula", "paper_postural") for end in ("", "_lo", "_hi")]


def refused(argv: list[str], tmp_path: Path, capsys, command: str = "score") -> str:
    """Run ``command`` expecting exit 2, one line on stderr, nothing on stdout and nothing
    written under ``tmp_path``; the line without its prefix."""
    before = sorted(tmp_path.rglob("*"))
    capsys.readouterr()
    code = main([command, *argv])
    out, err = capsys.readouterr()
    assert code == 2, err
    assert out == "" and err.count("\n") == 1 and "Traceback" not in err, err
    assert sorted(tmp_path.rglob("*")) == before, "a refused command wrote something"
    prefix = f"ergohandover {command}: error: "
    assert err.startswith(prefix), err
    return err.removeprefix(prefix).rstrip("\n")


def example_npy(tmp_path: Path, name: str) -> Path:
    """Format ``name``'s example file as an NPY array, which holds no joint names."""
    path = tmp_path / f"{name}.npy"
    np.save(path, read_keypoints(KEYPOINTS / EXAMPLES[name][0], FORMATS[name]).points)
    return path


# 1. Bones that do not fit the declared format ---------------------------------------------------

@pytest.mark.parametrize(("given", "fits"), [("h36m17", "coco17"), ("coco17", "h36m17")])
@pytest.mark.parametrize("flags", [[], ["--up", "y"], ["--up", "z", "--units", "cm"]])
def test_a_file_in_the_other_17_joint_format_is_refused_naming_it(given, fits, flags, tmp_path,
                                                                  capsys):
    path = example_npy(tmp_path, fits)
    line = refused(["--keypoints", str(path), "--format", given, *flags, "--output",
                    str(tmp_path / "out.csv")], tmp_path, capsys)
    assert line.startswith(f"{path}: its bones fit {fits}, not --format {given} (its "), line
    assert line.endswith(f"): try --format {fits}"), line
    assert "--up" not in line and "--units" not in line  # no flag that would score it wrong


def test_the_format_the_refusal_names_scores_the_file(tmp_path):
    path = example_npy(tmp_path, "coco17")
    assert main(["score", "--keypoints", str(path), "--format", "coco17", "--output",
                 str(tmp_path / "out.csv")]) == 0


def test_a_file_no_format_fits_is_refused_naming_the_joint_order(tmp_path, capsys):
    path = tmp_path / "smpl.npy"
    points = read_keypoints(KEYPOINTS / "smpl24.npy", FORMATS["smpl24"]).points
    np.save(path, points[:, ::-1])  # the joints in reverse order
    line = refused(["--keypoints", str(path), "--format", "smpl24", "--output",
                    str(tmp_path / "out.csv")], tmp_path, capsys)
    assert line.startswith(f"{path}: its bones do not fit --format smpl24 (its "), line
    assert line.endswith("): give its joints in smpl24's order (docs/capture.md), or the "
                         "format they are in"), line


@pytest.mark.parametrize("body", ["p5-female", "p50-male", "p95-male"])
def test_every_format_fits_its_own_bones_in_any_posture_and_not_another(body):
    spec = BodySpec.from_percentile(body)
    _, state, _ = random_twin_postures(60, 11, spec)
    for name, fmt in FORMATS.items():
        points = place(state, spec, fmt)
        for one in range(len(points)):  # frame by frame: no median over postures to lean on
            assert misfit(bone_lengths(points[one:one + 1], fmt))[0] <= 1.0, (name, one)
            for other in FORMATS.values():
                if other is not fmt and len(other.joints) == len(fmt.joints):
                    assert misfit(bone_lengths(points[one:one + 1], other))[0] > 1.0, \
                        (name, other.name, one)


def test_a_file_with_too_few_points_seen_is_not_judged():
    points = np.full((1, 17, 3), np.nan)
    points[0, :3] = np.eye(3)
    assert np.isnan(misfit(bone_lengths(points, FORMATS["h36m17"]))[0])


# 2. A capture's output read back ----------------------------------------------------------------

def keypoint_scores(tmp_path: Path, name: str, *flags: str) -> Path:
    file, more = EXAMPLES[name]
    out = tmp_path / f"{name}-keypoints.csv"
    assert main(["score", "--keypoints", str(KEYPOINTS / file), "--format", name, *more,
                 *flags, "--output", str(out)]) == 0
    return out


def read(path: Path) -> pd.DataFrame:
    return pd.read_csv(path, dtype=str, keep_default_na=False)


@pytest.mark.parametrize("name", list(EXAMPLES))
def test_score_input_gives_a_captures_scores_and_intervals_back(name, tmp_path):
    first = keypoint_scores(tmp_path, name, "--load-kg", "6")
    again = tmp_path / "again.csv"
    assert main(["score", "--input", str(first), "--output", str(again)]) == 0
    before, after = read(first), read(again)
    assert (before["unseen"] != "").any(), "the example leaves nothing unseen"
    assert list(after.columns) == list(before.columns)
    pd.testing.assert_frame_equal(after[SCORES], before[SCORES])
    assert again.read_bytes() == first.read_bytes()


def test_missing_points_declared_unseen_come_back_row_by_row(tmp_path):
    # Frames that miss different points leave different columns unseen.
    points = read_keypoints(KEYPOINTS / "h36m17.csv", FORMATS["h36m17"]).points.copy()
    points[1, FORMATS["h36m17"].index("left_wrist")] = np.nan
    points[3, FORMATS["h36m17"].index("head")] = np.nan
    path = tmp_path / "gaps.npy"
    np.save(path, points)
    first, again = tmp_path / "first.csv", tmp_path / "again.csv"
    assert main(["score", "--keypoints", str(path), "--format", "h36m17", "--missing", "unseen",
                 "--output", str(first)]) == 0
    assert len(set(read(first)["unseen"])) >= 3
    assert main(["score", "--input", str(first), "--output", str(again)]) == 0
    pd.testing.assert_frame_equal(read(again)[SCORES], read(first)[SCORES])


ZED_RIGID = [f"{side}_{column}" for side in ("left", "right") for column in (
    "shoulder_raise", "wrist_flexion", "wrist_deviation", "wrist_twist")]
"""The columns ZED BODY_34 leaves unseen in every frame (its fitted skeleton holds them)."""


def test_a_filled_unseen_cell_is_measured_as_an_assumed_one(tmp_path):
    table = read(keypoint_scores(tmp_path, "zed34"))
    assert all(set(ZED_RIGID) <= set(cell.split(";")) for cell in table["unseen"])
    filled = table.copy()
    filled[ZED_RIGID] = "0"
    path, again = tmp_path / "filled.csv", tmp_path / "again.csv"
    filled.to_csv(path, index=False)
    assert main(["score", "--input", str(path), "--output", str(again)]) == 0
    after = read(again)
    assert not any(set(ZED_RIGID) & set(cell.split(";")) for cell in after["unseen"])
    assumed = read(keypoint_scores(tmp_path, "zed34", *(f"--assume={c}=0" for c in ZED_RIGID)))
    pd.testing.assert_frame_equal(after[["unseen", *SCORES]], assumed[["unseen", *SCORES]])
    for score in ("reba", "rula", "paper_postural"):  # a known value only narrows
        assert (after[f"{score}_lo"].astype(int) >= table[f"{score}_lo"].astype(int)).all()
        assert (after[f"{score}_hi"].astype(int) <= table[f"{score}_hi"].astype(int)).all()


@pytest.mark.parametrize(("change", "says"), [
    (lambda t: t.__setitem__("trunk_flexion", ["", *t["trunk_flexion"][1:]]),
     "{file}: row 1, column 'trunk_flexion': an empty cell is not a number (expected "),
    (lambda t: t.__setitem__("unseen", ["left_elbow"] * len(t)),
     "{file}: row 1, column 'unseen': 'left_elbow' is not a Posture column (expected the row's "
     "unseen Posture columns joined by ';', as `score --keypoints` writes them)"),
])
def test_a_captures_output_changed_by_hand_is_refused(change, says, tmp_path, capsys):
    table = read(keypoint_scores(tmp_path, "h36m17"))
    change(table)
    path = tmp_path / "changed.csv"
    table.to_csv(path, index=False)
    line = refused(["--input", str(path), "--output", str(tmp_path / "out.csv")], tmp_path,
                   capsys)
    assert line.startswith(says.format(file=path)), line
    if "empty cell" in says:
        assert line.endswith("; the row's 'unseen' cell does not name this column (an empty "
                             "cell is unseen only where it does)"), line


def test_workload_flags_are_refused_for_a_captures_output(tmp_path, capsys):
    first = keypoint_scores(tmp_path, "coco17")
    line = refused(["--input", str(first), "--shift-hours", "8", "--output",
                    str(tmp_path / "out.csv")], tmp_path, capsys)
    assert line == (f"--shift-hours cannot be used with {first}: it has an 'unseen' column (a "
                    "capture's), and the workload columns need every angle")


def test_robustness_refuses_a_captures_output_naming_the_unseen_columns(tmp_path, capsys):
    first = keypoint_scores(tmp_path, "zed34")
    unseen = [c for c in POSTURE_COLUMNS if any(c in cell.split(";")
                                                for cell in read(first)["unseen"])]
    line = refused(["--postures", str(first), "--draws", "10", "--output",
                    str(tmp_path / "out.csv")], tmp_path, capsys, command="robustness")
    assert line == (f"--postures {first}: 6 of 6 rows leave columns unseen (empty, as its "
                    f"'unseen' column says): {', '.join(unseen)}; every column is needed here: "
                    "score the keypoints again with --assume COLUMN=VALUE for each, or fill "
                    "them")


def test_robustness_reads_a_captures_output_once_every_column_is_given(tmp_path):
    table = read(keypoint_scores(tmp_path, "zed34"))
    for name in {c for cell in table["unseen"] for c in cell.split(";") if c}:
        table[name] = "0"
    path, out = tmp_path / "given.csv", tmp_path / "robust.csv"
    table.to_csv(path, index=False)
    assert main(["robustness", "--postures", str(path), "--draws", "10", "--output",
                 str(out)]) == 0
    assert len(pd.read_csv(out)) == 6 * 3


def test_a_captured_answer_in_the_other_17_joint_format_is_refused_naming_it():
    from ergohandover.search.answers import AnswerReader, Refused

    reader = AnswerReader("paper_postural", keypoints="keypoints:h36m17")
    coco = read_keypoints(KEYPOINTS / "coco17_long.csv", FORMATS["coco17"]).points[0]
    with pytest.raises(Refused) as refusal:
        reader.read(",".join(repr(float(v)) for v in coco.ravel()))
    assert str(refusal.value).startswith("the frame: its bones fit coco17, not "
                                         "--answer-format keypoints:h36m17 (its ")
    assert str(refusal.value).endswith("): try --answer-format keypoints:coco17")
    h36m = read_keypoints(KEYPOINTS / "h36m17.csv", FORMATS["h36m17"]).points[0]
    assert reader.read(",".join(repr(float(v)) for v in h36m.ravel())).kind == "keypoints"
