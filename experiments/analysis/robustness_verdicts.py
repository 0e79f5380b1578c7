"""Which of the robustness part's comparisons hold, and under which error model the optimum
measures worse than a shortest-distance location, in words, from results/robustness/ only:
the README's and the report's robustness text and the headline rules share them."""

from __future__ import annotations

import pandas as pd

MEASURED = "IMU (Schall et al. 2016)"
"""The measured error model of the headline (``error_model`` in the measured_*.csv)."""


def shortest(comparisons, score: str | None = None) -> pd.DataFrame:
    """The nominal optimum against each start's shortest-distance location, for one score (or
    every score)."""
    rows = comparisons[(comparisons["a"] == "nominal optimum")
                       & comparisons["b"].str.startswith("shortest")]
    return rows if score is None else rows[rows["score"] == score]


def optimum_measured(measured) -> pd.Series:
    """The nominal optimum's paper score under the headline model (measured_locations.csv)."""
    rows = headline_model(measured)["locations"]
    return rows[rows["score"] == "paper_postural"].set_index("location").loc["nominal optimum"]


def headline_model(measured) -> dict[str, pd.DataFrame]:
    """The measured tables' rows of the headline model (:data:`MEASURED`)."""
    return {name: table[table["error_model"] == MEASURED] for name, table in measured.items()}


def kept(rows) -> str:
    """``5 of 5``: how many comparisons survive."""
    return f"{int(rows['survives'].sum())} of {len(rows)}"


REVERSAL_SCORES = {"paper_postural": "paper score", "reba": "REBA", "rula": "RULA"}
MODEL_PHRASES = {MEASURED: "with the IMU-like error",
                 "IMU, uncorrelated": "with the IMU-like error uncorrelated",
                 "IMU, SDs ×0.5": "with the IMU-like SDs halved",
                 "IMU, SDs ×1.5": "with the IMU-like SDs ×1.5"}
"""How a reversing condition names each IMU-like error model (4 of its 15 SDs measured, the
rest of it assumed: results/robustness/measured_error.csv says which)."""


def _listed(items: list[str]) -> str:
    """``a``, ``a and b``, ``a, b and c``."""
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


def reversal_clauses(comparisons, measured) -> list[str]:
    """Every error model under which the nominal optimum measures worse than a shortest-
    distance location (the whole interval above zero), one clause per score and set of starts:
    ``RULA worse from start 1 at 1°, 2° and 5° on every angle``. The stress test's SDs come
    first, then the measured model and its variants."""
    rows = pd.concat([
        comparisons[comparisons["perturbation"] == "posture error"].assign(
            condition=lambda f: f["angle_sd_deg"].map(lambda sd: f"{sd:g}°"), kind=0),
        measured["comparisons"].assign(
            condition=lambda f: f["error_model"].map(lambda m: MODEL_PHRASES.get(m, m)),
            kind=1)], ignore_index=True)
    worse = shortest(rows)
    worse = worse[worse["ci_low"] > 0]
    clauses = []
    for score, label in REVERSAL_SCORES.items():
        mine = worse[worse["score"] == score]
        starts = mine.groupby(["kind", "condition"], sort=False)["b"].agg(_starts)
        by_starts: dict[str, list[tuple[int, str]]] = {}
        for (kind, condition), where in starts.items():
            by_starts.setdefault(where, []).append((kind, condition))
        for where, conditions in by_starts.items():
            stress = [c for k, c in conditions if k == 0]
            said = ([f"at {_listed(stress)} on every angle"] if stress else []) + [
                c for k, c in conditions if k == 1]
            plural = "s" if "," in where else ""
            clauses.append(f"{label} worse from start{plural} {where} {_listed(said)}")
    return clauses


def _starts(locations) -> str:
    """``1, 2``: the start numbers of shortest-distance locations (``b`` of comparisons)."""
    return ", ".join(b.rsplit(" ", 1)[1] for b in locations)


def start_verdicts(rows) -> str:
    """One score's comparisons with the 5 shortest-distance locations in words: better from
    all, or from which starts it is worse (with the differences), no different and better."""
    better, worse = rows[rows["survives"]], rows[rows["ci_low"] > 0]
    if len(better) == len(rows):
        return f"better from {len(rows)} of {len(rows)}"
    same = rows[~rows["survives"] & (rows["ci_low"] <= 0)]
    parts = []
    if len(worse):
        low, high = worse["difference"].min(), worse["difference"].max()
        size = f"{low:+.2f}" if len(worse) == 1 else f"{low:+.2f} to {high:+.2f}"
        parts.append(f"worse from start{'s' if len(worse) > 1 else ''} {_starts(worse['b'])} "
                     f"({size})")
    if len(same):
        parts.append(f"not distinguishable from {_starts(same['b'])}")
    if len(better):
        parts.append(f"better from {_starts(better['b'])}")
    return ", ".join(parts)


def measured_verdicts(measured) -> str:
    """The optimum against the shortest-distance locations under the measured error, per
    score."""
    imu = headline_model(measured)["comparisons"]
    return (f"on the paper score it is {start_verdicts(shortest(imu, 'paper_postural'))}, on "
            f"REBA {start_verdicts(shortest(imu, 'reba'))} and on RULA "
            f"{start_verdicts(shortest(imu, 'rula'))}")


def measured_counts(measured) -> str:
    """How many starts the optimum beats under the measured error, per score, with the starts
    it cannot be told from on the paper score."""
    imu = headline_model(measured)["comparisons"]
    paper = shortest(imu, "paper_postural")
    unclear = paper[~paper["survives"] & (paper["ci_low"] <= 0)]
    better = lambda rows: int(rows["survives"].sum())  # noqa: E731
    return (f"against the shortest-distance location of each of the {len(paper)} starts it is "
            f"better on REBA from {better(shortest(imu, 'reba'))} and on RULA from "
            f"{better(shortest(imu, 'rula'))}, but on the paper score from only "
            f"{better(paper)}" + (f" (not distinguishable from {len(unclear)})" if len(unclear)
                                  else ""))
