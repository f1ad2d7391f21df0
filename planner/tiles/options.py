"""The options of a tiled run (:class:`TileOptions`) and the MILP limits they give each tile."""

from __future__ import annotations

from dataclasses import dataclass, replace

from planner.errors import UsageError
from planner.plan import PlanOptions
from planner.solve.milp import WALL_CAP, MilpOptions
from planner.solve.windows import WindowOptions


@dataclass(frozen=True)
class TileOptions:
    """``tile_m``: core side; ``margin_m``: default the slant range S_max (the exact margin);
    ``tile_time_limit_s``: MILP time per tile; ``bound_time_limit_s``: time of the whole-matrix cover
    MILP for the bound (0: LP bound only); ``local_search_moves``: move budget of the local search on the
    kept plan (:func:`planner.solve.local_search.shrink`; 0: none; a count, not a time, so
    the plan does not depend on the load). ``deterministic`` (default; CP-SAT with one thread): both
    limits are CP-SAT work in deterministic seconds, with a wall-clock cap of ``WALL_CAP`` times as
    long, so the plan is the same under any load and on any number of Dask workers; otherwise they are
    wall-clock seconds and a time-limited tile may stop at another incumbent under another load.
    ``lagrange``: also the Lagrangian bound over the tiles (:mod:`planner.tiles.lagrange`), its parts
    ``lagrange_group`` x ``lagrange_group`` tiles, ``lagrange_iterations`` subgradient steps and
    ``lagrange_work_s`` CP-SAT deterministic seconds per part and step (default: on, single tiles, the
    LP-dual split only, 10 s; its cost and gain on the plants: docs/studies/plant.md). ``windows``: the
    window re-solves after the local search (:class:`planner.solve.windows.WindowOptions`; ``passes=0``: none).
    ``search_seeds``: the local search runs once per seed ``0 .. search_seeds - 1`` from the same kept plan
    (as Dask tasks when there is a client) and the smallest result is kept, the lowest seed on ties; the
    same plan on any number of workers."""

    tile_m: float = 100.0
    margin_m: float | None = None
    tile_time_limit_s: float = 30.0
    bound_time_limit_s: float = 60.0
    deterministic: bool = True
    lagrange: bool = True
    lagrange_group: int = 1
    lagrange_iterations: int = 0
    lagrange_work_s: float = 10.0
    local_search_moves: int = 20_000
    search_seeds: int = 1
    windows: WindowOptions = WindowOptions()

    def margin_for(self, max_slant_range_m: float) -> float:
        """The tiles' margin (m): ``margin_m``, or the slant range where it is not given (the exact margin)."""
        return max_slant_range_m if self.margin_m is None else self.margin_m

    def __post_init__(self) -> None:
        if not self.tile_m > 0 or (self.margin_m is not None and self.margin_m < 0):
            raise UsageError("tile size must be > 0 and margin >= 0", field="tile_m", value=self.tile_m)
        if not self.tile_time_limit_s > 0 or self.bound_time_limit_s < 0:
            raise UsageError("tile time limit must be > 0", field="tile_time_limit_s", value=self.tile_time_limit_s)
        if self.lagrange_group < 1 or self.lagrange_iterations < 0 or not self.lagrange_work_s > 0:
            raise UsageError(
                "Lagrangian parts need a group >= 1, iterations >= 0 and work > 0",
                field="lagrange_group",
                value=self.lagrange_group,
            )
        if self.local_search_moves < 0:
            raise UsageError(
                "local search moves must be >= 0", field="local_search_moves", value=self.local_search_moves
            )
        if self.search_seeds < 1:
            raise UsageError("must be >= 1", field="search_seeds", value=self.search_seeds)


def deterministic_limits(milp: MilpOptions, tiling: TileOptions) -> bool:
    """Whether the tile and bound MILPs run on CP-SAT work limits (see :class:`TileOptions`)."""
    return tiling.deterministic and milp.backend == "cpsat" and milp.threads == 1


def limits_line(capped: list[str], work_limited: bool) -> str:
    if not work_limited:
        return "MILP limits: wall clock (a time-limited tile may end at another plan under another load)"
    return "MILP limits: CP-SAT work in deterministic seconds (same plan under any load, serial or on Dask)" + (
        f"; wall-clock cap reached in {', '.join(capped)}: those answers may depend on the load" if capped else ""
    )


def tile_milp(options: PlanOptions, tiling: TileOptions) -> MilpOptions:
    limit = tiling.tile_time_limit_s
    if deterministic_limits(options.milp, tiling):
        return options.milp.with_work_limit(limit, WALL_CAP)
    return replace(options.milp, time_limit_s=limit)
