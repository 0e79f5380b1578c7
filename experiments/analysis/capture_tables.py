"""The capture part's blocks, from results/capture/ only: the README's sentence on what a
captured posture's scores can say, and the report's tables of what each keypoint format measures
and how often REBA, RULA and the paper's score come out right from it.
``python capture_tables.py`` rewrites them after the study."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
from readme_blocks import rewrite

TITLES = {"h36m17": "H36M-17", "coco17": "COCO-17", "mediapipe33": "MediaPipe-33",
          "zed34": "ZED BODY_34", "smpl24": "SMPL-24"}
SCORE_NAMES = {"reba": "REBA", "rula": "RULA", "paper_postural": "paper"}
SOURCES = {3.5: "a pose model trained on ergonomics data, VEHS-7M (Wen et al. 2025)",
           15.0: "markerless against optical motion capture, median over 46 people (Wang, "
                 "Fethke & Baek)"}
"""Where each published angle error of the study's config comes from."""


def _read(results: Path) -> tuple[pd.DataFrame, pd.DataFrame, dict]:
    folder = results / "capture"
    return (pd.read_csv(folder / "columns.csv"), pd.read_csv(folder / "scores.csv"),
            json.loads((folder / "manifest.json").read_text()))


def _pct(value: float) -> str:
    return f"{100 * value:.0f} %"


def claim(results: Path) -> str:
    """The README's sentence: how wide REBA's interval is without error, and how often the
    paper's score (which reads no wrist or shoulder girdle) comes out right from ZED BODY_34
    keypoints at each published error."""
    _, scores, manifest = _read(results)
    by = scores.set_index(["score", "format", "angle_sd_deg"])
    widths = by.loc[("reba", slice(None), 0.0), "mean_width"]
    errors = sorted(sd for sd in scores["angle_sd_deg"].unique() if sd > 0)
    paper = [by.loc[("paper_postural", "zed34", sd)] for sd in errors]
    at = " and ".join(f"{_pct(r['right'])} ({100 * r['right_ci_low']:.0f}–"
                      f"{_pct(r['right_ci_high'])}) with {sd:g}°" for r, sd in zip(
                          paper, errors, strict=True))
    return (f"no common keypoint format pins REBA at a handover: each leaves the wrists or the "
            f"shoulder girdle unseen (ZED's SDK holds them rigid), so REBA comes as an interval, "
            f"{widths.min():.1f}–{widths.max():.1f} points wide on average over "
            f"{manifest['postures']:,} of the twin's handover postures; the paper's score, which "
            f"reads neither, comes out right from ZED BODY_34 keypoints in {at} of error on "
            "every measured angle")


def measured_table(results: Path) -> list[str]:
    """Per format: the columns it measures in every posture, in some, never; and how far the
    mid-hip to mid-shoulder trunk lies from the twin's."""
    columns, _, _ = _read(results)
    lines = ["| format | measured in every posture | in some (where the elbow is bent) | "
             "unseen | largest error where measured [deg] |", "|---|---|---|---|---|"]
    for name, group in columns.groupby("format", sort=False):
        sides = group.assign(column=group["column"].str.replace(r"^(left|right)_", "", regex=True))
        share = sides.groupby("column", sort=False)["measured"].min()
        worst = sides.groupby("column", sort=False)["max_error_deg"].max()
        always = [c for c in share.index if share[c] == 1]
        some = [c for c in share.index if 0 < share[c] < 1]
        never = [c for c in share.index if share[c] == 0]
        errors = worst.dropna()
        largest = (f"{errors.max():.1f} ({errors.idxmax().replace('_', ' ')})"
                   if errors.max() >= 0.05 else "< 0.05 (the twin's own)")
        lines.append(f"| {TITLES[name]} | {len(always)} of {len(share)} | "
                     f"{', '.join(some) or '–'} | {', '.join(never) or '–'} | {largest} |")
    return lines


def accuracy_table(results: Path) -> list[str]:
    """Per format and angle error: right (and holds) for each score, with 95 % intervals."""
    _, scores, manifest = _read(results)
    names = list(SCORE_NAMES)
    lines = ["| format | angle error SD [deg] | " + " | ".join(
        f"{SCORE_NAMES[s]} right (holds)" for s in names) + " | REBA interval width |",
             "|---|---|" + "---|" * (len(names) + 1)]
    for (name, sd), group in scores.groupby(["format", "angle_sd_deg"], sort=False):
        by = group.set_index("score")
        cells = [f"{_pct(by.loc[s, 'right'])} [{_pct(by.loc[s, 'right_ci_low'])}, "
                 f"{_pct(by.loc[s, 'right_ci_high'])}] ({_pct(by.loc[s, 'holds'])})"
                 for s in names]
        lines.append(f"| {TITLES[name]} | {sd:g} | {' | '.join(cells)} | "
                     f"{by.loc['reba', 'mean_width']:.2f} |")
    sources = "; ".join(f"{sd:g}°: {text}" for sd, text in SOURCES.items())
    return [*lines, "", f"N = {manifest['postures']:,} postures, each measured "
            f"{int(scores['draws'].iloc[0])} times per error; [95 % interval over postures]; "
            f"right: the score is one value and the error-free twin's; holds: its interval "
            f"holds that. Errors: {sources}."]


def blocks(results: Path) -> dict[str, str]:
    """Each generated block's text, from ``results``/capture/ only."""
    text = claim(results)
    return {"capture-claim": text[0].upper() + text[1:] + ".",
            "capture-measured": "\n" + "\n".join(measured_table(results)) + "\n",
            "capture-accuracy": "\n" + "\n".join(accuracy_table(results)) + "\n"}


def main() -> None:
    """Rewrite the capture blocks from results/ wherever each lives."""
    from common import RESULTS

    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
