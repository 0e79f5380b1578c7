"""Command-line options generated from frozen dataclass configs: one source of truth.

A field's ``metadata["help"]`` becomes its ``--help`` text and ``metadata["choices"]`` its
choices; the dataclass's own validation runs when the config is built from the parsed flags.
"""

from __future__ import annotations

import argparse
import dataclasses
from typing import Any, TypeVar

T = TypeVar("T")


def flag_name(field: dataclasses.Field) -> str:
    return "--" + field.name.replace("_", "-")


def add_dataclass_arguments(parser: argparse.ArgumentParser | Any, cls: type,
                            title: str | None = None) -> None:
    """Add one ``--flag`` per field of dataclass ``cls`` (default: the field's default)."""
    group = parser.add_argument_group(title) if title else parser
    for field in dataclasses.fields(cls):
        meta = field.metadata
        kind = type(field.default)
        group.add_argument(
            flag_name(field),
            dest=field.name,
            type=kind if kind in (int, float, str) else str,
            default=None,
            choices=meta.get("choices"),
            metavar=None if "choices" in meta else field.name.split("_")[-1].upper(),
            help=f"{meta.get('help', '')} (default: {field.default})",
        )


def dataclass_from_args(cls: type[T], args: argparse.Namespace) -> T:
    """Build ``cls`` from the flags given on the command line; unset flags keep defaults."""
    given = {
        f.name: getattr(args, f.name)
        for f in dataclasses.fields(cls)
        if getattr(args, f.name, None) is not None
    }
    return cls(**given)


def add_body_arguments(parser: argparse.ArgumentParser) -> None:
    """``--percentile``, ``--stature``, ``--mass``, ``--sex``: the worker's size."""
    from ..twin.anthropometry import PERCENTILES

    group = parser.add_argument_group("worker (default: ANSUR II 50th-percentile man)")
    group.add_argument("--percentile", choices=sorted(PERCENTILES),
                       help="a named survey percentile (stature, mass and sex together)")
    group.add_argument("--stature", type=float, metavar="M", help="stature [m], 1.40-2.10")
    group.add_argument("--mass", type=float, metavar="KG", help="body mass [kg], 35-160")
    group.add_argument("--sex", choices=("male", "female"), help="sex")


def body_from_args(args: argparse.Namespace):
    """The BodySpec the flags describe: a percentile, then any explicit overrides."""
    import dataclasses

    from ..twin.anthropometry import BodySpec

    body = BodySpec.from_percentile(args.percentile) if args.percentile else BodySpec()
    overrides = {k: v for k, v in (("stature_m", args.stature), ("mass_kg", args.mass),
                                   ("sex", args.sex)) if v is not None}
    return dataclasses.replace(body, **overrides) if overrides else body
