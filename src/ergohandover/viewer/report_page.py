"""One printable HTML page per handover: the twin's picture, REBA, RULA, OWAS and the paper's
score with their items, the revised NIOSH lifting equation, the static back load and strength,
and the share of the study's workforce the location suits.

The page is self-contained (the picture is embedded), laid out for one A4 sheet, and every
number on it is also a cell of the CSV written beside it: each value's element carries the
column it shows (``data-column``), so a test can read the page back and compare.
"""

from __future__ import annotations

import base64
import html
import math
from collections.abc import Mapping

import numpy as np
import pandas as pd

REBA_ITEMS = ("reba_trunk", "reba_neck", "reba_legs", "reba_load", "reba_score_a",
              "reba_left_upper_arm", "reba_left_lower_arm", "reba_left_wrist",
              "reba_right_upper_arm", "reba_right_lower_arm", "reba_right_wrist",
              "reba_score_b", "reba_score_c", "reba_action_level")
RULA_ITEMS = ("rula_left_upper_arm", "rula_left_lower_arm", "rula_left_wrist",
              "rula_right_upper_arm", "rula_right_lower_arm", "rula_right_wrist",
              "rula_neck", "rula_trunk", "rula_legs", "rula_action_level")
OWAS_ITEMS = ("owas_back", "owas_arms", "owas_legs", "owas_load", "owas_code")
LIFT_ITEMS = ("niosh_h_cm", "niosh_v_cm", "niosh_d_cm", "niosh_a_deg", "niosh_hm",
              "niosh_vm", "niosh_dm", "niosh_am", "niosh_fm", "niosh_cm", "niosh_rwl_kg",
              "niosh_li")
BACK_ITEMS = ("back_moment_nm", "back_compression_n", "back_shear_n", "back_strength_share",
              "back_capable_pct", "shoulder_moment_nm", "elbow_moment_nm")
SHIFT_ITEMS = ("shift_capacity_end", "shift_failure_min", "shoulder_load_share",
               "shoulder_capacity_end", "elbow_load_share", "elbow_capacity_end",
               "trunk_load_share", "trunk_capacity_end", "lifft_dose", "lifft_high_risk")
ACCOMMODATION_ITEMS = ("exact_share", "exact_low", "exact_high", "measured_share",
                       "measured_low", "measured_high")
HEADLINE = ("reba", "rula", "owas", "paper_postural", "niosh_li", "back_compression_n",
            "measured_share")
PAGE_COLUMNS = tuple(dict.fromkeys((*HEADLINE, *REBA_ITEMS, *RULA_ITEMS, *OWAS_ITEMS,
                                    *LIFT_ITEMS, *BACK_ITEMS, *SHIFT_ITEMS,
                                    *ACCOMMODATION_ITEMS)))
"""Every column a page shows, in page order."""
LABELS = {
    "niosh_h_cm": "H, horizontal [cm]", "niosh_v_cm": "V, hand height [cm]",
    "niosh_d_cm": "D, travel [cm]", "niosh_a_deg": "A, asymmetry [°]",
    "niosh_hm": "HM", "niosh_vm": "VM", "niosh_dm": "DM", "niosh_am": "AM", "niosh_fm": "FM",
    "niosh_cm": "CM", "niosh_rwl_kg": "RWL [kg]", "niosh_li": "lifting index",
    "back_moment_nm": "L5/S1 moment [N m]", "back_compression_n": "L5/S1 compression [N]",
    "back_shear_n": "L5/S1 shear [N]", "back_strength_share": "share of mean back strength",
    "back_capable_pct": "% capable (back)", "shoulder_moment_nm": "shoulder moment [N m]",
    "elbow_moment_nm": "elbow moment [N m]", "exact_share": "suited, error-free",
    "exact_low": "  95 % interval, low", "exact_high": "  95 % interval, high",
    "measured_share": "suited, as measured", "measured_low": "  95 % interval, low",
    "measured_high": "  95 % interval, high",
    "shift_capacity_end": "weakest joint's capacity at the end",
    "shift_failure_min": "a joint first fails after [min]",
    "shoulder_load_share": "shoulder load [share of strength]",
    "shoulder_capacity_end": "  its capacity at the end", "elbow_load_share":
    "elbow load [share of strength]", "elbow_capacity_end": "  its capacity at the end",
    "trunk_load_share": "low back load [share of strength]",
    "trunk_capacity_end": "  its capacity at the end", "lifft_dose": "LiFFT daily dose",
    "lifft_high_risk": "LiFFT high-risk probability",
}
DECIMALS = {"niosh_h_cm": 1, "niosh_v_cm": 1, "niosh_d_cm": 1, "niosh_a_deg": 1,
            "niosh_rwl_kg": 2, "niosh_li": 2, "back_moment_nm": 1, "back_compression_n": 0,
            "back_shear_n": 0, "back_strength_share": 3, "back_capable_pct": 1,
            "shoulder_moment_nm": 1, "elbow_moment_nm": 1, "shift_failure_min": 1}
"""Decimals shown (and written to the CSV) per column."""
WHOLE = ("reba", "rula", "paper_", "owas", "back_band")
"""Columns (or prefixes) of whole numbers: scores, items, codes, bands."""

STYLE = """
@page { size: A4; margin: 12mm; }
body { font: 10.5px/1.35 "DejaVu Sans", Arial, sans-serif; color: #111; margin: 0; }
h1 { font-size: 16px; margin: 0 0 2px; } h2 { font-size: 11.5px; margin: 8px 0 3px; }
.sub { color: #444; margin-bottom: 6px; }
.grid { display: grid; grid-template-columns: 1fr 1fr; gap: 4px 16px; }
img { width: 100%; border: 1px solid #bbb; }
table { border-collapse: collapse; width: 100%; }
td { padding: 1px 4px; border-bottom: 1px solid #e3e3e3; }
td.v { text-align: right; font-variant-numeric: tabular-nums; }
.big td.v { font-weight: bold; font-size: 12px; }
.note { color: #555; font-size: 9px; margin-top: 6px; }
.flags { color: #a40000; font-weight: bold; margin: 4px 0; }
"""


def shown(column: str, value) -> str:
    """How a value is shown (and written to the CSV beside the page): scores, items and codes
    as whole numbers, the rest to :data:`DECIMALS` (3 when not listed)."""
    if isinstance(value, str):
        return value
    if value is None or pd.isna(value):
        return ""
    if isinstance(value, float) and math.isinf(value):
        return "never" if column.endswith("_failure_min") else "inf"
    if isinstance(value, (bool, np.bool_)) or (column not in DECIMALS and column.startswith(WHOLE)):
        return str(round(float(value)))
    return f"{float(value):.{DECIMALS.get(column, 3)}f}"


def _rows(row: Mapping, columns, labels: Mapping | None = None) -> str:
    cells = []
    for c in columns:
        if c not in row:
            continue
        # Items are listed under their method's heading: "trunk", not "reba trunk".
        plain = c.split("_", 1)[1] if c.startswith(("reba_", "rula_", "owas_")) else c
        label = html.escape((labels or LABELS).get(c, plain.replace("_", " ")))
        cells.append(f'<tr><td>{label}</td><td class="v" data-column="{c}">'
                     f"{html.escape(shown(c, row[c]))}</td></tr>")
    return "<table>" + "".join(cells) + "</table>"


def report_page(row: Mapping, title: str, subtitle: str, picture: bytes | None,
                notes: list[str], warnings: list[str] = (), why: str = "") -> str:
    """The page of one handover: ``row`` holds the Evaluation, workload and accommodation
    columns (shown as :func:`shown` writes them), ``picture`` the twin's PNG, ``warnings`` the
    row's flags (action limits exceeded, knife edges of cut-offs), shown above the scores;
    ``why``: why the workforce's shares are empty, said where they would be."""
    if why:
        warnings = [*warnings, f"no workforce share: {why}"]
    image = ("" if picture is None else '<img alt="the twin holding the box" src="data:image/'
             f'png;base64,{base64.b64encode(picture).decode()}">')
    headline = _rows(row, HEADLINE,
                     {"reba": "REBA", "rula": "RULA", "owas": "OWAS action category",
                      "paper_postural": "paper's postural score", "niosh_li": "lifting index",
                      "back_compression_n": "L5/S1 compression [N]",
                      "measured_share": "workforce suited, as measured"})
    parts = [
        f"<h1>{html.escape(title)}</h1><div class='sub'>{html.escape(subtitle)}</div>",
        "".join(f"<div class='flags' data-flag>⚠ {html.escape(w)}</div>" for w in warnings),
        f"<div class='grid'><div>{image}</div><div><h2>Scores</h2>"
        f"<div class='big'>{headline}</div></div></div>",
        "<div class='grid'>",
        f"<div><h2>REBA items</h2>{_rows(row, REBA_ITEMS)}</div>",
        f"<div><h2>RULA items</h2>{_rows(row, RULA_ITEMS)}"
        f"<h2>OWAS code</h2>{_rows(row, OWAS_ITEMS)}</div>",
        f"<div><h2>Revised NIOSH lifting equation</h2>{_rows(row, LIFT_ITEMS)}"
        f"<h2>Over a shift of handovers</h2>{_rows(row, SHIFT_ITEMS)}</div>",
        f"<div><h2>Back load and strength</h2>{_rows(row, BACK_ITEMS)}"
        f"<h2>The study's workforce at this location</h2>"
        + (f"<div class='why' data-why>{html.escape(why)}</div>" if why else
           _rows(row, ACCOMMODATION_ITEMS)) +
        "</div></div>",
        "".join(f"<div class='note'>{html.escape(n)}</div>" for n in notes),
    ]
    return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}"
            f"</title><style>{STYLE}</style></head><body>{''.join(parts)}</body></html>")
