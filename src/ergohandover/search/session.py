"""One worker's personalisation session: propose → observe → update, saved after every answer.

Each trial is a real handover, so an answer must never be lost and a session must survive an
interruption (a break, a closed terminal, Ctrl-C). The session's state is a small JSON file
written atomically after every answer: the settings that fix what the searcher proposes and
what a score means, and the history of what it was told. A searcher is deterministic given its
seed and its history (:mod:`.protocol`), so a rerun with the same settings rebuilds it by
:func:`~.protocol.replay` and proposes exactly what the interrupted session would have proposed
next. A state made with other settings is refused: its answers would mean something else.

State file (JSON)::

    {"format": "ergohandover personalise state", "version": 1,
     "settings": {"searcher", "seed", "objective", "evaluator", "grid", "prior"},
     "posture_header": null or [column, ...],
     "history": [{"trial": 1, "cell", "x", "y", "z" [m],
                  "score" (null: infeasible), "answer", "answered_at"}, ...]}

The history holds every trial (a real handover) in order. A searcher may propose a location it
was told about before: it is then told the known answer again without a new handover, and
nothing is written (:class:`~.protocol.Evaluations`; files of an earlier version list such
repeats with ``trial`` null, which are read and skipped: :func:`~.protocol.replay` answers them
from memory again).
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from ..envs.scores import Answer, ScoreSource
from ..errors import ErgohandoverError
from ..io.atomic import atomic_write
from .oracles import Oracle, Proposal
from .protocol import AskTellSearcher, replay
from .protocol import run as run_search
from .record import Budget

FORMAT = "ergohandover personalise state"
VERSION = 1
TRIAL_COLUMNS = ("trial", "x", "y", "z", "feasible", "score", "answer", "answered_at")


@dataclass(frozen=True)
class Recommended:
    """Where a session recommends handing over: the ``cell`` and its ``location`` [m], the
    first ``trial`` there (None: not handed over there yet) and the model's probability that
    it is the worker's optimum (NaN: the model states none)."""

    cell: int
    location: tuple[float, float, float]
    trial: Trial | None
    p_optimal: float = math.nan

    @property
    def score(self) -> float:
        """The score observed there (NaN: not handed over there yet)."""
        return self.trial.score if self.trial is not None else math.nan


class StateError(ErgohandoverError, ValueError):
    """A state file that cannot be read as a session's state."""


class StateMismatch(ErgohandoverError, ValueError):
    """A state file made with other settings: ``key`` (dotted) was ``old``, is ``new``."""

    def __init__(self, key: str, old: Any, new: Any):
        super().__init__(f"its session has {key} = {old!r}, this one {new!r}")
        self.key, self.old, self.new = key, old, new


@dataclass(frozen=True)
class Trial:
    """One handover of the session: its number, the ``cell`` and its ``location`` [m], the
    ``score`` (``inf``: infeasible), the answer as given and when [ISO 8601, UTC], and the
    angles the answer carried (None: none; NaN: unseen), which a fitted twin is fitted to."""

    trial: int
    cell: int
    location: tuple[float, float, float]
    score: float
    answer: str
    answered_at: str
    posture: dict[str, float] | None = None

    def to_json(self) -> dict:
        x, y, z = self.location
        found = {"trial": self.trial, "cell": self.cell, "x": x, "y": y, "z": z,
                 "score": self.score if math.isfinite(self.score) else None,
                 "answer": self.answer, "answered_at": self.answered_at}
        if self.posture is not None:  # JSON has no NaN: an unseen angle is null
            found["posture"] = {a: v if math.isfinite(v) else None
                                for a, v in self.posture.items()}
        return found

    @classmethod
    def from_json(cls, data: dict) -> Trial:
        score = math.inf if data["score"] is None else float(data["score"])
        posture = data.get("posture")
        if posture is not None:
            posture = {a: math.nan if v is None else float(v) for a, v in posture.items()}
        return cls(int(data["trial"]), int(data["cell"]),
                   (float(data["x"]), float(data["y"]), float(data["z"])), score,
                   str(data["answer"]), str(data["answered_at"]), posture)


def as_json(value: Any) -> Any:
    """``value`` as it reads back from JSON (tuples become lists), to compare settings."""
    return json.loads(json.dumps(value))


def first_difference(old: Any, new: Any, key: str = "") -> tuple[str, Any, Any] | None:
    """The first (dotted key, old, new) where two JSON values differ, or None."""
    if isinstance(old, dict) and isinstance(new, dict):
        for name in [*old, *(k for k in new if k not in old)]:
            found = first_difference(old.get(name), new.get(name),
                                     f"{key}.{name}" if key else name)
            if found:
                return found
        return None
    return None if old == new else (key, old, new)


class Session:
    """The settings, the history and where they are saved.

    Args:
        path: the state file.
        settings: what fixes the proposals and the meaning of a score (JSON values).
    """

    def __init__(self, path: Path, settings: dict, history: list[Trial] | None = None,
                 posture_header: tuple[str, ...] | None = None):
        self.path, self.settings = Path(path), as_json(settings)
        self.history = list(history or [])
        self.posture_header = posture_header

    @classmethod
    def open(cls, path: Path, settings: dict) -> Session:
        """The session saved at ``path`` if there is one (refused if made with other
        settings), else a new one (nothing is written until the first answer)."""
        path = Path(path)
        if not path.exists():
            return cls(path, settings)
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
            kind, version = data.get("format"), data.get("version")
        except (json.JSONDecodeError, UnicodeDecodeError, AttributeError) as exc:
            raise unreadable(exc) from None
        if kind != FORMAT:
            raise StateError(f"not a personalise state file (format {kind!r})")
        if version != VERSION:
            raise StateError(f"state version {version!r}; this version of ergohandover reads "
                             f"version {VERSION}")
        try:
            history = [Trial.from_json(item) for item in data["history"]
                       if item["trial"] is not None]  # an earlier version's repeats
            saved, header = data["settings"], data.get("posture_header")
        except (KeyError, TypeError, ValueError) as exc:
            raise unreadable(exc) from None
        found = first_difference(saved, as_json(settings))
        if found:
            raise StateMismatch(*found)
        return cls(path, settings, history, tuple(header) if header else None)

    @property
    def trials(self) -> list[Trial]:
        """The handovers, in order."""
        return self.history

    def best(self, searcher: AskTellSearcher | None = None) -> Recommended | None:
        """Where to hand over: the location ``searcher``'s model recommends
        (:meth:`~.protocol.AskTellSearcher.recommend`: its own model of the worker, or a model
        of its answers; never the lowest single reading), with the first trial there (None:
        its model recommends a location not handed over at yet). Without a searcher (a state
        file read alone), the trial of the lowest feasible score, the earliest of equals. None
        when nothing feasible was seen."""
        if searcher is None:
            feasible = [r for r in self.trials if math.isfinite(r.score)]
            if not feasible:
                return None
            found = min(feasible, key=lambda r: r.score)
            return Recommended(found.cell, found.location, found)
        model = searcher.recommend()
        if model.cell is None:
            return None
        trial = next((r for r in self.trials if r.cell == model.cell
                      and math.isfinite(r.score)), None)
        return Recommended(model.cell, searcher.grid.point(model.cell), trial, model.p_optimal)

    def uncertainty(self, best: Recommended | None, searcher: AskTellSearcher) -> dict:
        """How sure the recommendation ``best`` is: of a searcher told preferences, its model's
        probability that ``best`` is the best of the feasible locations tried; of a model that
        states it, its probability that ``best`` is the worker's optimum; else how many of the
        feasible locations tried scored within one point of it (one answer is one
        measurement: any of them may be as good)."""
        if best is None:
            return {}
        feasible = [t for t in self.trials if math.isfinite(t.score)]
        if searcher.answers == "preferences":
            return {"p_best_of_tried": searcher.confidence(), "feasible_tried": len(feasible)}
        if math.isfinite(best.p_optimal):
            return {"p_optimal": best.p_optimal, "feasible_tried": len(feasible)}
        close = sum(1 for t in feasible if t is not best.trial and t.score <= best.score + 1)
        return {"within_1_of_it": close, "feasible_tried": len(feasible)}

    def resume(self, searcher: AskTellSearcher) -> AskTellSearcher:
        """``searcher`` told this session's history, as it was told the first time (each
        answer with the angles it carried)."""
        return replay(searcher, self.answers())

    def answers(self) -> list[tuple[int, Answer]]:
        """(cell, answer) of every trial of the history, in order, as the searcher heard it."""
        return [(r.cell, Answer(r.score, posture=r.posture)) for r in self.history]

    def add(self, record: Trial) -> None:
        """Record an answer and save the state (atomically: the file is whole, old or new)."""
        self.history.append(record)
        self.save()

    def save(self) -> None:
        state = {"format": FORMAT, "version": VERSION, "settings": self.settings,
                 "posture_header": list(self.posture_header) if self.posture_header else None,
                 "history": [r.to_json() for r in self.history]}
        text = json.dumps(state, indent=1) + "\n"
        self.path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(self.path, lambda handle: handle.write(text))

    def table(self) -> pd.DataFrame:
        """One row per trial: :data:`TRIAL_COLUMNS` (score empty where infeasible)."""
        rows = [{"trial": r.trial, "x": r.location[0], "y": r.location[1], "z": r.location[2],
                 "feasible": int(math.isfinite(r.score)),
                 "score": r.score if math.isfinite(r.score) else None, "answer": r.answer,
                 "answered_at": r.answered_at} for r in self.trials]
        return pd.DataFrame(rows, columns=list(TRIAL_COLUMNS))


def unreadable(exc: Exception) -> StateError:
    """A state file whose JSON is not a state's, with the parser's first line."""
    detail = str(exc).splitlines()[0] if str(exc) else ""
    return StateError(f"not a personalise state file ({type(exc).__name__}: {detail})")


def now() -> str:
    return time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())


class AnsweredScores(ScoreSource):
    """The scores of a session: each new cell proposed to ``oracle``, its answer saved before
    the searcher hears it (an interruption in between loses nothing)."""

    def __init__(self, session: Session, oracle: Oracle, grid, objective: str, budget: int,
                 say: Callable[[str], None], answers: str = "scores"):
        self.session, self.oracle, self.grid, self.objective = session, oracle, grid, objective
        self.budget, self.say, self.answers = budget, say, answers

    def score(self, flat: int) -> float:
        return self.answer(flat).score

    def answer(self, flat: int) -> Answer:
        location = tuple(round(v, 9) for v in self.grid.point(flat))
        before = next((t for t in reversed(self.session.trials) if math.isfinite(t.score)), None)
        proposal = Proposal(len(self.session.trials) + 1, self.budget, flat, location,
                            None if before is None else (before.trial, before.cell,
                                                         before.location))
        self.say(proposal.describe())
        answer = self.oracle.answer(proposal)
        self.session.posture_header = self.oracle.header
        self.session.add(Trial(proposal.trial, flat, location, answer.score, answer.text,
                               now(), answer.posture))
        return answer


ENDINGS = {"evaluation_cap": "budget", "stop_score": "target", "grid": "grid",
           "ask_cap": "searcher"}
"""Why a session ends, in the command's words, from :attr:`~.record.Record.stopped_by`."""


def run(session: Session, searcher: AskTellSearcher, oracle: Oracle, budget: int,
        target: float | None = None, say: Callable[[str], None] = print) -> str:
    """Propose, ask ``oracle``, record and save, until the session ends; why it ended.

    Args:
        session: its state (``searcher`` has been told its history: :meth:`Session.resume`).
        searcher: proposes the cells.
        oracle: answers each proposal (may raise :class:`~.oracles.AnswersEnded` or
            KeyboardInterrupt: every answer before is saved).
        budget: trials (real handovers) in all, those of the history included.
        target: end at the first score at or below it (None: run the budget out).
        say: shows each proposal.

    Returns:
        ``budget``, ``target`` (reached), ``grid`` (every location tried) or ``searcher`` (it
        kept proposing known locations).
    """
    # The oracle answers as the searcher is told (scores, or preferences).
    scores = AnsweredScores(session, oracle, searcher.grid, session.settings.get("objective"),
                            budget, say, answers=searcher.answers)
    record = run_search(searcher, scores, Budget(evaluations=budget, stop_score=target),
                        known=session.answers())
    return ENDINGS[record.stopped_by]
