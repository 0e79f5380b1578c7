"""The study's section ``capture``: how well each keypoint format measures the twin, and the
hash of the capture layer's code its results follow from."""

from __future__ import annotations

import dataclasses
import hashlib
from pathlib import Path

from ..typed_json import setting


@dataclasses.dataclass(frozen=True)
class CaptureConfig:
    """How well each keypoint format measures the twin (:mod:`.accuracy`): the twin's
    postures at ``postures`` locations drawn (seeded) from the landscape's feasible ones, each
    measured ``draws`` times at every angle error SD of ``angle_sds``: 3.5° for pose models
    trained on ergonomics data (VEHS-7M; Wen et al. 2025), 15° the median RMSE of markerless
    joint angles against optical motion capture (46 people; Wang, Fethke & Baek)."""

    postures: int = setting(1000, lo=1)
    angle_sds: tuple[float, ...] = setting((0.0, 3.5, 15.0), lo=0, unit="deg")
    draws: int = setting(20, lo=1)
    seed: int = setting(40, lo=0)


def capture_code_version() -> str:
    """A hash of the capture layer's source (the capture part's results follow from it)."""
    from ... import capture

    digest = hashlib.sha256()
    for path in sorted(Path(capture.__file__).parent.glob("*.py")):
        digest.update(path.name.encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]
