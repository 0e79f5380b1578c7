"""OWAS: the Ovako Working posture Analysing System (Karhu, Kansi & Kuorinka 1977, *Applied
Ergonomics* 8:199-201).

A posture is a four-digit code — back, arms, legs, load — and the code's action category
(1 no action, 2 corrective action in the near future, 3 as soon as possible, 4 immediately)
comes from one 4 x 3 x 7 x 3 table. OWAS classifies by observation, not by angle; the angle
cut-offs below are what a table of measured angles needs, and they are stated as such:

* back bent: trunk flexion or extension beyond 20°; twisted: twist or side bend beyond 20°
  (the 20° of the OWAS training material, "Ovako Working Posture Assessment System" (1980),
  read as transcribed in a public slide deck);
* an arm above shoulder level: its flexion or abduction beyond 90° (the elbow above the
  shoulder, the same material's definition);
* knees bent: flexion beyond :data:`KNEE_BENT_DEG` (an assumption: no source read gives an
  angle); one leg: ``bilateral_support`` 0; seated: ``seated`` 1. Kneeling (6) and walking (7) are
  not in a posture table, so never given;
* load: up to 10 kg, up to 20 kg, above 20 kg.

The table is the one five independent public implementations agree on; three cells differ
in others (docs/workload.md lists them).
"""

from __future__ import annotations

import numpy as np

from ..ergonomics import Posture
from ..ergonomics.posture import SIDES

BENT_DEG = 20.0
"""Trunk flexion (either way), twist or side bend beyond which the back is bent or twisted."""
ARM_ABOVE_SHOULDER_DEG = 90.0
"""Upper-arm flexion or abduction beyond which the elbow is above the shoulder."""
KNEE_BENT_DEG = 20.0
"""Knee flexion beyond which a standing leg is bent: an assumption (OWAS's "knees bent" is
what an observer sees; the back's 20° is reused)."""
LOAD_EDGES_KG = (10.0, 20.0)
"""Load classes: up to 10 kg, up to 20 kg, above."""

# Rows: (back, arms) in order 11, 12, 13, 21, ..., 43; each row: legs 1-7, each with loads 1-3.
_ROWS = """
111 111 111 222 222 111 111
111 111 111 222 222 111 111
111 111 111 223 223 111 112
223 223 223 333 333 222 233
223 223 233 344 344 334 234
334 223 333 344 444 444 234
111 111 112 333 444 111 111
223 111 112 444 444 333 111
223 111 233 444 444 444 111
233 223 223 444 444 444 234
334 234 334 444 444 444 234
444 234 334 444 444 444 234
"""
TABLE = np.array([[[int(c) for c in group] for group in row.split()]
                  for row in _ROWS.split("\n") if row.strip()], dtype=np.int8).reshape(4, 3, 7, 3)
"""Action category by [back - 1, arms - 1, legs - 1, load - 1]."""

COLUMNS = ("owas_back", "owas_arms", "owas_legs", "owas_load", "owas_code", "owas")
"""The columns :func:`owas` gives: the four digits, the code (e.g. 2131) and the action
category ``owas``."""


def back(p: Posture) -> np.ndarray:
    """1 straight, 2 bent, 3 twisted or bent sideways, 4 bent and twisted."""
    bent = np.abs(p["trunk_flexion"]) > BENT_DEG
    twisted = (np.abs(p["trunk_twist"]) > BENT_DEG) | (np.abs(p["trunk_side_bend"]) > BENT_DEG)
    return np.where(bent & twisted, 4, np.where(twisted, 3, np.where(bent, 2, 1)))


def arms(p: Posture) -> np.ndarray:
    """1 both arms below shoulder level, 2 one above, 3 both above."""
    above = [(p.arm(side, "upper_arm_flexion") > ARM_ABOVE_SHOULDER_DEG)
             | (np.abs(p.arm(side, "upper_arm_abduction")) > ARM_ABOVE_SHOULDER_DEG)
             for side in SIDES]
    return 1 + above[0].astype(int) + above[1].astype(int)


def legs(p: Posture) -> np.ndarray:
    """1 sitting; standing on 2 straight legs 2, on 1 straight leg 3, on 2 bent legs 4, on 1
    bent leg 5."""
    bent = np.maximum(p["left_knee_flexion"], p["right_knee_flexion"]) > KNEE_BENT_DEG
    one_leg = p["bilateral_support"] == 0
    standing = np.where(bent, np.where(one_leg, 5, 4), np.where(one_leg, 3, 2))
    return np.where(p["seated"] == 1, 1, standing)


def load(p: Posture) -> np.ndarray:
    """1 up to 10 kg, 2 up to 20 kg, 3 above 20 kg."""
    return 1 + np.searchsorted(LOAD_EDGES_KG, p["load_kg"], side="left")


def owas(p: Posture) -> dict[str, np.ndarray]:
    """Every column of :data:`COLUMNS` for N postures (int16 arrays)."""
    digits = {"owas_back": back(p), "owas_arms": arms(p), "owas_legs": legs(p),
              "owas_load": load(p)}
    b, a, g, w = digits.values()
    code = 1000 * b + 100 * a + 10 * g + w
    category = TABLE[b - 1, a - 1, g - 1, w - 1]
    return {**{k: v.astype(np.int16) for k, v in digits.items()},
            "owas_code": code.astype(np.int16), "owas": category.astype(np.int16)}
