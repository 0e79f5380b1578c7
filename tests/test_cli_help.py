"""The command line tells the truth about itself.

Every default and number its ``--help`` states is the code's (a flag that several commands take
has one default, the study's); every file a help text names exists; every bad input is one line
on stderr naming the flag as the user typed it (with the unit where the value has one; a format
problem called a format problem; the file's name for a file), exit code 2 and no output; and
every output folder is created when it is missing."""

from __future__ import annotations

import contextlib
import dataclasses
import inspect
import json
import re
import shlex
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from synthetic import bowl_landscape

from ergohandover.cli import build_parser, main
from ergohandover.cli.options import evaluator_from_args, grid_from_args
from ergohandover.cli.values import BadValue
from ergohandover.envs.handover_env import EPISODE_STEPS, HandoverEnv
from ergohandover.ergonomics import ScoringSettings
from ergohandover.landscape.cache import landscape_key
from ergohandover.scene.robot import RobotSpec
from ergohandover.search.qlearning import QLearningConfig
from ergohandover.study.config import StudyConfig
from ergohandover.study.learning.config import Target
from ergohandover.study.shared import grid_of
from ergohandover.twin.anthropometry import MASS_RANGE_KG, STATURE_RANGE_M
from ergohandover.twin.task import TaskSpec

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "postures.csv"
PARSERS = build_parser().commands
STUDY = StudyConfig()
TARGET = {f.name: f.default for f in dataclasses.fields(Target)}
STUDY_WORKER = inspect.signature(StudyConfig.evaluator).parameters["worker"].default
STUDY_EVALUATOR = STUDY.evaluator()
SMALL = "-0.1,0.1,1.0,1.2,0.35,0.5"  # 5 x 5 x 4 points every 5 cm

STUDY_DEFAULTS = {
    "boundary": STUDY.landscape.boundary, "step": STUDY.landscape.step,
    "gaze": STUDY.landscape.gaze, "percentile": STUDY_WORKER, "objective": TARGET["objective"],
    "episode_end": STUDY.learning.episode_end, "seed": STUDY.baselines.seed,
    "solver": STUDY_EVALUATOR.solver, "trunk_reference": STUDY_EVALUATOR.trunk_reference}
"""Each shared flag's default as the study has it (read here from the study, not the CLI)."""
MODEL = {"evaluate", "robustness", "sweep", "train", "baseline", "view", "report"}
SHARED_BY = {"boundary": {"sweep", "train", "baseline", "view", "personalise"},
             "step": {"sweep", "train", "baseline", "view", "personalise"},
             "gaze": MODEL | {"personalise"}, "percentile": MODEL | {"personalise", "score"},
             "trunk_reference": MODEL | {"personalise"},
             "solver": {"evaluate", "robustness", "sweep", "personalise", "report"},
             "seed": {"train", "baseline", "robustness", "personalise", "score"},
             "objective": {"train", "personalise"}, "episode_end": {"train"}}
COMMAND_DEFAULTS = {("personalise", "boundary"): STUDY.population.boundary,
                    ("personalise", "step"): STUDY.population.step}
"""Where a command's default is another part of the study's: personalising searches the grid the
population study found every worker's optimum on."""


def action(parser, dest: str):
    return next((a for a in parser._actions if a.dest == dest), None)


def shown(value) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def flat(text: str) -> str:
    """Without whitespace: the help's wrapping breaks lines at spaces and hyphens."""
    return "".join(text.split())


# (a, b) The help states the code's defaults; shared flags have the study's ------------------

def test_the_study_names_one_worker():
    assert TARGET["worker"] == STUDY_WORKER == STUDY.population.reference


@pytest.mark.parametrize("dest", list(SHARED_BY))
def test_a_shared_flag_has_the_studys_default_in_every_command_and_its_help(dest):
    expected = STUDY_DEFAULTS[dest]
    having = {name for name, parser in PARSERS.items() if action(parser, dest) is not None}
    assert having == SHARED_BY[dest]
    for name in having:
        flag, default = action(PARSERS[name], dest), COMMAND_DEFAULTS.get((name, dest), expected)
        assert flag.default == default, (name, dest)
        assert f"(default: {shown(default)}" in flag.help, (name, flag.help)
        assert flat(flag.help) in flat(PARSERS[name].format_help())


@pytest.mark.parametrize("command", sorted(MODEL))
def test_without_flags_a_command_models_the_studys_worker_task_and_grid(command):
    required = {"evaluate": ["--points", "p.csv"], "robustness": ["--points", "-"],
                "train": ["--agent", "random-draws"], "report": ["--location", "0,1,0.4"]}
    args = build_parser().parse_args([command, *required.get(command, [])])
    evaluator = evaluator_from_args(args)
    assert evaluator == STUDY_EVALUATOR
    if command in ("evaluate", "robustness", "report"):  # given locations, no grid
        return
    grid = grid_from_args(evaluator, args.boundary, args.step)
    assert grid == grid_of(STUDY_EVALUATOR, STUDY.landscape.boundary, STUDY.landscape.step)
    # So the landscape a command sweeps by default is the study's, the one it recorded.
    manifest = json.loads((ROOT / "results" / "landscape" / "manifest.json").read_text())
    assert landscape_key(evaluator, grid) == manifest["landscape_key"]


def ranges_in(text: str) -> list[tuple[float, float]]:
    return [(float(a), float(b)) for a, b in re.findall(r"(?<![\w.])(\d+(?:\.\d+)?)-(\d+(?:\.\d+)?)"
                                                         r"(?![\w.])", text)]


MODEL_FLAGS = [("score", ScoringSettings, {}), ("evaluate", TaskSpec, {"gaze": "gaze"}),
               ("baseline", RobotSpec, {"distance": "robot_distance"})]


@pytest.mark.parametrize(("command", "cls"), [(c, cls) for c, cls, _ in MODEL_FLAGS])
def test_a_model_flag_states_its_fields_default_and_range(command, cls):
    checked = 0
    for field in dataclasses.fields(cls):
        flag = action(PARSERS[command], field.name)
        if flag is None:  # the robot's flags: only the settings a user moves the robot with
            continue
        checked += 1
        default = STUDY_DEFAULTS.get(field.name, field.default)
        assert flag.default == default and f"(default: {default})" in flag.help
        meta = field.metadata
        if meta.get("choices"):
            assert "|".join(meta["choices"]) == flag.metavar
            continue
        stated = ranges_in(flag.help)
        assert stated, f"{flag.help!r} states no range"
        assert all(r == (meta["lo"], meta["hi"]) for r in stated), (field.name, flag.help)
    assert checked >= 4


def test_the_body_flags_state_the_models_ranges():
    parser = PARSERS["evaluate"]
    for dest, (lo, hi) in (("stature", STATURE_RANGE_M), ("mass", MASS_RANGE_KG)):
        assert ranges_in(action(parser, dest).help) == [(lo, hi)]
    assert f"default: --percentile {STUDY_WORKER}" in parser.format_help()


def test_the_target_help_states_the_papers_target_and_the_twins_computed_minimum():
    paper = inspect.signature(HandoverEnv).parameters["target"].default
    stats = pd.read_csv(ROOT / "results" / "landscape" / "stats.csv").set_index("score")
    minimum = stats.loc[TARGET["objective"], "min"]
    flag = action(PARSERS["train"], "target")
    assert flag.default == paper
    assert f"(default: {paper:g}, the paper's target" in flag.help
    assert (f"the twin's own minimum of {TARGET['objective']} on the default grid is "
            f"{minimum:g}") in flag.help
    assert re.findall(r"minimum[^;)]* is (\d+)", flag.help) == [f"{minimum:g}"]


def test_the_train_help_states_the_learners_numbers():
    parser = PARSERS["train"]
    q = QLearningConfig()
    assert action(parser, "episode_steps").default == EPISODE_STEPS
    assert f"(default: {EPISODE_STEPS})" in action(parser, "episode_steps").help
    temperature = action(parser, "temperature").help
    assert f"fixed {q.tau:g}" in temperature
    assert f"bounded {q.tau_bounds[0]:g}-{q.tau_bounds[1]:g}" in temperature
    assert f"alpha {q.alpha:g}, gamma {q.gamma:g}" in parser.description
    paper = json.loads((ROOT / "experiments" / "configs" / "paper.json").read_text())
    caps = " and ".join(f"{c:g}" for c in paper["learning"]["wall_caps_s"])
    assert f"the paper's: {caps}" in action(parser, "time_cap").help


def test_every_file_a_help_text_names_exists():
    named, helps = set(), [build_parser(), *PARSERS.values()]
    for token in re.findall(r"[\w./<>-]+", "\n".join(p.format_help() for p in helps)):
        token = token.rstrip(".,;:")
        if token.startswith("-") or "<" in token or token.startswith("runs/"):
            continue  # a flag, or where a command writes
        file = re.fullmatch(r"[\w./-]*\w\.(md|csv|json|py|npz|png|urdf)", token)
        if (file and ("/" in token or token.endswith(".md"))) or re.fullmatch(r"\w+/", token):
            named.add(token)
    assert {"docs/architecture.md", "docs/learning.md", "results/landscape/stats.csv"} <= named
    missing = sorted(p for p in named if not (ROOT / p).exists())
    assert not missing, f"help texts name files the repository does not have: {missing}"


# (c) Bad inputs: one line naming the flag as typed, exit code 2, nothing written --------------

def rule(lo: float, hi: float, unit: str) -> str:
    return f"{lo:g}-{hi:g} {unit}"


def field_rule(cls, name: str) -> str:
    meta = next(f for f in dataclasses.fields(cls) if f.name == name).metadata
    unit = meta["unit"] or re.search(r"\[(\w+)\]", meta["help"])[1]
    return rule(meta["lo"], meta["hi"], unit)


OUTPUT = {"score": "file", "evaluate": "file", "robustness": "file", "baseline": "file",
          "sweep": "dir", "train": "dir", "landscape-stats": "dir", "view": "file",
          "personalise": "dir", "report": "dir"}
OUTPUT_FLAG = {"view": "--export"}  # the viewer serves; what it writes is a recording
BAD_FLAGS = [
    # A location in centimetres, given as metres: refused, not reported 100 m up.
    (["report", "--location", "0,100,41"],
     "--location 0,100,41: beyond any reach (3 m on an axis; locations are in metres, worker "
     "frame): centimetres? then 0,1,0.41"),
    (["evaluate", "--points", "POINTS", "--stature", "-1.7"],
     f"--stature -1.7: outside {rule(*STATURE_RANGE_M, 'm')}"),
    (["evaluate", "--points", "POINTS", "--mass", "20"],
     f"--mass 20: outside {rule(*MASS_RANGE_KG, 'kg')}"),
    # An abbreviation argparse accepts is named as typed; the unit is the field's.
    (["evaluate", "--points", "POINTS", "--box-mass", "40"],
     f"--box-mass 40: outside {field_rule(TaskSpec, 'box_mass_kg')}"),
    (["baseline", "--robot-height", "5"],
     f"--robot-height 5: outside {field_rule(RobotSpec, 'mount_height')}"),
    (["score", "--input", "POSTURES", "--twist-from-deg", "45"],
     f"--twist-from-deg 45: outside {field_rule(ScoringSettings, 'twist_from_deg')}"),
    (["sweep", "--step", "-1"], "--step -1: must be > 0 m"),
    (["robustness", "--postures", "POSTURES", "--angle-sd", "2", "-1"],
     "--angle-sd -1: outside 0-45 deg"),
    (["robustness", "--postures", "POSTURES", "--draws", "0"], "--draws 0: must be >= 1"),
    (["robustness", "--postures", "POSTURES", "--stature", "1.8"],
     "--stature cannot be used with --postures"),
    (["train", "--agent", "random-draws", "--steps", "1e3"], "--steps 1e3: not a whole number"),
    (["train", "--agent", "random-draws", "--time-cap", "2 min"],
     "--time-cap '2 min': not a number (expected > 0 s)"),
    (["train", "--agent", "random-draws", "--steps", "5", "--target", "nan"],
     "--target nan: not a finite number"),
    (["evaluate", "--points", "POINTS", "--coupling", "1.5"], "--coupling 1.5: not a whole number"),
    (["evaluate", "--points", "POINTS", "--gaze", "maybe"], "--gaze maybe: not one of on, off"),
    (["sweep", "--bound", "nowhere"], "--bound nowhere: not body, paper-code or six numbers"),
    (["baseline", "--start", "1,2"], "--start 1,2: not three finite numbers X,Y,Z in metres"),
    (["train", "--agent", "random-draws", "--steps"], "--steps: expected one argument"),
    (["train", "--agent", "random-draws", "--steps", "5", "--temperature", "adaptive"],
     "--temperature adaptive cannot be used with --agent random-draws"),
    # Checked by the model after parsing (it takes two flags): both named as flags.
    (["evaluate", "--points", "POINTS", "--handle-span", "0.3"],
     "--handle-span 0.3: outside the valid range: at least --box-width 0.36"),
    (["sweep", "--boundary", SMALL, "--step", "0.5"],
     "--step 0.5: larger than the boundary along x"),
]


def run_bad(argv: list[str], tmp_path: Path, capsys) -> str:
    """Run ``argv`` with an output in a folder that must stay absent; the one error line."""
    points = tmp_path / "points.csv"
    points.write_text("x,y,z\n0,1.1,0.4\n")
    argv = [str(points) if a == "POINTS" else str(EXAMPLE) if a == "POSTURES" else a
            for a in argv]
    out = tmp_path / "out" / ("result.csv" if OUTPUT[argv[0]] == "file" else "result")
    before = sorted(tmp_path.rglob("*"))
    capsys.readouterr()
    assert main([*argv, OUTPUT_FLAG.get(argv[0], "--output"), str(out)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert sorted(tmp_path.rglob("*")) == before, "a bad input left a file or folder behind"
    err = captured.err
    assert err.startswith(f"ergohandover {argv[0]}: error: ") and err.count("\n") == 1, err
    assert "Traceback" not in err and "_m =" not in err and "_kg =" not in err
    return err


@pytest.mark.parametrize(("argv", "message"), BAD_FLAGS)
def test_a_bad_flag_is_one_line_naming_it_as_typed(tmp_path, capsys, argv, message):
    assert message in run_bad(argv, tmp_path, capsys)


def numeric_flags() -> list[tuple[str, str, str]]:
    """(command, flag, 'whole' or 'number') of every flag whose value is a number."""
    out = []
    for name, parser in PARSERS.items():
        for flag in parser._actions:
            if not flag.option_strings or not callable(flag.type):
                continue
            try:
                flag.type("abc")
            except BadValue as exc:
                if exc.problem.startswith(("not a number", "not a whole number")):
                    kind = "whole" if exc.problem.startswith("not a whole") else "number"
                    out.append((name, flag.option_strings[0], kind))
    return out


NUMERIC = numeric_flags()


def test_every_kind_of_numeric_flag_is_found():
    found = {flag for _, flag, _ in NUMERIC}
    assert {"--steps", "--seed", "--workers", "--stature", "--box-mass-kg", "--coupling",
            "--robot-distance", "--twist-from-deg", "--time-cap", "--target", "--step"} <= found


@pytest.mark.parametrize(("command", "flag", "kind"), NUMERIC)
def test_a_number_that_is_not_one_is_a_format_error(tmp_path, capsys, command, flag, kind):
    err = run_bad([command, flag, "1,5"], tmp_path, capsys)
    assert f"{flag} 1,5: not a {'whole ' if kind == 'whole' else ''}number" in err
    if kind == "whole":
        err = run_bad([command, flag, "1e3"], tmp_path, capsys)
        assert f"{flag} 1e3: not a whole number (expected an integer" in err
    else:  # 1e3 is a number: at most out of range, never a format error
        with contextlib.suppress(BadValue):
            assert PARSERS[command]._option_string_actions[flag].type("1e3") == 1000.0
            return
        err = run_bad([command, flag, "1e3"], tmp_path, capsys)
        assert f"{flag} 1e3: outside" in err or f"{flag} 1e3: must be" in err


def binary_file(path: Path) -> Path:
    """A landscape-like .npz (binary, with zero bytes) under a CSV's name."""
    with path.open("wb") as handle:
        np.savez(handle, a=np.arange(10))
    return path


def written(content: str | bytes):
    def make(path: Path) -> Path:
        (path.write_bytes if isinstance(content, bytes) else path.write_text)(content)
        return path
    return make


def folder(path: Path) -> Path:
    path.mkdir()
    return path


def bad_coupling() -> str:
    frame = pd.read_csv(EXAMPLE, dtype=str)
    frame.loc[1, "coupling"] = "5"
    return frame.to_csv(index=False)


FILE_CASES = {
    "binary points": (["evaluate", "--points", "FILE"], binary_file,
                      "is a binary file, not a CSV text file"),
    "binary postures": (["score", "--input", "FILE"], binary_file,
                        "is a binary file, not a CSV text file"),
    "other encoding": (["evaluate", "--points", "FILE"],
                       written(b"x,y,z,note\n0,1.1,0.4,caf\xe9\n"),
                       "is not UTF-8 text (byte 0xe9"),
    "empty": (["score", "--input", "FILE"], written(""), "is empty"),
    "header only": (["evaluate", "--points", "FILE"], written("x,y,z\n"),
                    "has a header but no rows"),
    "wrong columns": (["evaluate", "--points", "FILE"], written("x,y\n0,1\n"),
                      "is missing required column 'z'"),
    "points in centimetres": (["evaluate", "--points", "FILE"],
                              written("x,y,z\n0,1,0.4\n0,100,41\n10,120,30\n"),
                              ": row 2: 0,100,41 is beyond any reach (3 m on an axis; locations "
                              "are in metres, worker frame): centimetres? then 0,1,0.41 (2 such "
                              "rows)"),
    "bad cell": (["evaluate", "--points", "FILE"], written("x,y,z\n0,1,abc\n"),
                 ": row 1, column 'z': 'abc' is not a number"),
    "bad posture": (["score", "--input", "FILE"], written(bad_coupling()),
                    ": row 2, column 'coupling': 5 is not allowed"),
    "missing": (["evaluate", "--points", "FILE"], lambda p: p, "does not exist"),
    "a folder": (["score", "--input", "FILE"], folder, "is a folder"),
    "a CSV as a landscape": (["train", "--agent", "random-draws", "--steps", "5", "--landscape",
                              "FILE"], written("x,y,z\n0,1,0.4\n"), "not a readable landscape"),
    "binary as a landscape": (["landscape-stats", "FILE"], binary_file,
                              "not a readable landscape"),
    "missing landscape": (["baseline", "--landscape", "FILE"], lambda p: p, "no such file"),
    "missing postures": (["robustness", "--postures", "FILE"], lambda p: p, "no such file"),
    "binary points for robustness": (["robustness", "--points", "FILE"], binary_file,
                                     "is a binary file, not a CSV text file"),
}


@pytest.mark.parametrize("case", list(FILE_CASES))
def test_a_bad_file_is_one_line_naming_it(tmp_path, capsys, case):
    argv, make, problem = FILE_CASES[case]
    path = make(tmp_path / "table.csv")
    err = run_bad([str(path) if a == "FILE" else a for a in argv], tmp_path, capsys)
    assert str(path) in err and problem in err, err
    if "--landscape" in argv:
        assert f"--landscape {shlex.quote(str(path))}: " in err


def test_a_utf16_file_reads_as_its_utf8_twin(tmp_path, capsys):
    # Spreadsheets save "Unicode text" as UTF-16 with a byte-order mark: read, not refused.
    text = EXAMPLE.read_text(encoding="utf-8")
    outputs = []
    for encoding in ("utf-8", "utf-16"):
        source = tmp_path / f"{encoding}.csv"
        source.write_text(text, encoding=encoding)
        assert main(["score", "--input", str(source), "--output",
                     str(tmp_path / f"{encoding}-scored.csv")]) == 0
        outputs.append((tmp_path / f"{encoding}-scored.csv").read_text())
    assert outputs[0] == outputs[1]
    assert (tmp_path / "utf-16.csv").read_bytes()[:2] in (b"\xff\xfe", b"\xfe\xff")


def test_a_file_in_the_way_of_an_output_is_refused_before_anything_runs(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("")
    for argv, out in ((["score", "--input", str(EXAMPLE)], blocker / "s.csv"),
                      (["sweep"], blocker), (["evaluate", "--points", str(EXAMPLE)], tmp_path)):
        assert main([*argv, OUTPUT_FLAG.get(argv[0], "--output"), str(out)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and f"--output {out}: " in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]


# (d) Every output folder is created when missing --------------------------------------------

def test_score_and_evaluate_create_their_output_folders(tmp_path):
    out = tmp_path / "new" / "deeper" / "scores.csv"
    assert main(["score", "--input", str(EXAMPLE), "--output", str(out)]) == 0
    assert len(pd.read_csv(out)) == len(pd.read_csv(EXAMPLE))
    points = tmp_path / "points.csv"
    points.write_text("x,y,z\n0,1.1,0.4\n")
    out, pictures = tmp_path / "a" / "b" / "evaluation.csv", tmp_path / "c" / "d"
    assert main(["evaluate", "--points", str(points), "--output", str(out), "--render",
                 str(pictures), "--workers", "1"]) == 0
    assert len(pd.read_csv(out)) == 1 and len(list(pictures.glob("*.png"))) == 1


@pytest.mark.slow
def test_sweep_stats_train_and_baseline_create_their_output_folders(tmp_path, capsys):
    grid = ["--boundary", SMALL, "--step", "0.05", "--workers", "1"]
    sweep = tmp_path / "s" / "t" / "sweep"
    assert main(["sweep", *grid, "--output", str(sweep)]) == 0
    landscape = json.loads((sweep / "manifest.json").read_text())["landscape"]
    stats = tmp_path / "u" / "v"
    assert main(["landscape-stats", landscape, "--output", str(stats)]) == 0
    assert (stats / "landscape_stats.csv").is_file()
    bowl = bowl_landscape().save(tmp_path / "bowl.npz")
    run = tmp_path / "w" / "x" / "run"
    assert main(["train", "--agent", "random-draws", "--steps", "50", "--landscape", str(bowl),
                 "--output", str(run)]) == 0
    assert (run / "trace.csv").is_file()
    out, paths = tmp_path / "y" / "z" / "baselines.csv", tmp_path / "p" / "q"
    assert main(["baseline", *grid, "--start", "0,1.1,0.6", "--output", str(out), "--paths",
                 str(paths)]) == 0
    assert len(pd.read_csv(out)) == 2 and out.with_suffix(".md").is_file()
    assert (out.parent / "manifest.json").is_file() and list(paths.glob("*.csv"))


def test_no_help_text_quotes_a_measured_speed():
    """Speeds belong to the benchmarks that measure them on the machine at hand, and to the
    README that quotes their committed runs: a help text that states one drifts from both."""
    measured = re.compile(r"\d+(\.\d+)?\s?(x|×) (as fast|faster)|about \d+(\.\d+)? ?%"
                          r"|\d+(\.\d+)? ?(ms|seconds|minutes)\b")
    for name, parser in build_parser().commands.items():
        found = measured.search(" ".join(parser.format_help().split()))
        assert found is None, (name, found and found.group(0))
