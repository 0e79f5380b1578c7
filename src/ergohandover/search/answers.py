"""What a person may answer for one proposed handover, and how each answer becomes a score.

In the field the score at a location comes from whoever watched the handover: an ergonomist
who read the score off the worker's posture, or a posture-capture tool that measured the angles.
So an answer is one line, one of:

- a score of the objective, within its range (:data:`SCORE_RANGES`); a fraction is allowed
  (the mean of two raters' scores);
- ``x`` (or ``infeasible``): the worker could not take the box there;
- a Posture CSV row (comma-separated, the columns of docs/architecture.md, "File contracts"),
  scored with the package's scorers exactly as ``ergohandover score`` scores that row. Its
  values are in the contract's order (the 24 required columns, or all 38) unless a header line
  (the column names, as a posture file's first line) was given before: then in that order.

A session whose answers come from a posture-capture program (``--answer-format
keypoints:FORMAT``) takes instead one captured frame per answer: the format's joints in its
order, x, y, z each, in metres, comma-separated (``nan`` for a point not seen), or ``x``. The
frame is scored as ``ergohandover score --keypoints`` scores it, with the session's task (the
box's mass, coupling and activity) as known; where the format leaves the objective open (a
column it cannot see), the answer is the middle of the objective's interval.

A session of preferences (``--answers pairwise``) takes instead, for every handover after the
first feasible one, how it compared with the handover before it (:class:`PreferenceReader`):
``better``, ``worse`` or ``same`` (or ``b``, ``w``, ``s``), or ``x``; the first handover is
answered ``ok`` (or ``x``).

Anything else is refused with one line saying what was typed and what is allowed, so that the
person can answer again; nothing is guessed.
"""

from __future__ import annotations

import io
import math
import re

import numpy as np

from ..envs.scores import Answer
from ..ergonomics import ScoringSettings, score_postures
from ..ergonomics.posture import POSTURE_COLUMNS, REQUIRED_COLUMNS, PostureError
from ..errors import ConfigError, ErgohandoverError
from ..io.csv_input import InputError
from ..io.posture_csv import read_postures
from ..robustness.posture_error import angles_of

SCORE_RANGES = {"paper_postural": (3, 14), "reba": (1, 15), "reba_ab": (2, 24), "rula": (1, 7)}
"""The lowest and highest value each objective can take. Highest: as
:data:`ergohandover.envs.scores.SCORE_MAX`. Lowest: the paper's score adds neck (>= 1), trunk
(>= 1), legs (>= 1), hands above the neck (>= 0) and an arm (>= 0); REBA's and RULA's final
scores start at 1; Table A and Table B of REBA start at 1 each."""
INFEASIBLE = ("x", "infeasible")
"""The answers saying that the worker could not take the box at the location."""


ANSWER_FORMATS = ("score", "keypoints:FORMAT[:UP]")
"""What ``--answer-format`` takes: scores (or x, or posture rows), or captured frames."""


def frame_format(text: str, objective: str):
    """(format, up axis) of an answer format ``keypoints:FORMAT[:UP]``; a one-line
    :class:`ConfigError` naming what is allowed otherwise."""
    from ..capture import keypoint_format
    from ..capture.formats import z_up
    from ..capture.unseen import SCORES

    kind, _, rest = text.partition(":")
    name, _, up = rest.partition(":")
    try:
        if kind != "keypoints" or not name:
            raise ConfigError(f"use {' or '.join(ANSWER_FORMATS)}")
        fmt = keypoint_format(name)
        z_up(up or fmt.up)  # a known axis
        if objective not in SCORES:
            raise ConfigError(f"a captured frame gives {', '.join(SCORES)}, not objective "
                              f"{objective}")
    except ErgohandoverError as exc:
        raise ConfigError(f"answer_format = {text!r}: {exc}") from None
    return fmt, up or fmt.up


class Refused(ErgohandoverError, ValueError):
    """An answer that is not one; the message is one line naming it and what is allowed."""


SCORE_NAMES = {"paper_postural": "paper postural", "reba": "REBA",
               "reba_ab": "REBA Table A + Table B", "rula": "RULA"}
"""Each objective as a practitioner names it at the prompt."""
DECIMAL_COMMA = re.compile(r"\d+,\d+")
"""A score typed with a decimal comma; no posture row has two values."""


def neutral_slope(body) -> float:
    """The clavicle slope at rest [deg] of ``body`` (a BodySpec; None: the 50th-percentile
    man's), which a captured frame's shoulder raise is measured from."""
    from ..capture.angles import NEUTRAL_CLAVICLE_DEG, clavicle_slope_deg

    return NEUTRAL_CLAVICLE_DEG if body is None else clavicle_slope_deg(body)


class AnswerReader:
    """Turns answer lines into scores of ``objective``; remembers a posture header line.

    Args:
        objective: what a score answer is (one of :data:`SCORE_RANGES`).
        scoring: the settings posture rows are scored with (``ergohandover score``'s defaults
            unless the session's evaluator says otherwise).
        header: the column names of posture rows, from an earlier header line (None: the
            contract's order).
        keypoints: the answer format ``keypoints:FORMAT[:UP]`` of captured frames (None:
            scores, x and posture rows).
        task: the Posture columns a captured frame cannot show, known from the session's task
            (the box's mass as ``load_kg``, ``coupling``, ``activity``).
        body: the session's worker, whose resting clavicle slope a captured frame's shoulder
            raise is measured from (None: the 50th-percentile man's).
    """

    def __init__(self, objective: str, scoring: ScoringSettings | None = None,
                 header: tuple[str, ...] | None = None, keypoints: str | None = None,
                 task: dict[str, float] | None = None, body=None):
        self.objective = objective
        self.lo, self.hi = SCORE_RANGES[objective]
        self.scoring = scoring or ScoringSettings()
        self.header = header
        self.keypoints = None if keypoints is None else frame_format(keypoints, objective)
        self.task = task or {}
        self.body = body

    def begin(self, previous: tuple | None) -> None:
        """A score does not depend on the handover before it (:class:`PreferenceReader`'s
        does)."""

    @property
    def prompt(self) -> str:
        if self.keypoints:
            return f"a {self.keypoints[0].name} frame, or 'x' if the worker cannot take it there: "
        return (f"score ({SCORE_NAMES[self.objective]} {self.lo}-{self.hi}), 'x' if the worker "
                "cannot take it there, or a posture CSV row: ")

    @property
    def expected(self) -> str:
        if self.keypoints:
            fmt = self.keypoints[0]
            return (f"a {fmt.name} frame ({3 * len(fmt.joints)} numbers: x, y, z of each of its "
                    f"{len(fmt.joints)} joints in metres), or x if the worker cannot take the "
                    "box there")
        return (f"a {SCORE_NAMES[self.objective]} score {self.lo}-{self.hi}, x if the worker "
                "cannot take the box there, or a posture CSV row")

    def read(self, line: str) -> Answer | None:
        """The answer of ``line``, or None for a posture header line (noted for the rows that
        follow); :class:`Refused` if it is not an answer."""
        text = line.strip()
        if not text:
            raise Refused(f"nothing typed: expected {self.expected}")
        if text.lower() in INFEASIBLE:
            return Answer(math.inf, "infeasible", text)
        if self.keypoints:
            return self._frame(text)
        if DECIMAL_COMMA.fullmatch(text):  # 7,5: a score with a decimal comma, not a row
            text = text.replace(",", ".")
        if "," in text:
            return self._posture(text)
        try:
            value = float(text)
        except ValueError:
            raise Refused(f"{text!r} is not an answer: expected {self.expected}") from None
        if not (math.isfinite(value) and self.lo <= value <= self.hi):
            raise Refused(f"{text!r} is outside {self.lo}-{self.hi}, the range of "
                          f"{SCORE_NAMES[self.objective]}: expected {self.expected}")
        return Answer(value, "score", text)

    def _posture(self, text: str) -> Answer | None:
        cells = [cell.strip() for cell in text.split(",")]
        if any(cell in POSTURE_COLUMNS for cell in cells):
            self.header = self._header(cells)
            return None
        columns = self.header or {len(REQUIRED_COLUMNS): REQUIRED_COLUMNS,
                                  len(POSTURE_COLUMNS): POSTURE_COLUMNS}.get(len(cells))
        if columns is None or len(columns) != len(cells):
            after = (f"the header line's {len(self.header)}" if self.header else
                     f"{len(REQUIRED_COLUMNS)} (the required Posture columns, in the contract's "
                     f"order) or {len(POSTURE_COLUMNS)} (all of them); or type a header line "
                     "first")
            raise Refused(f"a posture row of {len(cells)} values: expected {after}")
        try:
            _, posture = read_postures(io.StringIO(f"{','.join(columns)}\n{text}\n"),
                                       what="the posture row", radians=None)
        except (InputError, PostureError) as exc:
            raise Refused(str(exc)) from None
        return Answer(float(score_postures(posture, self.scoring)[self.objective][0]),
                      "posture", text, angles_of(posture))

    def _frame(self, text: str) -> Answer:
        from ..capture import capture, capture_scores
        from ..capture.bones import check_format
        from ..capture.checks import check_keypoints
        from ..capture.readers import Keypoints

        fmt, up = self.keypoints
        cells = [cell.strip() for cell in text.split(",")]
        try:
            values = np.array([float(cell) for cell in cells])
        except ValueError:
            raise Refused(f"{text[:40]!r} is not an answer: expected {self.expected}") from None
        if values.size != 3 * len(fmt.joints):
            raise Refused(f"a frame of {values.size} values: expected {self.expected}")
        points = values.reshape(1, len(fmt.joints), 3)
        try:
            frame = Keypoints(np.array([1]), points, fmt)
            check_format(frame, "the frame", "--answer-format keypoints:{}")
            check_keypoints(frame, up, "unseen", "the frame")
            captured = capture(points, fmt, up, self.task, neutral_slope(self.body))
        except ErgohandoverError as exc:
            raise Refused(str(exc)) from None
        scores = capture_scores(captured, self.scoring)
        low, high = scores[f"{self.objective}_lo"][0], scores[f"{self.objective}_hi"][0]
        unseen = dict(zip(POSTURE_COLUMNS, captured.unseen[0], strict=True))
        angles = {a: math.nan if unseen[a] else v for a, v in angles_of(captured.columns).items()}
        return Answer((low + high) / 2, "keypoints", text, angles)

    @staticmethod
    def _header(cells: list[str]) -> tuple[str, ...]:
        missing = [c for c in REQUIRED_COLUMNS if c not in cells]
        if missing:
            raise Refused(f"a posture header line without column {missing[0]!r} (required: "
                          f"{len(REQUIRED_COLUMNS)} columns, docs/architecture.md)")
        twice = sorted({c for c in cells if cells.count(c) > 1})
        if twice:
            raise Refused(f"a posture header line naming {twice[0]!r} twice")
        return tuple(cells)


PREFERENCES = {"better": -1.0, "b": -1.0, "worse": 1.0, "w": 1.0, "same": 0.0, "s": 0.0}
"""What a handover compared with the one before it may be called, and the answer it is
(:mod:`~ergohandover.search.preferences`: BETTER, WORSE, SAME)."""


class PreferenceReader:
    """Turns answer lines into preferences: this handover against the last feasible one before
    it (:meth:`begin` says which that is), ``ok`` for the first, ``x`` where the worker could
    not take the box."""

    header = None

    def __init__(self):
        self.previous: tuple | None = None

    def begin(self, previous: tuple | None) -> None:
        """The trial this proposal is compared with: ``Proposal.previous`` (number, cell,
        location; None: nothing before)."""
        self.previous = previous

    @property
    def prompt(self) -> str:
        if self.previous is None:
            return "'ok' once the handover is done, or 'x' if the worker cannot take it there: "
        return (f"better, worse or same than trial {self.previous[0]}'s handover, or 'x' if "
                "the worker cannot take it there: ")

    @property
    def expected(self) -> str:
        if self.previous is None:
            return "ok (the first handover: nothing to compare it with), or x"
        return (f"better, worse or same (b, w, s): this handover against trial "
                f"{self.previous[0]}'s, or x if the worker cannot take the box there")

    def read(self, line: str) -> Answer:
        text = line.strip()
        word = text.lower()
        if word in INFEASIBLE:
            return Answer(math.inf, "infeasible", text)
        if self.previous is None and word == "ok":
            return Answer(0.0, "first", text)
        if self.previous is not None and word in PREFERENCES:
            return Answer(PREFERENCES[word], "preference", text)
        shown = repr(text) if text else "nothing typed"
        raise Refused(f"{shown} is not an answer: expected {self.expected}")
