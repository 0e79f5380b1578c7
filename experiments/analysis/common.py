"""Shared by the figure scripts: paths, reading results (figures never recompute), and the rules
every figure follows.

The scores (the paper's postural score, REBA, RULA) are small integers and most groups hold
5-10 values, so a box plot often collapses into a line. The rules, checked in :func:`save`:

- :func:`plot_kind` picks the plot of a panel: counts per value where the values take few
  levels, a box only where it summarises more than its dots show;
- :func:`integer_axis` gives an axis of integer values integer ticks and limits that keep a
  constant panel from getting fractional ones;
- every figure states N in its title or caption (:data:`N_PATTERN`);
- a share of a landscape's points says what it is a share of: :func:`share_of_grid` (all the
  grid's points, infeasible ones included) or :func:`share_of_feasible`.

A reader has the figure, not the code: panels, legends and ticks name scores, workers and
targets in words (:data:`SCORE_WORDS`, :func:`worker_words`), not by the results' column
names. :func:`save` writes what each panel shows into the PNG (:func:`panel_records`: its
texts and a fingerprint of its data), so that a test can read from the file that its words are
a reader's and that no two panels draw the same data.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import sys
import textwrap
from collections.abc import Iterable
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.collections import Collection
from matplotlib.image import AxesImage
from matplotlib.lines import Line2D
from matplotlib.patches import Rectangle
from matplotlib.ticker import MaxNLocator, NullLocator

from ergohandover.io.atomic import atomic_write

ROOT = Path(__file__).resolve().parents[2]
# run_all --quick points the scripts at results/quick and paper_figs/quick.
RESULTS = Path(os.environ.get("ERGOHANDOVER_RESULTS", ROOT / "results"))
FIGURES = Path(os.environ.get("ERGOHANDOVER_FIGURES", ROOT / "paper_figs"))

N_PATTERN = re.compile(r"\bN = \d[\d,]*")
# An integer axis is marked on the Axis artist itself, so the check in save() needs no
# bookkeeping beside the figure.
INTEGER = "integer"
# A box needs values to summarise: with fewer than 5 its quartiles are the values themselves.
BOX_MIN_VALUES = 5
# ... and distinct values: on fewer levels the quartiles land on the levels and the box is
# drawn as one or two lines.
BOX_MIN_LEVELS = 5
# Up to this many distinct values in a panel, how many runs sit at each value is the whole
# story, and a count says it exactly.
COUNT_MAX_LEVELS = 6
# Seeded, so a rerun on the same results writes the same bytes.
SEED = 20240611


def read(relative: str) -> pd.DataFrame:
    """A results CSV; a missing one ends the script with a one-line message."""
    path = RESULTS / relative
    if not path.exists():
        sys.exit(f"missing {path}: run python experiments/run_all.py first")
    return pd.read_csv(path, keep_default_na=False, na_values=[""])


# --- what a panel shows -------------------------------------------------------------------


def box_informs(values: Iterable[float]) -> bool:
    """Whether a box of ``values`` says more than the values drawn as dots (see the limits)."""
    values = pd.Series(list(values), dtype=float).dropna()
    return len(values) >= BOX_MIN_VALUES and values.nunique() >= BOX_MIN_LEVELS


def plot_kind(values: Iterable[float], groups: Iterable | None = None) -> str:
    """How to draw a panel of ``values`` (one group per box, ``groups`` their keys):

    - ``"counts"``: at most :data:`COUNT_MAX_LEVELS` distinct values (all equal included):
      draw how many values sit at each level;
    - ``"box"``: every group's box informs (:func:`box_informs`): boxes with the dots over them;
    - ``"strip"``: otherwise, the dots alone (jittered by :func:`jitter`).
    """
    values = pd.Series(list(values), dtype=float)
    if values.dropna().nunique() <= COUNT_MAX_LEVELS:
        return "counts"
    keys = pd.Series(list(groups)) if groups is not None else pd.Series(0, index=values.index)
    if len(keys) != len(values):
        raise ValueError(f"{len(values)} values but {len(keys)} group keys")
    informs = values.groupby(keys.to_numpy(), sort=False).apply(box_informs)
    return "box" if bool(informs.all()) else "strip"


def is_integral(values: Iterable[float]) -> bool:
    """Whether every (finite) value is a whole number: the axis then gets integer ticks."""
    values = np.asarray(list(values), dtype=float)
    values = values[np.isfinite(values)]
    return values.size > 0 and bool(np.all(values == np.round(values)))


def integer_limits(values: Iterable[float], pad: float = 0.5, span: float = 2.0):
    """Axis limits around integer ``values``: ``pad`` either side, at least ``span`` wide (so a
    constant panel shows the next value too and its ticks stay integers)."""
    values = np.asarray(list(values), dtype=float)
    values = values[np.isfinite(values)]
    low, high = float(values.min()) - pad, float(values.max()) + pad
    return low, max(high, low + span)


def integer_axis(ax, axis: str = "y", values: Iterable[float] | None = None,
                 pad: float = 0.5) -> None:
    """Integer tick locations on ``ax``'s ``axis`` ("x" or "y"); with ``values``, limits from
    :func:`integer_limits`. Marks the axis, so that :func:`save` checks its ticks."""
    target = ax.yaxis if axis == "y" else ax.xaxis
    target.set_major_locator(MaxNLocator(integer=True))
    target.set_minor_locator(NullLocator())
    target.set_gid(INTEGER)
    if values is not None:
        (ax.set_ylim if axis == "y" else ax.set_xlim)(*integer_limits(values, pad))


def jitter(n: int, width: float = 0.25, seed: int = SEED) -> np.ndarray:
    """``n`` offsets in [-width/2, width/2], the same on every run (seeded)."""
    return np.random.default_rng(seed).uniform(-width / 2, width / 2, n)


def box_and_dots(ax, x: float, values: Iterable[float], colour, width: float,
                 seed: int = SEED) -> None:
    """One group at ``x``: its values as dots with seeded horizontal jitter, and a box behind
    them only where it informs (:func:`box_informs`)."""
    values = np.asarray(list(values), dtype=float)
    values = values[np.isfinite(values)]
    if values.size == 0:
        return
    if box_informs(values):
        ax.boxplot([values], positions=[x], widths=width * 0.9, showfliers=False,
                   patch_artist=True, manage_ticks=False, zorder=2,
                   boxprops={"facecolor": colour, "alpha": 0.35, "linewidth": 0.8},
                   medianprops={"color": "black", "linewidth": 1.0},
                   whiskerprops={"linewidth": 0.8}, capprops={"linewidth": 0.8})
    ax.scatter(x + jitter(values.size, width * 0.7, seed), values, s=9, color=colour,
               edgecolor="black", linewidth=0.3, zorder=3)


# --- words -------------------------------------------------------------------------------


def percent(fraction: float, digits: int = 3) -> str:
    """``0.00712`` -> ``"0.712 %"``: at most ``digits`` significant digits (trailing zeros
    dropped), never scientific notation."""
    value = 100 * float(fraction)
    if value == 0:
        return "0 %"
    decimals = max(0, digits - 1 - int(np.floor(np.log10(abs(value)))))
    text = f"{value:.{decimals}f}"
    return (text.rstrip("0").rstrip(".") if "." in text else text) + " %"


def share_of_grid(fraction: float, digits: int = 3) -> str:
    """A share of all the grid's points, infeasible ones included (targets.csv ``fraction``;
    stats.csv ``feasible_fraction``)."""
    return f"{percent(fraction, digits)} of the grid"


def share_of_feasible(fraction: float, digits: int = 3) -> str:
    """A share of the grid's feasible points (stats.csv and variants.csv ``fraction_at_min``,
    distribution.csv ``fraction``)."""
    return f"{percent(fraction, digits)} of the feasible points"


# The results' score columns, in the words a reader of the paper knows ("paper score": the
# paper's own postural score).
SCORE_WORDS = {"paper_postural": "paper score", "reba": "REBA",
               "reba_ab": "REBA Table A + Table B", "rula": "RULA"}
# What "REBA Table A + Table B" is, for a caption beside it.
REBA_AB_NOTE = ("REBA Table A + Table B: REBA's trunk-neck-legs score (Table A) plus its "
                "arms score (Table B), added before REBA's Table C merges them into fewer "
                "levels")


def worker_words(name: str) -> str:
    """``"p5-female"`` -> ``"5th-percentile woman"``; a name of another form as it is."""
    match = re.fullmatch(r"p(\d+)-(female|male)", name)
    if not match:
        return name
    n = int(match[1])
    suffix = "th" if 10 <= n % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(n % 10, "th")
    return f"{n}{suffix}-percentile {'woman' if match[2] == 'female' else 'man'}"


def n_text(counts: Iterable[int], unit: str) -> str:
    """``"N = 10 runs per box"``, or ``"N = 8–10 ..."`` where the groups differ in size."""
    counts = [int(c) for c in counts]
    low, high = min(counts), max(counts)
    return f"N = {low:,} {unit}" if low == high else f"N = {low:,}–{high:,} {unit}"


def caption(fig, text: str, width: int = 150) -> None:
    """A caption under everything drawn so far (kept by the tight bounding box when saved):
    call it after the layout is final."""
    bottom = fig.get_tightbbox(fig.canvas.get_renderer()).y0 / fig.get_figheight()
    fig.text(0.5, min(0.0, bottom) - 0.01, textwrap.fill(text, width), ha="center", va="top",
             fontsize=8)


# --- checks and saving ---------------------------------------------------------------------


def figure_texts(fig) -> list[str]:
    """The figure's title, captions and every panel's titles: where N must be stated."""
    texts = [fig.get_suptitle(), *(t.get_text() for t in fig.texts)]
    texts += [ax.get_title(loc) for ax in fig.axes if ax.get_visible()
              for loc in ("left", "center", "right")]
    return [t for t in texts if t]


def integer_ticks(fig) -> dict[str, list[float]]:
    """Each integer axis's tick locations within its limits, named by panel and axis."""
    found = {}
    for k, ax in enumerate(fig.axes):
        if not ax.get_visible():
            continue
        for name, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            if axis.get_gid() != INTEGER:
                continue
            low, high = sorted(axis.get_view_interval())
            ticks = np.asarray(axis.get_majorticklocs(), dtype=float)
            inside = ticks[(ticks >= low - 1e-9) & (ticks <= high + 1e-9)]
            found[f"{k}:{ax.get_title()[:40]}:{name}"] = [float(t) for t in inside]
    return found


def panel_data(ax) -> str | None:
    """A fingerprint of the data a panel draws (lines, markers, bars, bands, images), or None
    for a panel that draws none: two panels with the same fingerprint show the same thing."""
    parts = []
    for artist in ax.get_children():
        if not artist.get_visible():
            continue
        if isinstance(artist, Line2D):
            parts.append(np.asarray(artist.get_xydata(), dtype=float))
        elif isinstance(artist, Collection):
            parts.append(np.asarray(artist.get_offsets(), dtype=float))
            parts += [np.asarray(path.vertices, dtype=float) for path in artist.get_paths()]
        elif isinstance(artist, Rectangle) and artist is not ax.patch:
            parts.append(np.array([*artist.get_xy(), artist.get_width(), artist.get_height()]))
        elif isinstance(artist, AxesImage):
            parts.append(np.asarray(artist.get_array(), dtype=float))
    if not parts:
        return None
    digest = hashlib.sha1()
    for part in parts:
        digest.update(np.round(np.nan_to_num(part.ravel()), 9).tobytes())
    return digest.hexdigest()[:16]


def legend_texts(legend) -> list[str]:
    return [] if legend is None else [t.get_text() for t in legend.get_texts()]


def panel_records(fig) -> list[dict]:
    """What a reader sees of each visible panel: its titles, axis labels, tick labels, legend
    entries and texts drawn in it, and :func:`panel_data`."""
    records = []
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        records.append({
            "title": " | ".join(t for t in (ax.get_title(loc) for loc in
                                            ("left", "center", "right")) if t),
            "xlabel": ax.get_xlabel(), "ylabel": ax.get_ylabel(),
            "xticks": [t.get_text() for t in ax.get_xticklabels() if t.get_text()],
            "yticks": [t.get_text() for t in ax.get_yticklabels() if t.get_text()],
            "legend": legend_texts(ax.get_legend()),
            "texts": [t.get_text() for t in ax.texts if t.get_text()],
            "data": panel_data(ax)})
    return records


def problems(fig) -> list[str]:
    """What keeps a figure from being saved: no N in its texts; an integer axis with a
    fractional tick or none at all."""
    found = [] if any(N_PATTERN.search(t) for t in figure_texts(fig)) else [
        "no 'N = ...' in the figure's title, captions or panel titles"]
    for axis, ticks in integer_ticks(fig).items():
        if not ticks or any(t != round(t) for t in ticks):
            found.append(f"integer axis {axis} has ticks {ticks}")
    return found


def save(fig, name: str, tight: bool = True) -> Path:
    """Write a figure into the figures folder atomically and close it, after the checks of
    :func:`problems`. The PNG carries its texts, integer ticks and panels
    (:func:`panel_records`) as metadata, so that a test reads them from the file that was
    written."""
    try:
        fig.canvas.draw()  # the ticks as drawn: limits and locators settle in a draw
        found = problems(fig)
        if found:
            raise ValueError(f"{name}: " + "; ".join(found))
        metadata = {"Description": "\n".join(figure_texts(fig)),
                    "Comment": json.dumps({
                        "integer_ticks": integer_ticks(fig), "panels": panel_records(fig),
                        "legends": [legend_texts(legend) for legend in fig.legends]},
                        sort_keys=True)}
        FIGURES.mkdir(parents=True, exist_ok=True)
        path = atomic_write(FIGURES / name, lambda h: fig.savefig(
            h, format="png", dpi=130, bbox_inches="tight" if tight else None,
            metadata=metadata), binary=True)
    finally:
        plt.close(fig)
    print(f"wrote {path}")
    return path
