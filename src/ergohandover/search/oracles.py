"""Who answers a proposed handover: the twin, a person at the terminal, or a file.

``twin`` scores the location with the worker's digital twin (demonstrations and tests). ``ask``
prints the location and reads the observed score from a line of standard input. ``file``
reads ``TRIAL,ANSWER`` lines that another program appends to a file (a capture tool, a VR
scene), waiting for the line of the proposed trial; the pending proposal is also written to a
small CSV beside the session's outputs, so that the program knows what to show next. An answer
is anything :class:`~.answers.AnswerReader` accepts; a bad one is refused in one line and the
oracle waits for another.
"""

from __future__ import annotations

import math
import sys
import time
from abc import ABC, abstractmethod
from pathlib import Path
from typing import IO, NamedTuple

from ..errors import ErgohandoverError
from ..io.atomic import atomic_write
from .answers import Answer, AnswerReader, PreferenceReader, Refused


class AnswersEnded(ErgohandoverError, EOFError):
    """No more answers will come (standard input ended): the session pauses."""


class Proposal(NamedTuple):
    """Trial ``trial`` of ``budget``: the grid ``cell`` at ``location`` (x, y, z) [m];
    ``previous``: the last feasible trial before it (number, cell, location), which a preference
    compares it with (None: none)."""

    trial: int
    budget: int
    cell: int
    location: tuple[float, float, float]
    previous: tuple[int, int, tuple[float, float, float]] | None = None

    def describe(self) -> str:
        return f"trial {self.trial}/{self.budget}: hand the box at {in_cm(self.location)}"


def in_cm(location) -> str:
    """A worker-frame location in centimetres, as a person setting up a handover reads it."""
    x, y, z = (round(100.0 * float(v), 1) + 0.0 for v in location)  # + 0.0: never "-0.0"
    side = "left" if x < 0 else "right"
    return (f"{abs(x):.1f} cm to the {side}, {y:.1f} cm up, {z:.1f} cm forward of the floor "
            f"midway between the worker's feet (x, y, z = {x:+.1f}, {y:.1f}, {z:.1f} cm)")


class Oracle(ABC):
    """Answers proposals; ``header`` is a posture header line it was given (None: none)."""

    name: str = ""
    header: tuple[str, ...] | None = None

    @abstractmethod
    def answer(self, proposal: Proposal) -> Answer:
        """The score at the proposal; :class:`AnswersEnded` when no answer will come."""

    def finish(self) -> None:  # noqa: B027  (optional: most oracles leave nothing behind)
        """The session has ended (nothing is pending any more)."""


class TwinOracle(Oracle):
    """The twin's score of ``objective`` at the cell (``inf`` where it cannot take the box)."""

    name = "twin"

    def __init__(self, grid, evaluator, objective: str, output: IO[str] | None = None):
        from ..envs.scores import OnlineScores

        self.scores = OnlineScores(grid, evaluator, objective, block=1)
        self.output = output or sys.stdout

    def answer(self, proposal: Proposal) -> Answer:
        score = self.scores.score(proposal.cell)
        shown = f"{score:g}" if math.isfinite(score) else "x (the twin cannot take the box there)"
        print(f"twin: {shown}", file=self.output, flush=True)
        return Answer(score, "twin", "twin", self.angles(proposal.cell) if math.isfinite(score)
                      else None)

    def angles(self, cell: int) -> dict[str, float]:
        """The twin's angles at ``cell`` (what a captured frame of it would measure)."""
        from ..robustness.posture_error import ANGLE_COLUMNS, angles_of
        from ..twin.evaluate import evaluate_arrays

        return angles_of(evaluate_arrays(self.scores.grid.coordinates([cell]),
                                         self.scores.evaluator, columns=ANGLE_COLUMNS))


class ComparingTwin(TwinOracle):
    """The twin's preference: this handover's score against the last feasible one's (lower is
    better; equal scores: same), ``ok`` for the first."""

    def answer(self, proposal: Proposal) -> Answer:
        from .answers import PREFERENCES

        score = self.scores.score(proposal.cell)
        if not math.isfinite(score):
            word, shown = "x", "x (the twin cannot take the box there)"
        elif proposal.previous is None:
            word = shown = "ok"
        else:
            before = self.scores.score(proposal.previous[1])
            word = "better" if score < before else "worse" if score > before else "same"
            shown = f"{word} ({self.scores.objective} {score:g} against {before:g})"
        print(f"twin: {shown}", file=self.output, flush=True)
        value = math.inf if word == "x" else 0.0 if word == "ok" else PREFERENCES[word]
        return Answer(value, "twin", word)


class AskOracle(Oracle):
    """Prompts on ``output`` and reads one answer a line from ``source``; echoes each line when
    ``source`` is not a terminal (a script's answers then show in the transcript)."""

    name = "ask"

    def __init__(self, reader: AnswerReader | PreferenceReader, source: IO[str] | None = None,
                 output: IO[str] | None = None, errors: IO[str] | None = None):
        self.reader = reader
        self.source = source or sys.stdin
        self.output, self.errors = output or sys.stdout, errors or sys.stderr
        self.echo = not self.source.isatty()

    @property
    def header(self) -> tuple[str, ...] | None:  # type: ignore[override]
        return self.reader.header

    def answer(self, proposal: Proposal) -> Answer:
        self.reader.begin(proposal.previous)
        while True:
            self.output.write(self.reader.prompt)
            self.output.flush()
            line = self.source.readline()
            if not line:
                print(file=self.output, flush=True)
                raise AnswersEnded("standard input ended")
            if self.echo:
                print(line.rstrip("\r\n"), file=self.output, flush=True)
            answer = read_or_refuse(self.reader, line, self.errors)
            if answer is not None:
                return answer


def read_or_refuse(reader: AnswerReader, line: str, errors: IO[str]) -> Answer | None:
    """The answer of ``line``; None after saying why it is not one (or noting a header)."""
    try:
        answer = reader.read(line)
    except Refused as exc:
        print(f"refused: {exc}", file=errors, flush=True)
        return None
    if answer is None:
        print(f"posture header noted: {len(reader.header or ())} columns", file=errors,
              flush=True)
    return answer


class FileOracle(Oracle):
    """Reads ``TRIAL,ANSWER`` lines appended to ``path``, polling every ``poll`` seconds.

    Trial N's answer is the first line ``N,ANSWER`` of the file whose ANSWER is one (a bad one
    is refused when its trial is proposed), whenever it was written: so a session reads the
    same answers whether or not it was interrupted and resumed (a resumed session reads the file
    from its start and skips the trials it has). Blank lines, ``#`` comments and a
    ``trial,...`` header line are ignored. Only complete lines (ending in a newline) are read,
    so a line being written is never read half.

    Args:
        path: the answers file (it may not exist yet).
        reader: turns an ANSWER into a score.
        poll: seconds between looks at the file [s].
        proposal_file: where the pending proposal is written (``trial,x,y,z``, metres).
    """

    name = "file"

    def __init__(self, path: Path, reader: AnswerReader | PreferenceReader, poll: float,
                 proposal_file: Path,
                 output: IO[str] | None = None, errors: IO[str] | None = None):
        self.path, self.reader, self.poll = Path(path), reader, poll
        self.proposal_file = proposal_file
        self.output, self.errors = output or sys.stdout, errors or sys.stderr
        self._offset, self._lines = 0, 0
        self._entries: list[tuple[int, str, str]] = []  # (trial, where, answer) not yet used

    @property
    def header(self) -> tuple[str, ...] | None:  # type: ignore[override]
        return self.reader.header

    def answer(self, proposal: Proposal) -> Answer:
        x, y, z = proposal.location
        text = f"trial,x,y,z\n{proposal.trial},{x:.6g},{y:.6g},{z:.6g}\n"
        self.proposal_file.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(self.proposal_file, lambda handle: handle.write(text))
        self.reader.begin(proposal.previous)
        waiting = False
        while True:
            self._read_new_lines()
            for entry in [e for e in self._entries if e[0] <= proposal.trial]:
                self._entries.remove(entry)
                trial, where, answer_text = entry
                if trial < proposal.trial:  # answered before (a resumed session)
                    continue
                print(f"answer ({where}): {answer_text.strip()}", file=self.output, flush=True)
                answer = read_or_refuse(self.reader, answer_text, self.errors)
                if answer is not None:
                    return answer
            if not waiting:
                print(f"waiting for a line '{proposal.trial},ANSWER' in {self.path}",
                      file=self.errors, flush=True)
                waiting = True
            time.sleep(self.poll)

    def _read_new_lines(self) -> None:
        """Note the complete lines appended since the last look."""
        try:
            with open(self.path, "rb") as handle:
                if handle.seek(0, 2) < self._offset:  # the file was rewritten: read it again
                    self._offset, self._lines, self._entries = 0, 0, []
                handle.seek(self._offset)
                data = handle.read()
        except FileNotFoundError:
            return
        end = data.rfind(b"\n") + 1
        self._offset += end
        for line in data[:end].decode("utf-8", errors="replace").splitlines():
            self._lines += 1
            where = f"{self.path} line {self._lines}"
            first, _, rest = line.strip().partition(",")
            if not line.strip() or first.startswith("#") or first.strip().lower() == "trial":
                continue
            try:
                self._entries.append((int(first), where, rest))
            except ValueError:
                print(f"refused: {where}: {first.strip()!r} is not a trial number (expected "
                      "TRIAL,ANSWER)", file=self.errors, flush=True)

    def finish(self) -> None:
        self.proposal_file.unlink(missing_ok=True)
