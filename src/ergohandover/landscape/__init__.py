"""The exhaustive landscape: the grid, every grid point evaluated once and kept in the cache,
its statistics. Callers get landscapes through the one door, :mod:`.store`."""

from .cache import Landscape, LandscapeError, landscape_key
from .store import CHUNK_POINTS, Finished, cached_landscape, landscape_of, landscapes_of

__all__ = ["CHUNK_POINTS", "Finished", "Landscape", "LandscapeError", "cached_landscape",
           "landscape_key", "landscape_of", "landscapes_of"]
