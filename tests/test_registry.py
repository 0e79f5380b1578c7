"""One registry, one protocol: every door offers the registry's names, and a searcher added as
one class and one registry entry runs through ``train``, ``personalise`` and the study."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from synthetic import bowl_landscape

from ergohandover.cli import main
from ergohandover.envs import LandscapeScores
from ergohandover.errors import ConfigError
from ergohandover.search import Budget, make, run
from ergohandover.search.cells import NewCellSearcher
from ergohandover.search.registry import SEARCHERS, Entry, entry, names
from ergohandover.study.config import StudyConfig


class Lowest(NewCellSearcher):
    """Proposes the cells in flat order: the smallest possible searcher."""

    name = "lowest"

    def _propose(self) -> int:
        return next(c for c in range(self.grid.size) if c not in self.told)

    def _learn(self, cell: int, score: float) -> None:
        """It learns nothing."""


@pytest.fixture
def lowest_registered(monkeypatch):
    """The one line that adds the searcher above."""
    monkeypatch.setitem(SEARCHERS, "lowest",
                        Entry("lowest", "flat order", "searcher", "test_registry:Lowest"))


def test_a_searcher_added_by_one_entry_runs_through_every_door(lowest_registered, tmp_path):
    bowl = bowl_landscape().save(tmp_path / "bowl.npz")
    assert main(["train", "--agent", "lowest", "--steps", "7", "--landscape", str(bowl),
                 "--output", str(tmp_path / "train")]) == 0
    summary = json.loads((tmp_path / "train" / "manifest.json").read_text())["summary"]
    assert summary["agent"] == "lowest" and summary["steps"] == 7
    assert main(["personalise", "--oracle", "twin", "--searcher", "lowest", "--trials", "3",
                 "--boundary", "-0.1,0.1,1.0,1.2,0.35,0.5", "--step", "0.05",
                 "--output", str(tmp_path / "personalise")]) == 0
    trials = (tmp_path / "personalise" / "trials.csv").read_text().splitlines()
    assert len(trials) == 1 + 3
    config = StudyConfig.from_dict({"personalise": {"searchers": ["lowest"]}})
    assert config.personalise.searchers == ("lowest",)


def test_every_door_offers_the_registry(capsys):
    from ergohandover.cli.personalise import registered_searchers
    from ergohandover.study.learning.config import LearningConfig
    from ergohandover.study.personalise.config import PersonaliseConfig

    fields = {f.name: f for f in dataclasses.fields(LearningConfig)}
    assert set(fields["agents"].metadata["choices"]) == set(SEARCHERS)
    fields = {f.name: f for f in dataclasses.fields(PersonaliseConfig)}
    assert set(fields["searchers"].metadata["choices"]) == set(SEARCHERS)
    assert set(registered_searchers()) == {n for n in names("searcher")
                                           if entry(n).variant_of is None}
    assert main(["train", "--agent", "sarsa", "--steps", "5"]) == 2
    assert "--agent sarsa: not one of " + ", ".join(SEARCHERS) in capsys.readouterr().err


def test_a_variant_is_its_searcher_always_warm_started():
    assert entry("bo+prior").variant_of == "bo" and entry("bo+prior").make == entry("bo").make
    grid = LandscapeScores(bowl_landscape()).grid
    with pytest.raises(ConfigError, match="searcher bo\\+prior needs a worker's prior"):
        make("bo+prior", grid, 0)
    assert make("random-order", grid, 0, prior=object()).prior is None  # takes none


def test_the_two_random_searches_differ_in_whether_a_repeat_costs():
    scores = LandscapeScores(bowl_landscape())
    draws = run(make("random-draws", scores.grid, 0), scores, Budget(steps=2_000))
    order = run(make("random-order", scores.grid, 0), scores, Budget(evaluations=343))
    assert draws.unit == "steps" and draws.steps == 2_000 and not draws.cells
    assert order.unit == "evaluations" and sorted(order.cells) == list(range(343))
    assert order.scores == [scores.score(c) for c in order.cells]
    assert np.isinf(order.scores).sum() == np.isinf([scores.score(c) for c in range(343)]).sum()
