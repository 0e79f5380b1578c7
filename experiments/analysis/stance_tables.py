"""The stance part's blocks, from results/stance/ only: the README's headline cell and the
report's table of the headline comparison for a planted worker and for one who may step.
``python stance_tables.py`` rewrites them after the study."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
from readme_blocks import rewrite

NAMES = {"paper_postural": "paper", "reba": "REBA", "rula": "RULA"}
ERROR_SD = 5.0  # the posture error the headline quotes [deg] (an IMU's, as the robustness part)


def _read(results: Path) -> tuple[pd.DataFrame, pd.DataFrame, pd.DataFrame, dict]:
    folder = results / "stance"
    return (pd.read_csv(folder / "locations.csv", keep_default_na=False, na_values=[""]),
            pd.read_csv(folder / "headline.csv", keep_default_na=False, na_values=[""]),
            pd.read_csv(folder / "posture_error.csv"),
            json.loads((folder / "manifest.json").read_text()))


def span(values) -> str:
    """``4`` or ``2–7``: the range of whole values as the tables write it."""
    low, high = int(min(values)), int(max(values))
    return f"{low}" if low == high else f"{low}–{high}"


def default_rows(head: pd.DataFrame) -> pd.DataFrame:
    """The default worker's headline comparison (the learner's optimised location)."""
    return head[head["optimised_location"] == "optimised"]


def headline(results: Path) -> str:
    locations, head, errors, manifest = _read(results)
    mine = default_rows(head)
    paper = mine[mine["score"] == "paper_postural"].set_index("stance")
    survives = errors[(errors["score"] == "paper_postural")
                      & (errors["angle_sd_deg"] == ERROR_SD)].groupby("stance")["survives"]
    far = locations[(locations["location"] == "shortest distance")
                    & (locations["stance"] == "step")
                    & (locations["worker"] == mine["worker"].iloc[0])]
    step = paper.loc["step"]
    beats = mine.groupby(["stance", "score"])["beats"].sum().astype(int)
    parts = [f"when the worker may step toward the box, the optimised location "
             f"({int(step['optimised'].iloc[0])}) beats the shortest-distance one from "
             f"{int(step['beats'].sum())} of {len(step)} starts on the paper score ("
             f"{span(step['shortest_distance'])} there, after a step of "
             f"{span(100 * far['step_m'])} cm; planted "
             f"{span(paper.loc['fixed', 'shortest_distance'])}), and from "
             f"{int(survives.sum()['step'])} of {int(survives.count()['step'])} at "
             f"{ERROR_SD:g}° of posture error (95 % Monte Carlo intervals; planted "
             f"{int(survives.sum()['fixed'])}); but on "
             f"REBA from only {beats['step', 'reba']} and on RULA from {beats['step', 'rula']} "
             f"of {len(step)} (planted {beats['fixed', 'reba']} and {beats['fixed', 'rula']})"]
    others = head[(head["optimised_location"] == "own optimised") & (head["score"] == "reba")]
    if len(others):
        stepping = others[others["stance"] == "step"]
        planted = others[others["stance"] == "fixed"]
        parts.append(f"the other participants' own optimum still has the lower REBA in "
                     f"{int(stepping['beats'].sum())} of {len(stepping)} comparisons (planted "
                     f"{int(planted['beats'].sum())})")
    parts.append(f"the stepping worker's own optimum scores "
                 f"{manifest['stepping_optimum_score']}")
    return "; ".join(parts)


def table(results: Path) -> list[str]:
    """The default worker's locations, planted and stepping, and the comparison at 5°."""
    locations, head, errors, _ = _read(results)
    worker = default_rows(head)["worker"].iloc[0]
    mine = locations[locations["worker"] == worker]
    at = errors[(errors["angle_sd_deg"] == ERROR_SD) & (errors["score"] == "paper_postural")]
    lines = ["| location | planted: paper / REBA / RULA | stepping: paper / REBA / RULA "
             f"| step [cm] | optimised better at {ERROR_SD:g}° (planted / stepping) |",
             "|---|---|---|---|---|"]
    for (name, start), rows in mine.groupby(["location", "start"], sort=False, dropna=False):
        by = rows.set_index("stance")
        where = f"{name}{'' if pd.isna(start) else f', {start}'} ({by['x'].iloc[0]:.3f}, " \
                f"{by['y'].iloc[0]:.3f}, {by['z'].iloc[0]:.3f})"
        cells = [" / ".join(str(int(by.loc[s, k])) if by.loc[s, "feasible"] else "–"
                            for k in NAMES) for s in ("fixed", "step")]
        verdict = ""
        if name == "shortest distance":
            pair = at[at["start"] == start].set_index("stance")
            verdict = " / ".join(
                f"{pair.loc[s, 'difference']:+.2f} ({pair.loc[s, 'ci_low']:+.2f} to "
                f"{pair.loc[s, 'ci_high']:+.2f}) {'yes' if pair.loc[s, 'survives'] else 'no'}"
                for s in ("fixed", "step"))
        lines.append(f"| {where} | {cells[0]} | {cells[1]} | "
                     f"{100 * by.loc['step', 'step_m']:.0f} | {verdict} |")
    return lines


def blocks(results: Path) -> dict[str, str]:
    """Each generated block's text, from ``results``/stance/ only."""
    text = headline(results)
    return {"stance-headline": text, "stance-claim": text[0].upper() + text[1:] + ".",
            "stance-table": "\n" + "\n".join(table(results)) + "\n"}


def main() -> None:
    """Rewrite the stance blocks from results/ wherever each lives."""
    from common import RESULTS

    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
