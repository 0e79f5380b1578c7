"""The study's typed configuration: the files parse to the defaults they claim, every bad key or
value is one line naming its key path (exit code 2 from the scripts, nothing written), and what
a part depends on is hashed from the typed form."""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys
from pathlib import Path

import pytest

from ergohandover.errors import ConfigError
from ergohandover.study.config import StudyConfig
from ergohandover.study.resume import part_hash

ROOT = Path(__file__).resolve().parents[1]
CONFIGS = ROOT / "experiments" / "configs"


def test_the_default_file_is_the_defaults_and_spelling_a_default_out_changes_nothing():
    default = StudyConfig.load(CONFIGS / "default.json")
    assert default == StudyConfig()
    spelled = StudyConfig.from_dict({"learning": {"runs": 100, "budgets": {
        "paper-2min": 37_800, "paper-5min": 94_500}}, "landscape": {"step": 0.003}})
    for part in ("landscape", "learning", "baselines", "population"):
        assert part_hash(spelled.part_inputs(part)) == part_hash(default.part_inputs(part))
    assert part_hash(StudyConfig.from_dict({"learning": {"runs": 101}}).part_inputs(
        "learning")) != part_hash(default.part_inputs("learning"))


def test_a_part_depends_on_its_section_the_landscape_and_what_it_reads():
    config = StudyConfig()
    assert set(config.part_inputs("landscape")) == {"landscape"}
    assert set(config.part_inputs("baselines")) == {"baselines", "landscape", "learning"}
    changed = StudyConfig.from_dict({"learning": {"runs": 3}})
    assert changed.part_inputs("population") == config.part_inputs("population")
    assert changed.part_inputs("baselines") != config.part_inputs("baselines")


def test_the_papers_protocol_runs_q_learning_and_dqn_at_its_wall_clock_caps():
    paper = StudyConfig.load(CONFIGS / "paper.json")
    assert paper.learning.agents == ("qlearning", "dqn")
    assert paper.learning.wall_caps_s == (120.0, 300.0) and not paper.learning.budgets
    assert paper.learning.dqn_targets == ("paper",) and paper.learning.runs == 10
    assert paper.learning.episode_end == "paper"
    assert paper.budget_names("paper") == ["wall-120s", "wall-300s"]


@pytest.mark.parametrize(("data", "message"), [
    ({"learnin": {}}, "learnin = {} is not a setting of the study (allowed: landscape, "),
    ({"learning": {"runz": 3}}, "learning.runz = 3 is not a setting of learning"),
    ({"learning": {"runs": -1}}, "learning.runs = -1 is outside the valid range (an integer >= 1)"),
    ({"learning": {"budgets": {"short": -5}}},
     "learning.budgets.short = -5 is outside the valid range (an integer >= 1)"),
    ({"learning": {"budgets": {"short": "abc"}}},
     "learning.budgets.short = 'abc' is not allowed (expected an integer >= 1)"),
    ({"learning": {"runs": 2.5}}, "learning.runs = 2.5 is not allowed (expected an integer"),
    ({"learning": {"runs": True}}, "learning.runs = True is not allowed"),
    ({"learning": {"agents": ["qlearning", "dqnn"]}}, "learning.agents[1] = 'dqnn' is not "
     "allowed (expected one of 'qlearning'"),
    ({"learning": {"targets": [{"objective": "reba"}]}}, "learning.targets[0].name is missing"),
    ({"learning": {"wall_targets": ["nowhere"]}}, "learning.wall_targets = 'nowhere' names no "
     "target"),
    ({"learning": {"budgets": {}, "wall_caps_s": []}}, "learning.budgets = {} is not allowed"),
    ({"landscape": {"step": 0}}, "landscape.step = 0.0 is outside the valid range (a number > "
     "0 m)"),
    ({"population": {"female_share": 1.5}}, "population.female_share = 1.5 is outside the "
     "valid range (a number 0-1)"),
    ({"participants": {"workers": ["p50-man"]}}, "participants.workers[0] = 'p50-man' is not "
     "allowed"),
    ({"baselines": {"location": {"budget": "paper-9min"}}}, "baselines.location.budget = "
     "'paper-9min' names no run of the learning part"),
    ([], "configuration = [] is not allowed (expected an object"),
])
def test_bad_configurations_are_one_line_naming_the_key_path(data, message):
    with pytest.raises(ConfigError) as caught:
        StudyConfig.from_dict(data)
    text = str(caught.value)
    assert text.startswith(message) and "\n" not in text


def test_overrides_set_nested_values_as_json_or_text():
    config = StudyConfig.load(CONFIGS / "paper.json", (
        "learning.wall_caps_s=[1, 2]", "baselines.location.budget=wall-2s",
        "population.size=7"))
    assert config.learning.wall_caps_s == (1.0, 2.0)
    assert config.baselines.location.budget == "wall-2s" and config.population.size == 7
    with pytest.raises(ConfigError, match="expected KEY=VALUE"):
        StudyConfig.load(CONFIGS / "default.json", ("learning.runs",))


@pytest.mark.parametrize(("args", "message"), [
    (["--set", "learning.runs=-1"], "learning.runs = -1 is outside the valid range"),
    (["--set", "learnin.runs=3"], "learnin = {'runs': 3} is not a setting of the study"),
    (["--set", 'learning.budgets={"short": -100}'], "learning.budgets.short = -100 is outside"),
])
@pytest.mark.slow
def test_run_all_refuses_a_bad_configuration_with_one_line_and_writes_nothing(tmp_path, args,
                                                                              message):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"learning": {"typo": 1}}))
    for command in (args, ["--config", str(bad)]):
        out = subprocess.run([sys.executable, str(ROOT / "experiments" / "run_all.py"), *command,
                              "--results", str(tmp_path / "results"), "--figures",
                              str(tmp_path / "figures")], capture_output=True, text=True,
                             timeout=120)
        assert out.returncode == 2, out.stderr
        lines = out.stderr.strip().splitlines()
        expected = message if command is args else "learning.typo = 1 is not a setting"
        assert len(lines) == 1 and lines[0].startswith(f"run_all: error: {expected}"), lines
        assert not (tmp_path / "results").exists() and not (tmp_path / "figures").exists()


def test_the_resolved_configuration_is_printed_whole():
    out = subprocess.run([sys.executable, str(ROOT / "experiments" / "run_all.py"),
                          "--config", str(CONFIGS / "quick.json"), "--show-config"],
                         capture_output=True, text=True, timeout=120, check=True)
    shown = json.loads(out.stdout)
    assert shown == json.loads(json.dumps(dataclasses.asdict(
        StudyConfig.load(CONFIGS / "quick.json"))))
    assert shown["learning"]["runs"] == 5 and shown["learning"]["targets"][0]["name"] == "paper"
