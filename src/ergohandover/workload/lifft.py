"""The low back's daily dose of repeated lifting: the Lifting Fatigue Failure Tool (LiFFT).

LiFFT (Gallagher, Sesek, Schall & Huangfu 2017, Appl Ergon 63:142) treats the lumbar spine as a
material that fails by fatigue: each lift does damage that grows exponentially with its peak
load moment (PLM: the load's weight times its horizontal distance from L5/S1), the day's
damages add up (Miner's rule) to a **cumulative damage**, and a logistic model turns its
logarithm into the **probability that the job is a high-risk one** (12 or more low-back
injuries per 200,000 hours worked, in the authors' validation jobs).

The constants are those of the authors' calculator (LiFFT workbook v1.4.0, 06/05/2018, as
transcribed in nbarr1/ErgonomicTool, methods/lifft/): damage per lift
10^(−5.8164 + 0.022288 · PLM[ft·lb]), the same line as e^(0.038 · PLM[N·m] + 0.32)/902,416;
risk e^Y/(1 + e^Y) with Y = 1.7229 + 1.0239 · log10(cumulative damage). The published article
prints neither the regression nor the logistic coefficients.

A handover is a lift whose load the worker takes at the hands' reach: its PLM is the box's
weight times how far forward of L5/S1 the hands hold it (:func:`~.back.grip_reach_m`).
"""

from __future__ import annotations

import numpy as np

from ..twin.anthropometry import GRAVITY

DAMAGE_LOG10 = (-5.81636221052493, 0.0222878437409416)
"""log10 of the damage of one lift: intercept and slope per ft·lb of peak load moment."""
RISK_LOGIT = (1.7229, 1.0239)
"""The high-risk job's log-odds: intercept and slope per log10 of the cumulative damage."""
NM_PER_FT_LB = 1.3558179483314004
"""One foot-pound [N m]."""


def peak_load_moment_nm(load_kg, reach_m) -> np.ndarray:
    """The load's weight times its horizontal distance forward of L5/S1 [N m]."""
    return np.asarray(load_kg, dtype=float) * GRAVITY * np.abs(np.asarray(reach_m, float))


def damage_per_lift(plm_nm) -> np.ndarray:
    """The spine's fatigue damage of one lift at a peak load moment [N m] (a share of its
    life: 1 is failure)."""
    intercept, slope = DAMAGE_LOG10
    return 10.0 ** (intercept + slope * np.asarray(plm_nm, dtype=float) / NM_PER_FT_LB)


def daily_dose(plm_nm, lifts) -> np.ndarray:
    """A day's cumulative damage of ``lifts`` lifts at each peak load moment."""
    return damage_per_lift(plm_nm) * np.asarray(lifts, dtype=float)


def high_risk_probability(dose) -> np.ndarray:
    """The probability that a job of this daily cumulative damage is a high-risk job."""
    intercept, slope = RISK_LOGIT
    y = intercept + slope * np.log10(np.asarray(dose, dtype=float))
    return 1.0 / (1.0 + np.exp(-y))
