"""The plain command's choice between one model and tiles, and the tiles' size and time split.

A site is planned by tiles when it is too large for one model and spans several tiles:

- the MILP method (the greedy and the closed form have no tiles);
- every zone in one frame (tiles are squares of one frame);
- at least :data:`MIN_PIECES` wall pieces in the work estimate (:func:`planner.plan.memory_guard.estimate_work`,
  from the geometry alone): there the single connected model ends its time far above its bound while the tiles
  close most of that gap (docs/studies/plant.md);
- at least :data:`MIN_TILES` tiles of side ``tile_m`` = max(:data:`TILE_M`, 1.5 S_max) over the zones' extent.

The tiled plan keeps the registration mode the single model would use (``--registration``, else the site's
default), so the choice changes how the plan is searched for, not what it must satisfy.

The time ``budget_s`` (``planner plan --set tile-budget=S``) is split by the tile count: each tile's MILP gets
``TILE_SHARE`` of it, spread over the tiles that run side by side, and the Lagrangian bound ``LAGRANGE_SHARE``;
the window re-solves ``WINDOW_SHARE``, spread over the stations expected (about ``STATIONS_PER_TILE`` per tile;
off by default, :data:`WINDOW_PASSES`); the whole-site plain cover (CFT: its own iteration counts) and the local
search (``MOVES_PER_PIECE`` moves per wall piece) take what is left; all of them count work, not seconds, so the
plan is the same under any load. A plan with a registration rule runs no CFT cover: its joined cover is not the
best start and costs much of the time; the local search gets that time instead, ``CONNECTED_MOVES_PER_PIECE``
moves per piece. Where no grid is given (``--grid-spacing``), a tiled site of at most :data:`FINE_GRID_PIECES`
pieces gets a candidate grid of :data:`FINE_GRID_M` (``Strategy.grid_spacing_m``;
:func:`planner.plan.problem.resolve` builds the pool with it), on which the search finds smaller plans
(docs/large-sites.md); a larger site keeps the 10-m grid, whose pool is large already.

Workers: half the machine's cores, at most one per tile; none (in this process) on a machine of two cores or
fewer, where a second process adds contention, not speed. Half, not all: with a worker on every core the client,
the scheduler and the workers compete for the same cores, and the tile phase gains little while spending much
more CPU (docs/studies/workers.md).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from planner.core.checks import count, real
from planner.core.errors import UsageError
from planner.core.settings import DEFAULTS
from planner.plan.memory_guard import estimate_work
from planner.site.model import Site
from planner.site.validate import ValidationReport
from planner.solve.cft import HEUR_ITERS
from planner.solve.windows import WindowOptions

if TYPE_CHECKING:
    from planner.plan.options import PlanOptions

#: the time budget of a tiled plan chosen automatically, s (its shares below)
BUDGET_S: float = DEFAULTS["strategy.budget_s"]
#: the local search's moves per wall piece of the site, unless a count is given
MOVES_PER_PIECE: float = DEFAULTS["tiling.moves_per_piece"]
#: the same for a connected plan of the automatic strategy, which runs no CFT cover (module docstring)
CONNECTED_MOVES_PER_PIECE = 15.0
#: the candidate grid of a tiled site of at most FINE_GRID_PIECES wall pieces where none is given, m (module docstring)
FINE_GRID_M = 4.0
#: the most wall pieces (work estimate) a tiled site may have for the fine grid
FINE_GRID_PIECES = 10_000
#: the most memory the fine grid's coverage problem may need (the guard's estimate) where no limit is given
FINE_GRID_BYTES = 2 * 2**30
#: the memory limit of each Dask worker unless set, bytes (1.5 GiB)
WORKER_MEMORY: int = DEFAULTS["strategy.worker_memory"]


@dataclass(frozen=True, kw_only=True)
class TileOptions:
    """``tile_m``: core side; ``margin_m``: default the slant range S_max (the exact margin); ``tile_time_limit_s``:
    MILP time per tile; ``bound_time_limit_s``: time of the whole-matrix cover MILP for the bound (0, the default: none;
    its bound is below the LP's on the plants, and CFT's cover replaces its cover); ``cft``: the whole-site plain cover
    by CFT (:mod:`planner.solve.cft`, ``cft_iters`` heuristic iterations per round), the plan of a run with no
    registration rule and a start of the connected one; ``tile_plans``: each tile's MILP, another start (off: the tiles
    give the coverage only, but for a plain cover with no CFT cover, which starts from them; the automatic strategy
    turns both off for a connected plan, where they are not the best start); ``local_search_moves``: move budget of the
    local search on the kept plan (:func:`planner.solve.local_search.shrink`; 0: none; None, the default:
    ``moves_per_piece`` per wall piece, a count, not a time, so the plan does not depend on the load). ``deterministic``
    (default; CP-SAT with one thread): both limits are CP-SAT work in deterministic seconds, with no wall-clock cap but
    the user's ``--time-limit`` per tile, so the plan is the same under any load and on any number of Dask workers;
    otherwise they are wall-clock seconds and a time-limited tile may stop at another incumbent under another load.
    ``lagrange``: also the Lagrangian bound over the tiles (:mod:`planner.bounds.lagrange`), its parts
    ``lagrange_group`` x ``lagrange_group`` tiles, ``lagrange_iterations`` subgradient steps and ``lagrange_work_s``
    CP-SAT deterministic seconds per part and step (docs/studies/plant.md). ``windows``: the window re-solves after the
    local search (:class:`planner.solve.windows.WindowOptions`; ``passes=0``: none). ``search_seeds``: the local search
    runs once per seed ``0 .. search_seeds - 1`` from the same kept plan (as Dask tasks when there is a client) and the
    smallest result is kept, the lowest seed on ties."""

    tile_m: float = 100.0
    margin_m: float | None = None
    tile_time_limit_s: float = DEFAULTS["tiling.tile_time_limit_s"]
    bound_time_limit_s: float = 0.0
    deterministic: bool = True
    tile_plans: bool = True
    cft: bool = True
    cft_iters: int = HEUR_ITERS
    lagrange: bool = True
    lagrange_group: int = 1
    lagrange_iterations: int = 0
    lagrange_work_s: float = DEFAULTS["tiling.lagrange_work_s"]
    local_search_moves: int | None = None
    moves_per_piece: float = MOVES_PER_PIECE
    search_seeds: int = 1
    windows: WindowOptions = WindowOptions()

    def moves_for(self, pieces: int) -> int:
        """The local search's move budget on a site of ``pieces`` wall pieces."""
        if self.local_search_moves is not None:
            return self.local_search_moves
        return round(self.moves_per_piece * pieces)

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
        if self.local_search_moves is not None and self.local_search_moves < 0 or not self.moves_per_piece >= 0:
            raise UsageError(
                "local search moves must be >= 0", field="local_search_moves", value=self.local_search_moves
            )
        if self.search_seeds < 1:
            raise UsageError("must be >= 1", field="search_seeds", value=self.search_seeds)


@dataclass(frozen=True, kw_only=True)
class StrategyOptions:
    """How a run searches for its plan: one model or tiles, and where the tiles run. ``single``: always one model.
    ``tiling``: always tiles, with these options. Neither (the default): the strategy :func:`choose` picks for the
    site, its tile budget ``budget_s`` split as the module says. ``workers``: Dask worker processes for the tiles
    (0: the machine's choice when chosen automatically, else in this process); ``scheduler``: an existing Dask
    cluster instead; ``worker_memory``: each worker's limit."""

    single: bool = False
    tiling: TileOptions | None = None
    budget_s: float = BUDGET_S
    workers: int = 0
    scheduler: str | None = None
    worker_memory: int = WORKER_MEMORY

    def __post_init__(self) -> None:
        if self.single and self.tiling is not None:
            raise UsageError("one model or tiles, not both", field="tiles", value=self.tiling.tile_m)
        real(self.budget_s, "budget_s", above=0)
        count(self.workers, "workers", 0)

    @property
    def runs_tiles_elsewhere(self) -> tuple[str, object] | None:
        """The first option given that only tiles use (workers, worker memory, scheduler), else None."""
        for name, value in (
            ("scheduler", self.scheduler),
            ("workers", self.workers),
            ("worker_memory", self.worker_memory != WORKER_MEMORY and self.worker_memory),
        ):
            if value:
                return name, value
        return None


#: a site spanning fewer tiles than this is planned as one model
MIN_TILES = 4
#: a site of fewer wall pieces (work estimate) than this is planned as one model
MIN_PIECES = 5_000
#: the smallest core side of a tile, m (1.5 S_max when that is larger: a core is then wider than its margin)
TILE_M = 100.0
#: shares of the budget: every tile's MILP together, the Lagrangian bound, the window re-solves (module docstring)
TILE_SHARE, LAGRANGE_SHARE, WINDOW_SHARE = 0.30, 0.15, 0.30
#: window re-solves of the automatic strategy: none (the local search's moves do better); ``--tiles M`` runs one pass
WINDOW_PASSES = 0
#: stations per tile the window budget is spread over (the generated plants need about this many)
STATIONS_PER_TILE = 6


@dataclass(frozen=True)
class Strategy:
    """What the plain command runs: ``tiling`` None for the single model; ``reason`` says why;
    ``grid_spacing_m``: the candidate grid it chooses where none is given (None: the pool's default)."""

    tiling: TileOptions | None
    workers: int
    reason: str
    grid_spacing_m: float | None = None

    @property
    def tiles(self) -> bool:
        return self.tiling is not None

    def to_dict(self) -> dict[str, object]:
        t = self.tiling
        out: dict[str, object] = {
            "kind": "tiles" if t else "single model",
            "reason": self.reason,
            "workers": self.workers,
        }
        if t:
            moves = t.local_search_moves if t.local_search_moves is not None else f"{t.moves_per_piece:g} per piece"
            out.update(
                tile_m=t.tile_m,
                tile_work_s=t.tile_time_limit_s,
                bound_work_s=t.bound_time_limit_s,
                lagrange_work_s=t.lagrange_work_s,
                cover=f"CFT, {t.cft_iters} iterations" if t.cft else None,
                grid_spacing_m=self.grid_spacing_m,
                search_moves=moves,
            )
        return out

    def line(self) -> str:
        where = f"on {self.workers} worker(s)" if self.workers else "in this process (no Dask worker)"
        what = f"tiles of {self.tiling.tile_m:g} m {where}" if self.tiling else "single model"
        grid = (
            f"; candidate grid {self.grid_spacing_m:g} m where none is given (at most {FINE_GRID_PIECES:,} pieces)"
            if self.grid_spacing_m is not None
            else ""
        )
        return f"strategy: {what} ({self.reason}{grid})"


def tile_count(site: Site, tile_m: float) -> int:
    """Tiles of side ``tile_m`` over the bounding box of the zones' vertices."""
    xy = np.vstack([z.xy for z in site.zones])
    ext = xy.max(axis=0) - xy.min(axis=0)
    return int(math.ceil(max(float(ext[0]), 1e-9) / tile_m) * math.ceil(max(float(ext[1]), 1e-9) / tile_m))


def resolve_strategy(site: Site, options: PlanOptions, validation: ValidationReport) -> Strategy:
    """The strategy of a run: ``options.strategy`` as given (one model, or tiles of a given size), else the
    automatic choice (:func:`strategy_for`); UsageError for tiles with a method other than the MILP, or Dask
    workers for one model."""
    o = options.strategy
    if o.tiling is not None:
        if options.method != "milp":
            raise UsageError("tiles plan with the MILP", field="method", value=options.method)
        return Strategy(o.tiling, o.workers, f"tiles of {o.tiling.tile_m:g} m asked for")
    strategy = (
        Strategy(None, 0, "one model asked for")
        if o.single
        else strategy_for(site, options, validation, o.budget_s, workers=o.workers or None)
    )
    given = o.runs_tiles_elsewhere
    if strategy.tiling is None and given is not None:
        raise UsageError(
            f"Dask workers and schedulers run tiles, and this plan is one model ({strategy.reason}); ask for tiles (--tiles M)",
            field=given[0],
            value=given[1],
        )
    return strategy


def strategy_for(
    site: Site, options: PlanOptions, validation: ValidationReport, budget_s: float, workers: int | None = None
) -> Strategy:
    """The plain command's strategy for ``site`` (:func:`choose` on the memory guard's work estimate of its wall
    pieces); ``workers``: the Dask workers asked for (``--workers``), else None for the machine's choice. The fine
    grid is kept only where its estimate fits the memory limit given (``--memory-limit``), else
    :data:`FINE_GRID_BYTES` (a constant, not the memory free now, so that the plan does not depend on the load):
    otherwise the 10-m grid, which the guard then checks."""
    max_slant_range_m = validation.range_limit.max_slant_range_m
    pieces = estimate_work(site, options.target_spacing_m, options.pool.grid_m, max_slant_range_m).targets
    strategy = choose(site, options, max_slant_range_m, pieces, budget_s, workers=workers)
    if strategy.grid_spacing_m is not None:  # the fine grid only where the memory guard will let its pool be built
        fine = estimate_work(site, options.target_spacing_m, strategy.grid_spacing_m, max_slant_range_m)
        if fine.bytes > (options.memory_limit_bytes or FINE_GRID_BYTES):
            strategy = replace(strategy, grid_spacing_m=None)
    return strategy


def choose(
    site: Site,
    options: PlanOptions,
    max_slant_range_m: float,
    pieces: int,
    budget_s: float,
    cores: int | None = None,
    workers: int | None = None,
) -> Strategy:
    """The strategy for ``site`` (module docstring); ``pieces``: the work estimate's wall pieces. ``workers``
    (given, >= 1): the tiles run on that many Dask workers, and the time split counts them as side by side;
    else the workers follow from ``cores`` (default: this machine's)."""
    if options.method != "milp":
        return Strategy(None, 0, f"method {options.method}")
    if pieces < MIN_PIECES:
        return Strategy(None, 0, f"about {pieces:,} wall pieces, fewer than {MIN_PIECES:,}")
    if len({z.frame for z in site.zones}) != 1:
        return Strategy(None, 0, "zones in several frames")
    tile_m = max(TILE_M, 1.5 * max_slant_range_m)
    n = tile_count(site, tile_m)
    if n < MIN_TILES:
        return Strategy(None, 0, f"the site spans {n} tile(s) of {tile_m:g} m, fewer than {MIN_TILES}")
    if not workers:
        cores = os.cpu_count() or 1 if cores is None else cores
        workers = 0 if cores <= 2 else min(cores // 2, n)
    side_by_side = max(workers, 1)
    # a registration rule (options resolved: milp.overlap is the rule or None): CFT's cover is no start worth its time
    connected = options.milp.overlap is not None
    tiling = TileOptions(
        tile_m=tile_m,
        tile_time_limit_s=_clamp(TILE_SHARE * budget_s * side_by_side / n, 2.0, 30.0),
        lagrange_work_s=_clamp(LAGRANGE_SHARE * budget_s * side_by_side / n, 1.0, 10.0),
        tile_plans=False,
        cft=not connected,
        moves_per_piece=CONNECTED_MOVES_PER_PIECE if connected else MOVES_PER_PIECE,
        windows=replace(
            WindowOptions(),
            passes=WINDOW_PASSES,
            seed=options.milp.seed,
            work_s=_clamp(WINDOW_SHARE * budget_s / (STATIONS_PER_TILE * n), 0.5, 3.0),
        ),
    )
    fine = pieces <= FINE_GRID_PIECES and options.pool.grid_spacing_m is None  # a grid given is the user's
    return Strategy(
        tiling,
        workers,
        f"about {pieces:,} wall pieces over {n} tiles of {tile_m:g} m (at least "
        f"{MIN_PIECES:,} and {MIN_TILES}); time budget {budget_s:g} s",
        FINE_GRID_M if fine else None,
    )


def _clamp(x: float, lo: float, hi: float) -> float:
    return float(min(max(x, lo), hi))
