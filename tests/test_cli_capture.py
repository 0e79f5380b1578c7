"""``ergohandover score --keypoints`` and ``--items``, and ``personalise --answer-format
keypoints:…``, end to end through the CLI: every example keypoint file scores as the worker
twin's own postures at the same handover locations, a rater's published worksheets come back
score for score, and every malformed input is refused in one line with nothing written."""

from __future__ import annotations

import importlib.util
import io
import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ergohandover.cli import main
from ergohandover.ergonomics.posture import POSTURE_COLUMNS
from ergohandover.ergonomics.worksheet import item_columns

ROOT = Path(__file__).resolve().parents[1]
KEYPOINTS = ROOT / "examples" / "keypoints"
POSTURES = ROOT / "examples" / "postures.csv"
WORKSHEETS = {sheet: ROOT / "examples" / f"worksheet_{sheet}.csv" for sheet in ("reba", "rula")}
EXAMPLES = {  # --format -> (file, further flags)
    "h36m17": ("h36m17.csv", []),
    "coco17": ("coco17_long.csv", []),
    "mediapipe33": ("mediapipe33.json", []),
    "zed34": ("zed34.npz", []),
    "smpl24": ("smpl24.npy", []),
    "bvh": ("twin.bvh", ["--units", "cm"]),
}
WITH_SPINE = ("h36m17", "zed34", "smpl24", "bvh")
"""The formats with a spine point and a neck base: the trunk and neck as the twin bends them."""
SCORES = ("reba", "rula", "paper_postural")
BOX_KG = "6"  # the study's box, which keypoints cannot show
ERROR = "ergohandover score: error: "


def example(name: str) -> list[str]:
    """The flags that read format ``name``'s example file."""
    file, flags = EXAMPLES[name]
    return ["--keypoints", str(KEYPOINTS / file), "--format", name, *flags]


def read(path: Path) -> pd.DataFrame:
    """A written CSV as text, an empty cell as ''."""
    return pd.read_csv(path, dtype=str, keep_default_na=False)


def numbers(column: pd.Series) -> np.ndarray:
    """A column of text cells as floats, an empty cell as NaN."""
    return pd.to_numeric(column.replace("", np.nan)).to_numpy(dtype=float)


def score(tmp_path: Path, *flags: str, name: str = "scores.csv") -> pd.DataFrame:
    out = tmp_path / name
    assert main(["score", *flags, "--output", str(out)]) == 0
    return read(out)


def refused(argv: list[str], tmp_path: Path, capsys, command: str = "score") -> str:
    """Run ``command`` expecting exit 2, one line on stderr, nothing on stdout and nothing
    written under ``tmp_path``; the line."""
    before = sorted(tmp_path.rglob("*"))
    capsys.readouterr()
    code = main([command, *argv])
    out, err = capsys.readouterr()
    assert code == 2, err
    assert out == "" and err.count("\n") == 1 and err.endswith("\n"), err
    assert err.startswith(f"ergohandover {command}: error: ") and "Traceback" not in err, err
    assert sorted(tmp_path.rglob("*")) == before, "a refused command wrote something"
    return err.rstrip("\n")


@pytest.fixture(scope="module")
def twin() -> pd.DataFrame:
    """The twin's own scores at the example files' handover locations, frame by frame."""
    from ergohandover.twin.evaluate import evaluate

    path = ROOT / "experiments" / "tools" / "capture_examples.py"
    spec = importlib.util.spec_from_file_location("capture_examples", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    table = evaluate(module.LOCATIONS)
    assert table["feasible"].all() and len(table) == 6
    return table


# 1. Every example file scores through the CLI --------------------------------------------------

@pytest.mark.parametrize("name", list(EXAMPLES))
def test_every_example_file_scores_as_the_twins_own_postures(name, tmp_path, twin):
    table = score(tmp_path, *example(name), "--load-kg", BOX_KG)
    bounds = [f"{s}{end}" for s in SCORES for end in ("", "_lo", "_hi")]
    assert list(table.columns) == ["frame", *POSTURE_COLUMNS, "unseen", *bounds]
    assert table["frame"].tolist() == ["1", "2", "3", "4", "5", "6"]
    assert (numbers(table["load_kg"]) == 6).all()
    unseen = [set(filter(None, cell.split(";"))) for cell in table["unseen"]]
    for row, names in enumerate(unseen):
        assert names <= set(POSTURE_COLUMNS), names
        empty = {c for c in POSTURE_COLUMNS if table.loc[row, c] == ""}
        assert empty == names, f"frame {row + 1}: empty {empty ^ names} vs unseen"
    for s in SCORES:
        given, lo, hi = (numbers(table[c]) for c in (s, f"{s}_lo", f"{s}_hi"))
        assert np.isfinite(lo).all() and np.isfinite(hi).all() and (lo <= hi).all(), s
        # given exactly where the interval is one value, and then that value
        np.testing.assert_array_equal(np.isfinite(given), lo == hi, err_msg=s)
        np.testing.assert_array_equal(given[lo == hi], lo[lo == hi], err_msg=s)
        truth = twin[s].to_numpy(dtype=float)
        if name in WITH_SPINE:
            inside = (lo <= truth) & (truth <= hi)
            assert inside.all(), f"{s}: twin {truth} outside [{lo}, {hi}]"
        if name == "zed34" and s == "paper_postural":  # ZED sees every column it reads
            np.testing.assert_array_equal(given, truth, err_msg=s)


def test_the_prior_gives_each_scores_distribution_and_the_same_seed_the_same_file(
        tmp_path, capsys):
    flags = [*example("h36m17"), "--load-kg", BOX_KG, "--unseen", "prior", "--draws", "200",
             "--seed", "3"]
    table = score(tmp_path, *flags, name="a.csv")
    score(tmp_path, *flags, name="b.csv")
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
    assert [c for c in table.columns if c.endswith("_probabilities")] == [
        f"{s}_probabilities" for s in SCORES]
    spread = 0
    for s in SCORES:
        lo, hi, given = (numbers(table[c]) for c in (f"{s}_lo", f"{s}_hi", s))
        for row, text in enumerate(table[f"{s}_probabilities"]):
            pairs = [cell.split(":") for cell in text.split(" ")]
            values = [int(v) for v, _ in pairs]
            shares = [float(p) for _, p in pairs]
            assert all(len(p) == len(f"{x:.3f}") for (_, p), x in zip(pairs, shares,
                                                                      strict=True)), text
            assert values == sorted(set(values)) and all(x > 0 for x in shares), text
            assert sum(shares) == pytest.approx(1.0, abs=0.002 * len(shares)), text
            assert lo[row] <= min(values) and max(values) <= hi[row], (s, row, text)
            if np.isfinite(given[row]):
                assert values == [int(given[row])] and shares == [1.0], (s, row, text)
            spread += len(values) > 1
    assert spread > 0, "no open score spread over values: the test would show nothing"


# 2. Frames, assumptions and the up axis -------------------------------------------------------

def test_frames_keeps_those_frames_and_scores_them_as_in_the_whole_file(tmp_path):
    whole = score(tmp_path, *example("h36m17"), name="whole.csv")
    part = score(tmp_path, *example("h36m17"), "--frames", "2:3", name="part.csv")
    assert part["frame"].tolist() == ["2", "3"]
    pd.testing.assert_frame_equal(part, whole.iloc[1:3].reset_index(drop=True))


def test_an_assumed_column_leaves_unseen_and_takes_its_value(tmp_path):
    assumed = ("left_wrist_flexion", "left_wrist_deviation")
    whole = score(tmp_path, *example("h36m17"), name="whole.csv")
    flags = [f for c in assumed for f in ("--assume", f"{c}=0")]
    table = score(tmp_path, *example("h36m17"), *flags, name="assumed.csv")
    for before, after in zip(whole["unseen"], table["unseen"], strict=True):
        assert set(before.split(";")) & set(assumed) == set(assumed)  # unseen without them
        assert set(filter(None, after.split(";"))) == set(before.split(";")) - set(assumed)
    for c in assumed:
        assert (numbers(table[c]) == 0).all()
    # an assumed neutral wrist can only narrow the intervals
    for s in SCORES:
        assert (numbers(table[f"{s}_lo"]) >= numbers(whole[f"{s}_lo"])).all()
        assert (numbers(table[f"{s}_hi"]) <= numbers(whole[f"{s}_hi"])).all()


@pytest.mark.parametrize(("up", "problem"), [
    ("z", "the body lies across the up axis 'z'"),
    ("y", "the body is upside down along the up axis 'y'"),
])
def test_a_wrong_up_axis_is_refused(tmp_path, capsys, up, problem):
    out = tmp_path / "out.csv"
    err = refused([*example("h36m17"), "--up", up, "--output", str(out)], tmp_path, capsys)
    assert err.startswith(f"{ERROR}{KEYPOINTS / 'h36m17.csv'}: {problem}"), err
    assert "(--up" in err


# 3. A rater's worksheet -----------------------------------------------------------------------

PRINTED = {  # sheet -> the published rows' sources and their printed scores
    "reba": [("Ejemplo 1", {"reba": 4}),
             ("rs9000/ergonomics", {"reba_score_a": 4, "reba_score_b": 3, "reba_score_c": 4,
                                    "reba": 4})],
    "rula": [("Metodo Rula", {"rula_left_table_a": 5, "rula_left_score_c": 6,
                              "rula_table_b": 6, "rula_score_d": 7, "rula": 7})],
}


@pytest.mark.parametrize("sheet", list(WORKSHEETS))
def test_the_example_worksheets_come_back_score_for_score(sheet, tmp_path, capsys):
    source = read(WORKSHEETS[sheet])
    items = [c for c in source.columns if c in item_columns(sheet)]
    scores = [c for c in source.columns if c != "source" and c not in items]
    assert source.columns[0] == "source" and (source["source"] != "").all()
    assert len(source) == len(PRINTED[sheet]) + 2  # the published rows and two of ours
    for row, (name, printed) in enumerate(PRINTED[sheet]):
        assert name in source.loc[row, "source"]
        for column, value in printed.items():
            assert source.loc[row, column] == str(value), (name, column)
    capsys.readouterr()
    table = score(tmp_path, "--items", str(WORKSHEETS[sheet]))
    err = capsys.readouterr().err
    # a score the sheet does not print (an empty cell) is not one that differs
    assert table["differs"].tolist() == [""] * len(source), table["differs"].tolist()
    assert "differ" not in err, err
    assert table["source"].tolist() == source["source"].tolist()
    for column in items:
        assert table[column].tolist() == source[column].tolist(), column
    for column in scores:  # the sheet's own, kept beside the tables' where printed
        assert table[f"given_{column}"].tolist() == source[column].tolist(), column
        printed = source[column] != ""
        assert printed.any(), column
        assert table.loc[printed, column].tolist() == source.loc[printed, column].tolist(), \
            column


def test_the_example_worksheets_hold_every_item_of_their_sheet():
    reba = read(WORKSHEETS["reba"])
    assert {"reba_trunk", "reba_neck", "reba_legs", "reba_load", "reba_upper_arm",
            "reba_lower_arm", "reba_wrist", "reba_coupling", "reba_activity"} <= set(reba)
    rula = read(WORKSHEETS["rula"])
    assert {"rula_upper_arm", "rula_lower_arm", "rula_wrist", "rula_wrist_twist",
            "rula_arm_muscle_use", "rula_arm_force", "rula_neck", "rula_trunk", "rula_legs",
            "rula_neck_trunk_legs_muscle_use", "rula_neck_trunk_legs_force"} <= set(rula)
    # the published rows' items, as printed
    assert reba.loc[0, ["reba_trunk", "reba_neck", "reba_legs", "reba_load", "reba_upper_arm",
                        "reba_lower_arm", "reba_wrist", "reba_coupling",
                        "reba_activity"]].tolist() == list("212221100")
    assert reba.loc[1, ["reba_trunk", "reba_neck", "reba_legs", "reba_load", "reba_upper_arm",
                        "reba_lower_arm", "reba_wrist", "reba_coupling",
                        "reba_activity"]].tolist() == list("222012300")
    assert rula.loc[0, ["rula_upper_arm", "rula_lower_arm", "rula_wrist", "rula_wrist_twist",
                        "rula_arm_muscle_use", "rula_arm_force", "rula_neck", "rula_trunk",
                        "rula_legs", "rula_neck_trunk_legs_muscle_use",
                        "rula_neck_trunk_legs_force"]].tolist() == list("43311034210")


REBA_SHEET = {"reba_trunk": 2, "reba_neck": 1, "reba_legs": 2, "reba_load": 2,
              "reba_upper_arm": 2, "reba_lower_arm": 1, "reba_wrist": 1, "reba_coupling": 0,
              "reba_activity": 0}
"""Ejemplo 1 of the REBA handout: Table A 3 + load 2, Table B 1, Table C (5, 1) 4."""


def test_a_sheet_whose_own_score_disagrees_with_the_tables_is_flagged(tmp_path, capsys):
    path = tmp_path / "sheet.csv"
    rows = [{**REBA_SHEET, "reba_score_a": 5, "reba": 4},
            {**REBA_SHEET, "reba_score_a": 5, "reba": 6},  # the rater's slip
            {**REBA_SHEET, "reba_trunk": 3, "reba_score_a": 6, "reba": 6}]
    pd.DataFrame(rows).to_csv(path, index=False)
    capsys.readouterr()
    table = score(tmp_path, "--items", str(path))
    err = capsys.readouterr().err
    assert table["differs"].tolist() == ["", "reba", ""]
    assert table["given_reba"].tolist() == ["4", "6", "6"]
    assert table["reba"].tolist() == ["4", "4", "6"]
    assert table["reba_score_a"].tolist() == ["5", "5", "6"]
    assert err.count("\n") == 1, err
    assert "; the file's own scores differ from the tables in rows 2 -> " in err, err


# 4. Malformed inputs: one line, exit 2, nothing written ----------------------------------------

def changed(tmp_path: Path, example: str, change) -> Path:
    """A copy of an example CSV, its cells as text, with ``change`` made to it."""
    table = pd.read_csv(KEYPOINTS / example, dtype=str)
    change(table)
    path = tmp_path / example
    table.to_csv(path, index=False)
    return path


def h36m_wide(tmp_path: Path, change) -> Path:
    return changed(tmp_path, "h36m17.csv", change)


def set_cell(row: int, column: str, value: str):
    def change(table):
        table.loc[row, column] = value
    return change


def coco_long(tmp_path: Path, change) -> Path:
    return changed(tmp_path, "coco17_long.csv", change)


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def npy(tmp_path: Path, array: np.ndarray) -> Path:
    path = tmp_path / "points.npy"
    np.save(path, array)
    return path


def bvh(tmp_path: Path, change) -> Path:
    return write(tmp_path, "twin_changed.bvh", change((KEYPOINTS / "twin.bvh").read_text()))


def longer_last_row(text: str) -> str:
    lines = text.rstrip("\n").split("\n")
    return "\n".join([*lines[:-1], lines[-1] + " 0.0"]) + "\n"


def items(tmp_path: Path, **change) -> Path:
    path = tmp_path / "items.csv"
    sheet = {k: v for k, v in {**REBA_SHEET, **change}.items() if v is not None}
    pd.DataFrame([sheet]).to_csv(path, index=False)
    return path


BVH_LINES = len((KEYPOINTS / "twin.bvh").read_text().splitlines())
"""The example BVH file's last line: its sixth frame's row."""


def wide(path: Path) -> list[str]:
    return ["--keypoints", str(path), "--format", "h36m17"]


BAD = {  # case -> (tmp_path -> argv, what the line says; {file}: the file as typed)
    "unknown format": (lambda t: [*example("h36m17")[:3], "h99"],
                       "--format h99: not one of h36m17, coco17, mediapipe33, zed34, smpl24, "
                       "bvh"),
    "keypoints without format": (lambda t: example("h36m17")[:2],
                                 "--keypoints needs --format (h36m17, coco17, mediapipe33, "
                                 "zed34, smpl24 or bvh)"),
    "format with input": (lambda t: ["--input", str(POSTURES), "--format", "h36m17"],
                          "--format cannot be used with --input (only with --keypoints)"),
    "draws with input": (lambda t: ["--input", str(POSTURES), "--draws", "10"],
                         "--draws cannot be used with --input (only with --keypoints)"),
    "load with items": (lambda t: ["--items", str(WORKSHEETS["reba"]), "--load-kg", "3"],
                        "--load-kg cannot be used with --items (only with --keypoints)"),
    "wrong joint count": (lambda t: wide(npy(t, np.zeros((2, 16, 3)))),
                          "{file}: every frame has 16 joints; format h36m17 has 17 (the "
                          "array's shape is (2, 16, 3); expected (frames, 17, 3))"),
    "wrong array shape": (lambda t: wide(npy(t, np.zeros((2, 17, 2)))),
                          "{file} holds an array of shape (2, 17, 2) (expected (frames, 17, "
                          "3), or (17, 3) for one frame, for format h36m17)"),
    "missing joint column": (lambda t: wide(h36m_wide(t, lambda f: f.pop("left_elbow_y"))),
                             "{file} has no column 'left_elbow_y' (1 of format h36m17's 51 "
                             "columns are absent"),
    "unknown joint": (lambda t: ["--keypoints", str(coco_long(t, set_cell(5, "joint",
                                                                          "left_tail"))),
                                 "--format", "coco17"],
                      "{file}: row 6, column 'joint': 'left_tail' is not a joint of format "
                      "coco17 (use its joint names, e.g. nose, or indices 0-16)"),
    "joint index too high": (lambda t: ["--keypoints", str(coco_long(t, set_cell(3, "joint",
                                                                                 "17"))),
                                        "--format", "coco17"],
                             "{file}: frame 1 has joint index 17 (so at least 18 joints); "
                             "format coco17 has 17"),
    "non-numeric cell": (lambda t: wide(h36m_wide(t, set_cell(1, "thorax_x", "abc"))),
                         "{file}: row 2, column 'thorax_x': 'abc' is not a number (expected a "
                         "coordinate, or an empty cell for a missing point)"),
    "repeated frame": (lambda t: wide(h36m_wide(t, set_cell(3, "frame", "2"))),
                       "{file}: frame 2 is in rows 2 and 4 (expected one row per frame)"),
    "missing point": (lambda t: wide(h36m_wide(t, set_cell(2, "left_wrist_z", "nan"))),
                      "{file}: frame 3, joint 'left_wrist' is missing (NaN or an empty cell; 1 "
                      "of 6 frames miss points): --missing unseen scores such frames"),
    "infinite point": (lambda t: wide(h36m_wide(t, set_cell(4, "head_y", "inf"))),
                       "{file}: frame 5, joint 'head' has an infinite coordinate"),
    "40 m tall": (lambda t: ["--keypoints", str(npy(t, 25 * np.load(KEYPOINTS / "zed34.npz")[
        "keypoints"])), "--format", "zed34", "--units", "m"],
                  "{file}: the body is 41.3 m tall read as --units m (the median extent of its "
                  "points along the up axis z): expected 0.3-3 m; is the up axis right (--up), "
                  "and what is the file's unit? A 1.7 m body would make one unit 0.0412 m "
                  "(--units 0.0412; m, cm and mm are 1, 0.01 and 0.001)"),
    "bvh in cm read as m": (lambda t: [*example("bvh")[:4], "--units", "m"],
                            "{file}: the body is 174 m tall read as --units m"),
    "legs of no unit": (lambda t: ["--keypoints", str(npy(t, 4 * np.load(KEYPOINTS / "zed34.npz")[
        "keypoints"])), "--format", "zed34"],
                        "{file}: its unit cannot be told: its legs are"),
    "units not a unit": (lambda t: [*example("h36m17"), "--units", "inch"],
                         "--units inch: not a unit (expected m, cm, mm, or the metres one unit "
                         "of the file is, a number above 0)"),
    "bvh without an elbow": (lambda t: ["--keypoints", str(bvh(t, lambda s: s.replace(
        "LeftForeArm", "LeftLowerArm"))), "--format", "bvh", "--units", "cm"],
                             "{file}: no joint for the left elbow (looked for LeftForeArm: "
                             "the Mixamo rig's name for it, whose names the file's fit best; "
                             "--joint-map left_elbow=JOINT names it)"),
    "bvh frame row too long": (lambda t: ["--keypoints", str(bvh(t, longer_last_row)),
                                          "--format", "bvh", "--units", "cm"],
                               f"{{file}}: line {BVH_LINES}: frame 6 has 82 values; the "
                               "HIERARCHY has 81 channels"),
    "bvh that is not one": (lambda t: ["--keypoints", str(write(t, "x.bvh", "MOTION\n")),
                                       "--format", "bvh"],
                            "{file} is not a BVH file: it does not start with HIERARCHY"),
    "unknown extension": (lambda t: wide(write(t, "points.txt", "1,2,3\n")),
                          "{file} has extension '.txt': a keypoint file is .csv, .npy, .npz, "
                          ".json"),
    "json not a list of frames": (lambda t: ["--keypoints", str(write(t, "mp.json", "42\n")),
                                             "--format", "mediapipe33"],
                                  "{file} holds a number: expected a list of frames (each a "
                                  "list of MediaPipe world landmarks"),
    "json frame without landmarks": (lambda t: ["--keypoints", str(write(
        t, "mp.json", json.dumps({"frames": [1, 2]}))), "--format", "mediapipe33"],
                                     "{file}: frame 1 is an object without "
                                     "pose_world_landmarks, worldLandmarks, world_landmarks "
                                     "(its keys: frames)"),
    "json wrong landmark count": (lambda t: ["--keypoints", str(write(
        t, "mp.json", json.dumps([[{"x": 0, "y": 0, "z": 0}] * 17]))), "--format",
        "mediapipe33"],
                                  "{file}: frame 1 has 17 joints; format mediapipe33 has 33"),
    "frames beyond the file": (lambda t: [*example("h36m17"), "--frames", "50:60"],
                               "--frames 50:60: {file} has frames 1-6"),
    "frames backwards": (lambda t: [*example("h36m17"), "--frames", "3:2"],
                         "--frames 3:2: expected frame numbers >= 1 with A <= B"),
    "assume unknown column": (lambda t: [*example("h36m17"), "--assume", "nosuch=1"],
                              "--assume nosuch=1: expected COLUMN=VALUE with a Posture column"),
    "assume a column misspelt": (lambda t: [*example("h36m17"), "--assume", "trunk_flex=10"],
                                 "--assume trunk_flex=10: expected COLUMN=VALUE with a Posture "
                                 "column (docs/architecture.md, \"File contracts\"); did you "
                                 "mean trunk_flexion"),
    "assume a measured column": (lambda t: [*example("h36m17"), "--assume",
                                            "left_knee_flexion=90"],
                                 "--assume left_knee_flexion=90: left_knee_flexion is measured "
                                 "in 6 of 6 frames: an assumed value fills only a column the "
                                 "capture cannot see"),
    "assume impossible value": (lambda t: [*example("h36m17"), "--assume",
                                           "left_wrist_flexion=500"],
                                "--assume left_wrist_flexion=500: '500' is not allowed for "
                                "left_wrist_flexion (expected a finite angle in degrees"),
    "load too heavy": (lambda t: [*example("h36m17"), "--load-kg", "30"],
                       "--load-kg 30: outside 0-25 kg"),
    "load twice": (lambda t: [*example("h36m17"), "--load-kg", "5", "--assume", "load_kg=5"],
                   "--load-kg and --assume load_kg=... both given: give one"),
    "item out of range": (lambda t: ["--items", str(items(t, reba_trunk=6))],
                          "{file}: row 1, column 'reba_trunk': 6 is not allowed (expected an "
                          "integer 1-5)"),
    "item missing": (lambda t: ["--items", str(items(t, reba_neck=None))],
                     "{file}: missing REBA item column 'reba_neck': a REBA sheet needs every "
                     "item"),
    "no item columns": (lambda t: ["--items", str(write(t, "items.csv", "trunk,neck\n2,1\n"))],
                        "{file}: no worksheet item columns: expected REBA's (reba_trunk, "),
    "non-numeric item": (lambda t: ["--items", str(items(t, reba_load="two"))],
                         "{file}: row 1, column 'reba_load': 'two' is not a number (expected "
                         "an item score)"),
    "empty item": (lambda t: ["--items", str(items(t, reba_activity=""))],
                   "{file}: row 1, column 'reba_activity': an empty cell is not a number"),
    "arm item both ways": (lambda t: ["--items", str(items(t, reba_left_wrist=1))],
                           "{file}: column 'reba_wrist' and column 'reba_left_wrist' both "
                           "given"),
}


@pytest.mark.parametrize("case", list(BAD))
def test_a_malformed_input_is_one_line_and_writes_nothing(case, tmp_path, capsys):
    make, message = BAD[case]
    argv = make(tmp_path)
    source = argv[argv.index(next(f for f in ("--keypoints", "--items", "--input")
                                  if f in argv)) + 1]
    out = tmp_path / "scores.csv"
    err = refused([*argv, "--output", str(out)], tmp_path, capsys)
    expected = message.format(file=source)
    assert err.startswith(ERROR + expected), f"\n{err}\n{ERROR + expected}"
    assert not out.exists()


@pytest.mark.parametrize("output", ["default", "new folder"])
def test_a_refused_input_leaves_no_folder_behind(output, tmp_path, capsys, monkeypatch):
    """The output's folder (a new runs/score/<timestamp>/, or --output's) is made only once
    the input has been read and scored (cli/options.py, ``writable``)."""
    monkeypatch.chdir(tmp_path)
    source = npy(tmp_path, np.zeros((2, 16, 3)))
    flags = [] if output == "default" else ["--output", str(tmp_path / "new" / "scores.csv")]
    err = refused([*wide(source), *flags], tmp_path, capsys)
    assert "every frame has 16 joints" in err


def test_there_are_enough_malformed_cases():
    assert len(BAD) >= 15


def test_a_missing_point_declared_unseen_scores_its_frame_with_those_columns_open(
        tmp_path, capsys):
    path = h36m_wide(tmp_path, set_cell(2, "left_wrist_z", "nan"))
    whole = score(tmp_path, *example("h36m17"), name="whole.csv")
    capsys.readouterr()
    table = score(tmp_path, *wide(path), "--missing", "unseen", name="gap.csv")
    summary = capsys.readouterr().err
    assert "1 with missing points" in summary
    # The summary names what was not measured: always (H36M-17 has no hand points), and in
    # the one frame of six that misses its left wrist.
    assert "; unseen in every frame: neck_twist, left_wrist_flexion, " in summary
    assert "; unseen in some frames: " in summary and "left_elbow_flexion (17 %)" in summary
    others = [0, 1, 3, 4, 5]
    pd.testing.assert_frame_equal(table.iloc[others], whole.iloc[others])
    before, after = (set(t.loc[2, "unseen"].split(";")) for t in (whole, table))
    assert before < after and {"left_elbow_flexion", "hands_above_neck"} <= after - before
    assert table.loc[2, "left_elbow_flexion"] == "" != whole.loc[2, "left_elbow_flexion"]
    for s in SCORES:  # the frame's intervals only widen
        assert int(table.loc[2, f"{s}_lo"]) <= int(whole.loc[2, f"{s}_lo"])
        assert int(table.loc[2, f"{s}_hi"]) >= int(whole.loc[2, f"{s}_hi"])


# 5. personalise with captured frames as the answers --------------------------------------------

SESSION = ["personalise", "--oracle", "ask", "--stature", "1.756", "--sex", "male",
           "--trials", "2", "--boundary", "-0.1,0.1,1.0,1.2,0.35,0.5", "--step", "0.05"]


def frame_answer(name: str, number: int) -> list[str]:
    """Frame ``number`` of format ``name``'s example file as an answer's numbers [m], in the
    format's joint order and frame (its default up axis)."""
    from ergohandover.capture import keypoint_format
    from ergohandover.capture.readers import read_keypoints

    kp = read_keypoints(KEYPOINTS / EXAMPLES[name][0], keypoint_format(name))
    points = kp.points[list(kp.frames).index(number)]
    assert points.shape == (len(kp.fmt.joints), 3) and np.isfinite(points).all()
    return [repr(float(v)) for v in points.ravel()]


def session(monkeypatch, capsys, answers: list[str], output: Path, *flags: str,
            answer_format: str = "keypoints:zed34"):
    monkeypatch.setattr(sys, "stdin", io.StringIO("".join(f"{a}\n" for a in answers)))
    capsys.readouterr()
    code = main([*SESSION, "--answer-format", answer_format, *flags, "--output", str(output)])
    out, err = capsys.readouterr()
    return code, out, err


def scored_frame(tmp_path: Path, name: str, number: int) -> pd.Series:
    """``score --keypoints``'s row of frame ``number`` of format ``name``'s example, with the
    box a session's worker takes (the default task's 6 kg: a frame answer is scored with it)."""
    table = score(tmp_path, *example(name), "--load-kg", "6", name=f"{name}.csv")
    return table[table["frame"] == str(number)].iloc[0]


def middle(row: pd.Series, objective: str) -> float:
    """The score, or the middle of its interval where it is open."""
    if row[objective]:
        return float(row[objective])
    return (float(row[f"{objective}_lo"]) + float(row[f"{objective}_hi"])) / 2


def history(output: Path) -> list[dict]:
    return json.loads((output / "state.json").read_text())["history"]


def test_a_captured_frame_answers_with_the_score_the_score_command_gives(
        monkeypatch, capsys, tmp_path):
    frame = ",".join(frame_answer("zed34", 1))
    assert frame.count(",") == 101
    code, out, err = session(monkeypatch, capsys, [frame, "x"], tmp_path / "s")
    assert code == 0, err
    assert "refused" not in err
    row = scored_frame(tmp_path, "zed34", 1)
    assert row["paper_postural"] == "4"  # exact, and the twin's own at the first location
    recorded = history(tmp_path / "s")
    assert [h["trial"] for h in recorded] == [1, 2]
    assert recorded[0]["score"] == 4.0 and recorded[0]["answer"] == frame
    assert recorded[1]["score"] is None and recorded[1]["answer"] == "x"
    trials = pd.read_csv(tmp_path / "s" / "trials.csv")
    assert trials["feasible"].tolist() == [1, 0] and trials["score"].iloc[0] == 4.0
    assert "paper_postural 4, observed at trial 1; 2 of 2 trials used" in out
    assert "a zed34 frame, or 'x' if the worker cannot take it there" in out


@pytest.mark.parametrize(("name", "number", "objective", "expected"), [
    ("zed34", 2, "reba", 4.5),  # the wrists and the shoulder girdle unseen: REBA 3-6
    ("h36m17", 1, "paper_postural", 4.5),  # no wrists: 4-5
])
def test_an_open_objective_is_answered_with_the_middle_of_its_interval(
        monkeypatch, capsys, tmp_path, name, number, objective, expected):
    code, _, err = session(monkeypatch, capsys, [",".join(frame_answer(name, number)), "x"],
                           tmp_path / "s", "--objective", objective,
                           answer_format=f"keypoints:{name}")
    assert code == 0, err
    row = scored_frame(tmp_path, name, number)
    assert row[objective] == "", f"frame {number}'s {objective} is no longer open"
    assert middle(row, objective) == expected
    assert history(tmp_path / "s")[0]["score"] == expected


def test_a_frame_of_the_wrong_length_is_refused_and_asked_again(monkeypatch, capsys, tmp_path):
    frame = frame_answer("zed34", 1)
    code, out, err = session(monkeypatch, capsys,
                             [",".join(frame[:-1]), ",".join(frame), "x"], tmp_path / "s")
    assert code == 0, err
    refusals = [line for line in err.splitlines() if line.startswith("refused:")]
    assert refusals == ["refused: a frame of 101 values: expected a zed34 frame (102 numbers: "
                        "x, y, z of each of its 34 joints in metres), or x if the worker cannot "
                        "take the box there"]
    assert out.split("trial 2/2")[0].count("a zed34 frame, or 'x'") == 2  # trial 1 asked twice
    expected = middle(scored_frame(tmp_path, "zed34", 1), "paper_postural")
    assert [h["score"] for h in history(tmp_path / "s")] == [expected, None]


@pytest.mark.parametrize(("flags", "message"), [
    (["--objective", "reba_ab"], "--answer-format keypoints:zed34: a captured frame gives reba, "
     "rula, paper_postural, not objective reba_ab"),
    (["--answer-format", "keypoints:zed99"], "--answer-format keypoints:zed99: format 'zed99' "
     "is not known"),
    (["--answer-format", "keypoints:zed34:q"], "--answer-format keypoints:zed34:q: up axis 'q' "
     "is not allowed"),
])
def test_a_captured_answer_format_that_cannot_be_is_refused(flags, message, tmp_path, capsys,
                                                           monkeypatch):
    monkeypatch.chdir(tmp_path)
    argv = [*SESSION[1:], "--answer-format", "keypoints:zed34", *flags]
    err = refused([*argv, "--output", str(tmp_path / "s")], tmp_path, capsys,
                  command="personalise")
    assert err.startswith(f"ergohandover personalise: error: {message}"), err


def test_the_twin_takes_no_answer_format(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    err = refused(["--oracle", "twin", "--answer-format", "keypoints:zed34", "--output",
                   str(tmp_path / "s")], tmp_path, capsys, command="personalise")
    assert err == ("ergohandover personalise: error: --answer-format cannot be used with "
                   "--oracle twin (only with --oracle ask or file)")
