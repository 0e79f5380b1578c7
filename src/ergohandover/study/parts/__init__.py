"""The study's parts, in run order. Each module has ``run(config, results, engine, force)``:
it runs the part (and the parts it reads, reused when finished) unless its manifest says it is
done, and returns whether it ran. ``experiments/run_all.py`` composes them (``--only PART``
runs one); nothing else does.
"""

from __future__ import annotations

import importlib
from types import ModuleType

PARTS = ("landscape", "learning", "baselines", "ablations", "participants", "population",
         "sensitivity", "validation", "robustness", "stance", "personalise", "capture", "people",
         "manikins", "accommodation")
"""Every part, in the order ``run_all`` runs them (a part after those it reads)."""


def part(name: str) -> ModuleType:
    """The module of part ``name`` (imported on first use: a part pulls in what it needs)."""
    if name not in PARTS:
        from ...errors import ConfigError

        raise ConfigError(f"part = {name!r} is not allowed (use {', '.join(PARTS)})")
    return importlib.import_module(f"{__name__}.{name}")
