"""The exhaustive landscape: the grid, the cached sweep of every grid point, its statistics."""
