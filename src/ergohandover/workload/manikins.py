"""The standard boundary manikins of workplace design — the 5th-percentile woman, the 50th
woman, the 50th man and the 95th man — as named bodies of the twin's ANSUR II model.

Each is the named percentile of :data:`~ergohandover.twin.anthropometry.PERCENTILES`: stature
and mass at one percentile of the survey's sex (the design convention that a "5th-percentile
woman" is small in both, not a multivariate percentile), every other measurement the body
model's mean given those two. Tools built on other surveys size theirs differently (3DSSPP's
5th-percentile woman is 151.4 cm and 50.8 kg, its 95th-percentile man 188.3 cm and 125.0 kg:
its source's AnthroPercentiles.h), so a manikin's scores are this survey's.
"""

from __future__ import annotations

from ..twin.anthropometry import BodySpec

MANIKINS = {"f05": "p5-female", "f50": "p50-female", "m50": "p50-male", "m95": "p95-male"}
"""Manikin name -> the named ANSUR II percentile it is."""


def manikin(name: str) -> BodySpec:
    """The body of manikin ``name`` (one of :data:`MANIKINS`)."""
    return BodySpec.from_percentile(MANIKINS[name])
