"""The package's exceptions: every error it raises derives from :class:`ErgohandoverError`.

The command line catches that one class and prints its message as one line with exit code 2,
so each message names the field, its value and what is allowed. Each class also derives from
the built-in it refines (``ValueError``, ``OSError``, ...), so callers that catch those keep
working.
"""

from __future__ import annotations


class ErgohandoverError(Exception):
    """Base class of every error raised by ergohandover; the message is one line."""


class ConfigError(ErgohandoverError, ValueError):
    """A configuration value outside its valid range or choices."""


class UsageError(ErgohandoverError, RuntimeError):
    """An object used out of order (e.g. an environment stepped before it was reset)."""


class ModelError(ErgohandoverError, ValueError):
    """A body or scene model that cannot be built or loaded (a name, a file, a shape)."""


class SerialisationError(ErgohandoverError, TypeError):
    """A value that cannot be written to a result file."""


class UnknownNameError(ErgohandoverError, KeyError):
    """A joint, link or column looked up by a name that does not exist."""
