"""Large sites by tiles (serially or as Dask tasks): :func:`plan_by_tiles`."""

from planner.tiles.engine import dask_client
from planner.tiles.run import TileOptions, plan_by_tiles

__all__ = ["TileOptions", "dask_client", "plan_by_tiles"]
