"""What the model refuses after parsing, said in the command line's terms.

Every flag's own range is checked while parsing (:mod:`.values`); what the model still refuses
takes several values at once (a handle span narrower than the box, a grid step larger than the
boundary) and its message names the model's fields (``handle_span = 0.3``). Here each becomes
the flag that sets it, and a landscape file that cannot be read is named with its flag.
"""

from __future__ import annotations

import dataclasses
import re
import shlex
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

from ..errors import ConfigError, ErgohandoverError
from ..io.csv_input import InputError

T = TypeVar("T")
BODY_FLAGS = {"stature_m": "--stature", "mass_kg": "--mass", "sex": "--sex",
              "elbow_height_m": "--elbow-height", "arm_length_m": "--arm-length",
              "shoulder_height_m": "--shoulder-height"}
"""The body's fields, whose flags are not their names."""


FIELD = re.compile(r"\b([a-z][a-z0-9_]*) = '?([^'\s,;)]*)'?(?: (?:m|kg|s|deg)\b)?")


def model(cls: Callable[..., T], *args, **kwargs) -> T:
    """``cls(*args, **kwargs)``, the model's own refusal written in flags. The checks of one
    value ran while parsing; what is left names several fields (``handle_span = 0.3 ... at least
    box_width = 0.36``): each becomes its flag and value, as the user typed them."""
    try:
        return cls(*args, **kwargs)
    except ConfigError as exc:
        raise InputError(as_flags(str(exc))) from None


def field_flags() -> dict[str, str]:
    """Model field -> the flag that sets it (the field's own name, but for the body's)."""
    from ..ergonomics import ScoringSettings
    from ..twin.task import TaskSpec

    names = [f.name for cls in (TaskSpec, ScoringSettings) for f in dataclasses.fields(cls)]
    names += ["solver", "trunk_reference", "boundary", "step"]
    return {**{name: "--" + name.replace("_", "-") for name in names}, **BODY_FLAGS}


def as_flags(message: str) -> str:
    """``field = value [unit]`` -> ``--flag value`` throughout; the first one ends with ``:``."""
    flags = field_flags()
    rewritten = FIELD.sub(lambda m: f"{flags[m[1]]} {m[2]}" if m[1] in flags else m[0],
                          message)
    return re.sub(r"^(--\S+ \S+) (is )?", r"\1: ", rewritten, count=1)


def read_landscape(path: Path, flag: str | None = None):
    """The landscape file ``path`` (given with ``flag``); a file that is not one is a one-line
    error naming the flag and the file."""
    from ..landscape import Landscape

    named = f"{flag} {shlex.quote(str(path))}" if flag else str(path)
    try:
        return Landscape.load(path)
    except ErgohandoverError as exc:  # the loader's message starts with the path: said once
        raise InputError(f"{named}: {str(exc).replace(f'{path} ', '', 1).removeprefix('is ')}") \
            from None
    except (KeyError, TypeError, ValueError) as exc:  # an .npz of other arrays
        raise InputError(f"{named}: not a landscape file ({type(exc).__name__})") from None
