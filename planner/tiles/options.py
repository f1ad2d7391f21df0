"""The MILP limits a tiled run gives each tile (:class:`TileOptions` itself is part of the resolved problem's
strategy: :mod:`planner.plan.strategy`)."""

from __future__ import annotations

from dataclasses import replace

from planner.plan import PlanOptions
from planner.solve.backends import CAPABILITIES
from planner.solve.milp import WALL_CAP, MilpOptions

__all__ = ["TileOptions", "deterministic_limits", "limits_line", "tile_milp"]
from planner.plan.strategy import TileOptions


def deterministic_limits(milp: MilpOptions, tiling: TileOptions) -> bool:
    """Whether the tile and bound MILPs run on CP-SAT work limits (see :class:`TileOptions`)."""
    return tiling.deterministic and CAPABILITIES[milp.backend].work_limit and milp.threads == 1


def limits_line(capped: list[str], work_limited: bool) -> str:
    if not work_limited:
        return "MILP limits: wall clock (a time-limited tile may end at another plan under another load)"
    return "MILP limits: CP-SAT work in deterministic seconds (same plan under any load, serial or on Dask)" + (
        f"; wall-clock cap reached in {', '.join(capped)}: those answers may depend on the load" if capped else ""
    )


def tile_milp(options: PlanOptions, tiling: TileOptions) -> MilpOptions:
    """A tile's MILP options: the tile limits, and no plain-cover start (CFT and its search) in the tiles, where
    the whole site's plain cover is made once (:mod:`planner.tiles.run`)."""
    limit = tiling.tile_time_limit_s
    options = replace(options, milp=replace(options.milp, plain_start=False))
    if deterministic_limits(options.milp, tiling):
        return options.milp.with_work_limit(limit, WALL_CAP)
    return replace(options.milp, time_limit_s=limit, work_limit=None)  # the user chose wall-clock limits
