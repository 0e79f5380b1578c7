"""The study's registry of questions: every question is a folder with its config section and
its part; no part imports another part; run_all orders the parts from what each needs; and
each question's results folder holds what its entry says it writes."""

from __future__ import annotations

import ast
import dataclasses
import sys
from pathlib import Path

import pandas as pd
import pytest

from ergohandover.study import registry
from ergohandover.study.config import StudyConfig
from ergohandover.study.registry import PARTS, QUESTIONS, needed, run_order

ROOT = Path(__file__).resolve().parents[1]
STUDY = ROOT / "src" / "ergohandover" / "study"
RESULTS = ROOT / "results"


def imported_modules(path: Path) -> set[str]:
    """Every module ``path`` imports, as absolute dotted names."""
    package = path.relative_to(ROOT / "src").with_suffix("").parts[:-1]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = (list(package[:len(package) - node.level + 1]) if node.level else [])
            module = ".".join([*base, *(node.module.split(".") if node.module else [])])
            found.add(module)
            found.update(f"{module}.{alias.name}" for alias in node.names)
        elif isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
    return found


def test_every_question_is_a_folder_with_its_config_section_and_its_part():
    sections = [f.name for f in dataclasses.fields(StudyConfig)]
    assert sorted(sections) == sorted(PARTS)
    for name in PARTS:
        assert (STUDY / name / "part.py").is_file()
        assert (STUDY / name / "config.py").is_file()
        section = type(getattr(StudyConfig(), name))
        assert section.__module__ == f"ergohandover.study.{name}.config"


@pytest.mark.parametrize("name", PARTS)
def test_no_part_imports_another_part(name):
    others = {f"ergohandover.study.{q}.part" for q in PARTS if q != name}
    for path in (STUDY / name).glob("*.py"):
        reached = imported_modules(path) & (others | {"ergohandover.study.registry.part"})
        assert not reached, f"{path.relative_to(ROOT)} imports {sorted(reached)}"


def test_each_question_needs_only_questions_run_before_it():
    for index, question in enumerate(QUESTIONS):
        earlier = {q.name for q in QUESTIONS[:index]}
        assert set(question.needs) <= earlier, question.name


def test_the_run_order_puts_every_part_after_what_it_needs_directly_or_not():
    assert run_order(["manikins"]) == ["landscape", "learning", "baselines", "participants",
                                       "population", "sensitivity", "robustness", "manikins"]
    assert run_order(["personalise"]) == ["population", "personalise"]
    assert run_order(["landscape"]) == ["landscape"]
    assert run_order(["people", "stance"]) == ["landscape", "learning", "baselines",
                                               "participants", "stance", "people"]
    assert needed("robustness") == ("landscape", "learning", "baselines", "participants",
                                    "population", "sensitivity")


def test_a_parts_hashed_inputs_are_its_section_and_everything_it_needs():
    config = StudyConfig()
    for name in PARTS:
        inputs = set(config.part_inputs(name)) - {"capture_code", "measured_data",
                                                   "fatigue_code"}
        # The accommodation part's workforce goes through the shift question's shifts.
        shifts = {"shift"} if name == "accommodation" else set()
        assert inputs == {name, "landscape", *needed(name), *shifts}


def test_an_unknown_part_is_one_line_naming_the_allowed_ones():
    from ergohandover.errors import ConfigError

    with pytest.raises(ConfigError, match=r"part = 'lanscape' is not allowed \(use landscape,"):
        registry.question("lanscape")


@pytest.mark.parametrize("question", QUESTIONS, ids=lambda q: q.name)
def test_each_committed_results_folder_holds_what_its_entry_says_it_writes(question):
    folder = RESULTS / question.name
    present = {p.name + ("/" if p.is_dir() else "") for p in folder.iterdir()} - {
        "manifest.json"}
    assert present == set(question.writes), question.name
    for name, columns in question.writes.items():
        if name.endswith(".csv"):
            header = pd.read_csv(folder / name, nrows=0).columns
            assert set(columns) <= set(header), f"{name} lacks {set(columns) - set(header)}"


@pytest.mark.parametrize("question", QUESTIONS, ids=lambda q: q.name)
def test_each_figure_script_a_question_names_exists(question):
    if question.figure:
        assert (ROOT / "experiments" / "analysis" / f"{question.figure}.py").is_file()


def test_run_all_only_a_part_runs_what_it_needs_first_and_forces_only_it(tmp_path,
                                                                          monkeypatch):
    """--only manikins --force: every part manikins needs runs first, in order, reused (not
    forced); manikins itself is forced; its figures alone are redrawn (it has none)."""
    sys.path.insert(0, str(ROOT / "experiments"))
    try:
        import run_all
    finally:
        sys.path.pop(0)
    calls: list[tuple[str, bool]] = []

    class FakePart:
        def __init__(self, name):
            self.name = name

        def run(self, config, results, engine, force=False):
            calls.append((self.name, force))
            return force

    drawn: list[tuple[str, ...]] = []
    monkeypatch.setattr(run_all, "part", FakePart)
    monkeypatch.setattr(run_all, "estimate", lambda *args: 1.0)
    monkeypatch.setattr(run_all, "build_figures",
                        lambda results, figures, scripts=(): drawn.append(tuple(scripts)))
    assert run_all.main(["--only", "manikins", "--force", "--results", str(tmp_path)]) == 0
    assert calls == [(name, name == "manikins") for name in run_order(["manikins"])]
    assert drawn == []
    calls.clear()
    assert run_all.main(["--only", "population", "--results", str(tmp_path)]) == 0
    assert calls == [("population", False)]
    assert drawn == [("fig_population",)]
