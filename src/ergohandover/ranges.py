"""Declared ranges for frozen config dataclasses: one field helper, one check.

A field made with :func:`ranged` carries its help text and valid range (or choices) in its
metadata; :func:`check_ranges` (called from ``__post_init__``) rejects a value outside it with
a one-line message naming the field, the value and what is allowed. The same metadata feeds
``--help`` (:mod:`~ergohandover.config_cli`). Pure Python, so the numpy-only scoring engine can
use it.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any


def ranged(default: Any, help: str, lo: float | None = None, hi: float | None = None,
           unit: str = "", choices: tuple[str, ...] | None = None) -> Any:
    """A dataclass field with a default, help text and either a [lo, hi] range or choices."""
    meta: dict[str, Any] = {"help": help}
    if choices is not None:
        meta["choices"] = choices
    else:
        meta.update(lo=lo, hi=hi, unit=unit)
    return dataclasses.field(default=default, metadata=meta)


def check_ranges(obj: Any, error: type[Exception]) -> None:
    """Raise ``error`` for the first field of ``obj`` outside its declared range or choices."""
    for f in dataclasses.fields(obj):
        if "help" not in f.metadata:
            continue
        value = getattr(obj, f.name)
        if "choices" in f.metadata:
            if value not in f.metadata["choices"]:
                allowed = " or ".join(repr(c) for c in f.metadata["choices"])
                raise error(f"{f.name} = {value!r} is not allowed (use {allowed})")
            continue
        lo, hi, unit = f.metadata["lo"], f.metadata["hi"], f.metadata["unit"]
        if isinstance(value, bool) or not isinstance(value, int | float) or not (
                math.isfinite(value) and lo <= value <= hi):
            raise error(f"{f.name} = {value!r} is outside the valid range {lo:g}-{hi:g}"
                        + (f" {unit}" if unit else ""))
