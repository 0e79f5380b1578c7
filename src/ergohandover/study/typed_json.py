"""Frozen dataclasses from JSON, checked once: every key known, every value of its type and within
its declared range or choices, each refusal one line naming the key path, the value and what is
allowed (``learning.runs = -1 is outside the valid range (an integer >= 1)``).

A field declares its range with :func:`setting` (the metadata format of
:func:`~ergohandover.ranges.ranged`: ``lo``/``hi``/``unit`` or ``choices``); for a tuple or a
dict the range applies to each element. Supported annotations: ``bool``, ``int``, ``float``,
``str``, ``X | None``, ``tuple[X, ...]``, ``dict[str, X]`` and nested dataclasses.
"""

from __future__ import annotations

import dataclasses
import math
import types
import typing
from typing import Any

from ..errors import ConfigError

MISSING = dataclasses.MISSING


def setting(default: Any = MISSING, help: str = "", lo: float | None = None,
            hi: float | None = None, unit: str = "", choices: tuple | None = None,
            positive: bool = False) -> Any:
    """A dataclass field with its default (a list or dict default is copied per instance), help
    text and range (``lo``, ``hi``, ``unit``; ``positive``: above 0) or ``choices``."""
    meta = {"help": help, "lo": lo, "hi": hi, "unit": unit, "choices": choices,
            "positive": positive}
    if isinstance(default, list | dict):
        return dataclasses.field(default_factory=lambda: type(default)(default), metadata=meta)
    if dataclasses.is_dataclass(default):
        return dataclasses.field(default_factory=lambda: default, metadata=meta)
    return dataclasses.field(default=default, metadata=meta)


def short(value: Any, width: int = 40) -> str:
    """``repr(value)``, cut to ``width`` characters (a whole section would not fit a line)."""
    text = repr(value)
    return text if len(text) <= width else text[:width - 3] + "..."


def from_json(cls: type, data: Any, path: str = "") -> Any:
    """An instance of dataclass ``cls`` from a JSON object; ConfigError on any bad key or value.

    Args:
        cls: a (frozen) dataclass whose fields are annotated with supported types.
        data: the parsed JSON object; keys left out take the field's default.
        path: the object's key path, for messages (``""`` at the top).
    """
    fields = {f.name: f for f in dataclasses.fields(cls)}
    where = path or "the study"
    if not isinstance(data, dict):
        raise ConfigError(f"{path or 'configuration'} = {short(data)} is not allowed (expected "
                          f"an object with keys {', '.join(fields)})")
    for key, value in data.items():
        if key not in fields:
            raise ConfigError(f"{join(path, key)} = {short(value)} is not a setting of {where} "
                              f"(allowed: {', '.join(fields)})")
    hints = typing.get_type_hints(cls)
    values = {}
    for name, field in fields.items():
        if name in data:
            values[name] = convert(hints[name], data[name], join(path, name), field.metadata)
        elif field.default is MISSING and field.default_factory is MISSING:
            raise ConfigError(f"{join(path, name)} is missing (expected "
                              f"{describe(hints[name], field.metadata)})")
    return cls(**values)


def join(path: str, key: str | int) -> str:
    return f"{path}[{key}]" if isinstance(key, int) else f"{path}.{key}" if path else key


def convert(kind: Any, value: Any, path: str, meta: typing.Mapping[str, Any]) -> Any:
    """``value`` as type ``kind``, checked against ``meta``'s range or choices."""
    origin, args = typing.get_origin(kind), typing.get_args(kind)
    if origin in (typing.Union, types.UnionType):
        if value is None and type(None) in args:
            return None
        (inner,) = [a for a in args if a is not type(None)]
        return convert(inner, value, path, meta)
    if dataclasses.is_dataclass(kind):
        return from_json(kind, value, path)
    if origin is tuple:
        if not isinstance(value, list):
            raise bad(value, path, kind, meta)
        return tuple(convert(args[0], v, join(path, i), meta) for i, v in enumerate(value))
    if origin is dict:
        if not isinstance(value, dict):
            raise bad(value, path, kind, meta)
        return {k: convert(args[1], v, join(path, k), meta) for k, v in value.items()}
    return scalar(kind, value, path, meta)


def scalar(kind: type, value: Any, path: str, meta: typing.Mapping[str, Any]) -> Any:
    if kind is bool:
        if not isinstance(value, bool):
            raise bad(value, path, kind, meta)
        return value
    if kind in (int, float):
        number = isinstance(value, int | float) and not isinstance(value, bool)
        if not number or (kind is int and not float(value).is_integer()) or not math.isfinite(
                value):
            raise bad(value, path, kind, meta)
        value = kind(value)
        lo, hi = meta.get("lo"), meta.get("hi")
        if ((lo is not None and value < lo) or (hi is not None and value > hi)
                or (meta.get("positive") and value <= 0)):
            raise ConfigError(f"{path} = {value!r} is outside the valid range "
                              f"({describe(kind, meta)})")
        return value
    if not isinstance(value, str) or (meta.get("choices") and value not in meta["choices"]):
        raise bad(value, path, kind, meta)
    return value


def bad(value: Any, path: str, kind: Any, meta: typing.Mapping[str, Any]) -> ConfigError:
    return ConfigError(f"{path} = {short(value)} is not allowed (expected "
                       f"{describe(kind, meta)})")


def describe(kind: Any, meta: typing.Mapping[str, Any]) -> str:
    """What a field accepts, in words: ``an integer >= 1``, ``one of 'on', 'off'``, ..."""
    origin, args = typing.get_origin(kind), typing.get_args(kind)
    if origin in (typing.Union, types.UnionType):
        inner = next(a for a in args if a is not type(None))
        return f"{describe(inner, meta)} or null"
    if origin is tuple:
        return f"a list of {describe(args[0], meta).removeprefix('a ').removeprefix('an ')}s"
    if origin is dict:
        return f"an object of {describe(args[1], meta).removeprefix('a ')}s by name"
    if dataclasses.is_dataclass(kind):
        return f"an object with keys {', '.join(f.name for f in dataclasses.fields(kind))}"
    if meta.get("choices"):
        return "one of " + ", ".join(repr(c) for c in meta["choices"])
    words = {bool: "true or false", int: "an integer", float: "a number", str: "a string"}
    text = words[kind]
    lo, hi, unit = meta.get("lo"), meta.get("hi"), meta.get("unit") or ""
    if meta.get("positive"):
        text += " > 0"
    elif lo is not None and hi is not None:
        text += f" {lo:g}-{hi:g}"
    elif lo is not None:
        text += f" >= {lo:g}"
    elif hi is not None:
        text += f" <= {hi:g}"
    return text + (f" {unit}" if unit else "")
