"""``score --keypoints`` on a file read a part at a time: the rows and the summary line are those
of the whole file byte for byte, in every format, with every option that carries across parts;
its refusals are the whole file's; a file beyond the bound is refused before any work unless
--yes; and a run stopped part-way leaves nothing behind. The parts here are a few frames long
and the bound a few frames, so small files made here cross them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from cli_run import score_whole_and_in_parts

import ergohandover.capture.chunks as chunks
from ergohandover.capture import FORMATS, keypoint_format
from ergohandover.capture.readers import read_keypoints
from ergohandover.cli import keypoints as cli_keypoints
from ergohandover.cli import main

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples" / "keypoints"
SOURCES = {"h36m17": "h36m17.csv", "coco17": "coco17_long.csv",
           "mediapipe33": "mediapipe33.json", "zed34": "zed34.npz", "smpl24": "smpl24.npy"}
FRAMES = 45
PART = 7
"""Frames a part holds here (the examples' formats have 17-34 joints)."""


def made(tmp_path: Path, name: str, kind: str = "csv", frames: int = FRAMES,
         frame_column: bool = True, edit=None) -> Path:
    """A file of ``frames`` frames of format ``name``: its example's postures repeated with
    noise of a few millimetres; ``edit(points)`` changes them first."""
    fmt = keypoint_format(name)
    kp = read_keypoints(EXAMPLES / SOURCES[name], fmt)
    rng = np.random.default_rng(1)
    points = np.resize(kp.points, (frames, *kp.points.shape[1:]))
    points = points + rng.normal(0.0, 0.004, points.shape)
    if edit is not None:
        edit(points)
    path = tmp_path / f"{name}_{frames}.{kind}"
    if kind == "npy":
        np.save(path, points)
        return path
    table = pd.DataFrame(points.reshape(frames, -1),
                         columns=[f"{j}_{a}" for j in fmt.joints for a in "xyz"])
    if frame_column:
        table.insert(0, "frame", np.arange(101, 101 + frames))
    table.to_csv(path, index=False)
    return path


def run(argv: list[str], capsys) -> tuple[int, str]:
    capsys.readouterr()
    code = main(["score", *argv])
    return code, capsys.readouterr().err


@pytest.fixture
def parts(monkeypatch):
    """Parts of :data:`PART` frames (of the format with the most joints; fewer in others)."""
    monkeypatch.setattr(cli_keypoints, "PART_VALUES", 3 * 34 * PART)


@pytest.mark.parametrize("name", list(FORMATS))
@pytest.mark.parametrize("kind", ["csv", "npy"])
def test_every_format_read_in_parts_gives_the_whole_files_bytes(name, kind, tmp_path,
                                                                 monkeypatch, parts):
    path = made(tmp_path, name, kind)
    assert chunks.streamed(path, keypoint_format(name))
    text, line = score_whole_and_in_parts(
        tmp_path, ["--keypoints", str(path), "--format", name, "--load-kg", "6"], monkeypatch)
    assert text.count("\n") == FRAMES + 1
    assert f"scored {FRAMES} frames of {path}" in line


@pytest.mark.parametrize("flags", [
    ["--units", "m", "--frames", "110:140"],
    ["--frames", "20"],  # a frame not in the file's numbers is refused below; here 1-based
    ["--missing", "unseen"],
    ["--unseen", "prior", "--draws", "25000", "--seed", "5"],  # blocks of 8 rows across parts
    ["--unseen", "prior", "--draws", "3"],  # one block: every part's rows wait to the end
    ["--assume", "neck_twist=10", "--up=-y"],
])
def test_options_that_carry_across_parts_give_the_whole_files_bytes(flags, tmp_path,
                                                                   monkeypatch, parts):
    def holes(points):
        points[[3, 17, 18, 40], 13] = np.nan  # the left wrist, in four parts' frames

    frame_column = "20" not in flags
    path = made(tmp_path, "h36m17", edit=holes if "unseen" in flags else None,
                frame_column=frame_column)
    text, line = score_whole_and_in_parts(
        tmp_path, ["--keypoints", str(path), "--format", "h36m17", *flags], monkeypatch)
    if "--missing" in flags:
        assert "4 with missing points (frames 104, 118, 119, 141)" in line
    if "prior" in flags:
        assert "reba_probabilities" in text.partition("\n")[0]


def test_a_file_without_frame_numbers_and_an_unknown_unit_reads_in_parts(tmp_path,
                                                                         monkeypatch, parts):
    def centimetres(points):
        points *= 100.0

    path = made(tmp_path, "coco17", frame_column=False, edit=centimetres)
    _, line = score_whole_and_in_parts(
        tmp_path, ["--keypoints", str(path), "--format", "coco17"], monkeypatch)
    assert "units cm, told from the legs" in line


def refusal(tmp_path: Path, path: Path, flags: list[str], capsys, monkeypatch) -> str:
    """The refusal of ``flags`` read whole and in parts: the same one line, exit 2, nothing
    written."""
    lines = []
    for parted in (False, True):
        out = tmp_path / "sub" / "out.csv"
        with monkeypatch.context() as patch:
            if not parted:
                patch.setattr(chunks, "streamed", lambda p, f: False)
            code, err = run(["--keypoints", str(path), *flags, "--output", str(out)], capsys)
        assert code == 2 and err.count("\n") == 1, err
        assert not (tmp_path / "sub").exists()
        lines.append(err)
    assert lines[0] == lines[1]
    return lines[1]


def infinite(points):
    points[30, 5, 1] = np.inf


def upside_down(points):
    points[..., 1] *= -1


def tall(points):
    points *= 3.0


@pytest.mark.parametrize("edit, flags, words", [
    (infinite, [], "frame 131, joint 'left_knee' has an infinite coordinate"),
    (lambda p: p.__setitem__((slice(20, 24), 2), np.nan), [],
     "frame 121, joint 'right_knee' is missing (NaN or an empty cell; 4 of 45 frames"),
    (lambda p: p.__setitem__(slice(33, 35), np.nan), ["--missing", "unseen"],
     "frame 134 has no points (every joint is missing; 2 such frame(s))"),
    (upside_down, [], "the body is upside down along the up axis '-y'"),
    (tall, ["--units", "m"], "m tall read as --units m (the median extent"),
    (None, ["--up", "x"], "the body lies across the up axis 'x'"),
    (None, ["--frames", "900:"], "--frames 900:: "),
    (None, ["--assume", "trunk_flexion=10"], "trunk_flexion is measured in 45 of 45 frames"),
    (None, ["--load-kg", "3", "--assume", "load_kg=2"], "--load-kg and --assume load_kg"),
])
def test_a_refusal_in_parts_is_the_whole_files(edit, flags, words, tmp_path, capsys,
                                               monkeypatch, parts):
    path = made(tmp_path, "h36m17", edit=edit)
    line = refusal(tmp_path, path, ["--format", "h36m17", *flags], capsys, monkeypatch)
    assert words in line


@pytest.mark.parametrize("row, cell, words", [
    (40, ("left_hip_y", "oops"), "row 40, column 'left_hip_y': 'oops' is not a number"),
    (33, ("frame", "1.5"), "row 33, column 'frame': '1.5' is not a frame number"),
    (38, ("frame", "103"), "frame 103 is in rows 3 and 38 (expected one row per frame)"),
])
def test_a_bad_cell_in_a_later_part_is_named_by_its_row_in_the_file(row, cell, words, tmp_path,
                                                                    capsys, monkeypatch, parts):
    path = made(tmp_path, "h36m17")
    table = pd.read_csv(path, dtype=str, keep_default_na=False)
    table.loc[row - 1, cell[0]] = cell[1]
    table.to_csv(path, index=False)
    line = refusal(tmp_path, path, ["--format", "h36m17"], capsys, monkeypatch)
    assert words in line


def test_a_file_beyond_the_bound_is_refused_before_any_work_unless_yes(tmp_path, capsys,
                                                                       monkeypatch, parts):
    monkeypatch.setattr(cli_keypoints, "MAX_FRAMES", 40)
    monkeypatch.chdir(tmp_path)
    path = made(tmp_path, "h36m17")
    before = sorted(tmp_path.rglob("*"))
    code, err = run(["--keypoints", str(path), "--format", "h36m17"], capsys)
    assert code == 2 and err.count("\n") == 1, err
    assert err.startswith(f"ergohandover score: error: --keypoints {path}: 45 frames "
                          "(estimated), more than 40 (about ")
    assert err.endswith("GB of memory on this machine); give --yes to run it\n")
    assert sorted(tmp_path.rglob("*")) == before, "a refused run wrote something"
    code, err = run(["--keypoints", str(path), "--format", "h36m17", "--yes"], capsys)
    assert code == 0 and "45 frames (estimated): about" in err, err
    assert len(list((tmp_path / "runs" / "score").glob("*/scores.csv"))) == 1


@pytest.mark.parametrize("file", ["mediapipe33.json", "coco17_long.csv", "zed34.npz",
                                  "twin.bvh"])
def test_a_file_read_whole_is_counted_and_bounded_too(file, tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(cli_keypoints, "MAX_FRAMES", 5)
    name = file.partition(".")[0].partition("_")[0].replace("twin", "bvh")
    path = EXAMPLES / file
    assert not chunks.streamed(path, None if name == "bvh" else keypoint_format(name))
    code, err = run(["--keypoints", str(path), "--format", name, "--units", "cm",
                     "--output", str(tmp_path / "o.csv")], capsys)
    assert code == 2 and "6 frames (estimated), more than 5" in err and "--yes" in err, err
    assert not (tmp_path / "o.csv").exists()


def test_frames_are_counted_from_the_size_of_a_long_file(tmp_path):
    path = made(tmp_path, "h36m17", frames=400)
    assert path.stat().st_size > chunks.SAMPLE_BYTES
    assert abs(chunks.count_frames(path, 17) - 400) <= 8
    assert chunks.count_frames(made(tmp_path, "smpl24", "npy", frames=33), 24) == 33


@pytest.mark.parametrize("stop", [RuntimeError("disk"), KeyboardInterrupt()])
@pytest.mark.parametrize("output", [None, "out/scores.csv", "-"])
def test_a_run_stopped_part_way_leaves_no_output(stop, output, tmp_path, capsys, monkeypatch,
                                                 parts):
    path = made(tmp_path, "h36m17")
    monkeypatch.chdir(tmp_path)
    calls = []
    table = cli_keypoints.frame_table

    def failing(*args):
        calls.append(1)
        if len(calls) == 3:
            raise stop
        return table(*args)

    monkeypatch.setattr(cli_keypoints, "frame_table", failing)
    before = sorted(tmp_path.rglob("*"))
    capsys.readouterr()
    with pytest.raises(RuntimeError if isinstance(stop, RuntimeError) else SystemExit):
        main(["score", "--keypoints", str(path), "--format", "h36m17",
              *(["--output", output] if output else [])])
    assert len(calls) == 3
    assert sorted(tmp_path.rglob("*")) == before, "a stopped run left a file or folder"
    assert capsys.readouterr().out == ""  # standard output gets the rows only when all are
