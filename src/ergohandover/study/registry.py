"""The study's questions: one folder each (``study/<name>/``: its config section, its
computation and its ``part.py``), and one entry here that declares what the question
**needs** (the questions whose results it reads), what it **writes** (its files, and the columns
other questions read), whether it has a **headline** (README rows declared in
experiments/analysis/headlines.py) and its time **budget** on 2 cores.

``experiments/run_all.py`` orders the questions from ``needs`` (:func:`run_order`); no part
imports another part, and a part reads what another wrote only through that question's
``recorded.py``. Each ``part.py`` has ``run(config, results, engine, force)``: it runs unless its
manifest says it is done and returns whether it ran (it never runs what it needs: run_all
does). Adding a question is a folder and one entry (docs/architecture.md says how).
"""

from __future__ import annotations

import dataclasses
import importlib
from types import ModuleType

from ..errors import ConfigError


@dataclasses.dataclass(frozen=True)
class Question:
    """One study question.

    Attributes:
        name: its folder, its config section, its part and its results folder.
        needs: the questions whose results it reads (run before it, and hashed into its
            manifest with their settings).
        writes: each file (or ``folder/``) it writes into ``results/<name>/``, with the columns
            another question reads from it (``()``: no other question reads it).
        budget_s: its declared wall time on 2 cores [s], landscapes already in the cache
            (``run_all`` prints its time against it; a committed part over it fails a test).
        headline: whether it answers README headline rows (declared under its name in
            experiments/analysis/headlines.py: claim, N, uncertainty, baseline, reversals).
        figure: its figure script in experiments/analysis/, or "".
    """

    name: str
    needs: tuple[str, ...]
    writes: dict[str, tuple[str, ...]]
    budget_s: float
    headline: bool = False
    figure: str = ""


XYZ = ("x", "y", "z")

QUESTIONS = (
    Question("landscape", (), {
        "stats.csv": ("score", "best_x", "best_y", "best_z"), "distribution.csv": (),
        "variants.csv": (), "gaze_effect.csv": ()}, 90, True, "fig_score_distribution"),
    Question("learning", ("landscape",), {
        "found.csv": ("target", "agent", "budget", "run", *XYZ, "argmin_x", "argmin_y",
                      "argmin_z"),
        "summary.csv": (), "comparisons.csv": (), "runs.csv": (), "curves.csv": (),
        "full_runs.csv": (), "power.csv": (), "targets.csv": (), "traces.csv": ()},
        480, True, "fig_learning"),
    Question("baselines", ("landscape", "learning"), {
        "baselines.csv": ("start_x", "start_y", "start_z", "method", *XYZ), "baselines.md": (),
        "other_starts.csv": (),
        "reachability.csv": (), "reachability_summary.csv": (), "paths/": (), "renders/": (),
        "recordings/": ()}, 250, True, "fig_baselines"),
    Question("ablations", ("landscape",), {"ik.csv": ()}, 40),
    Question("participants", ("landscape",), {
        "participants.csv": ("worker", "location", "start", *XYZ)}, 50, True,
        "fig_participants"),
    Question("population", (), {
        "workers.csv": ("worker",), "one_size.csv": (), "penalties.csv": (), "groups.csv": (),
        "who_pays_tests.csv": (), "height_fit.csv": (), "fixed_ratio_twin.csv": (),
        "proportions.csv": (), "working_heights.csv": ()}, 330, True, "fig_population"),
    Question("sensitivity", ("landscape",), {"sensitivity.csv": ()}, 100, False,
             "fig_sensitivity"),
    Question("validation", ("landscape",), {
        "validation.csv": (), "knee_height.csv": (), "handovers.csv": ()}, 10, False,
        "fig_validation"),
    Question("robustness", ("baselines", "participants", "population", "sensitivity"), {
        "locations.csv": ("location", *XYZ), **{f"{name}.csv": () for name in (
            "comparisons", "expected_landscape", "flips", "margins", "measured_comparisons",
            "measured_error", "measured_flips", "measured_locations", "one_size",
            "penalty_regression", "personal", "placement", "practice_carries", "regret",
            "regret_summary")}}, 330, True, "fig_robustness"),
    Question("stance", ("baselines", "participants"), {
        "headline.csv": (), "locations.csv": (), "posture_error.csv": ()}, 20, True),
    Question("personalise", ("population",), {
        "runs.csv": (), "summary.csv": (), "curves.csv": (), "workers.csv": (),
        "measured_runs.csv": (), "measured_summary.csv": ()}, 1100, True,
        "fig_personalise"),
    Question("capture", ("landscape",), {"columns.csv": (), "scores.csv": ()}, 15, False,
             "fig_capture"),
    Question("people", ("landscape",), {
        "handovers.csv": (), "skill.csv": (), "fit.csv": (), "locations.csv": (),
        "receiving.csv": (), "ranking.csv": (), "recommendation.csv": (),
        "study_task.csv": ()}, 200, True, "fig_people"),
    Question("manikins", ("robustness",), {"manikins.csv": ()}, 15),
    Question("accommodation", ("robustness",), {
        "cells.csv": (), "locations.csv": (), "zone.csv": (), "workers.csv": (),
        "shift.csv": (), "shift_zone.csv": ()}, 300, True,
        "fig_accommodation"),
    Question("shift", ("population", "robustness"), {
        "reference.csv": (), "curves.csv": (), "locations.csv": (), "trace.csv": ()}, 120,
             True, "fig_shift"),
)
"""Every question, in the order ``run_all`` runs them all (each after what it needs)."""

BY_NAME = {q.name: q for q in QUESTIONS}
PARTS = tuple(BY_NAME)
"""Every part's name, in run order."""


def question(name: str) -> Question:
    """The entry of question ``name`` (ConfigError naming the allowed ones otherwise)."""
    if name not in BY_NAME:
        raise ConfigError(f"part = {name!r} is not allowed (use {', '.join(PARTS)})")
    return BY_NAME[name]


def part(name: str) -> ModuleType:
    """The part module of question ``name`` (imported on first use: a part pulls in what it
    needs)."""
    question(name)
    return importlib.import_module(f"{__package__}.{name}.part")


def needed(name: str) -> tuple[str, ...]:
    """Every question ``name`` reads, directly or through another, in run order."""
    seen: set[str] = set()
    stack = list(question(name).needs)
    while stack:
        other = stack.pop()
        if other not in seen:
            seen.add(other)
            stack.extend(question(other).needs)
    return tuple(q for q in PARTS if q in seen)


def run_order(names: list[str] | tuple[str, ...]) -> list[str]:
    """The parts to run for ``names``: each with everything it needs, each once, every part
    after those it needs (the registry's order)."""
    wanted = {n for name in names for n in (name, *needed(name))}
    return [q for q in PARTS if q in wanted]
