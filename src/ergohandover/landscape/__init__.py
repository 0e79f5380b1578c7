"""The exhaustive landscape: the grid, every grid point evaluated once and kept in the cache,
its statistics. Callers get landscapes through the one door, :mod:`.store`, and every name
they need from here (nothing outside this package imports its modules' internals)."""

from .cache import Landscape, LandscapeError, checksum, landscape_key, twin_code_version
from .store import CHUNK_POINTS, Finished, cached_landscape, landscape_of, landscapes_of

__all__ = ["CHUNK_POINTS", "Finished", "Landscape", "LandscapeError", "cached_landscape",
           "checksum", "landscape_key", "landscape_of", "landscapes_of", "twin_code_version"]
