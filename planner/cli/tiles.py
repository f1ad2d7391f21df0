"""The ``plan`` command's large-site options: ``--tiles M`` plans by tiles, on Dask with ``--workers N``
(an embedded LocalCluster) or ``--scheduler tcp://HOST:PORT`` (an existing cluster)."""

from __future__ import annotations

import argparse
from dataclasses import replace
from typing import TYPE_CHECKING

from planner.cli.option_types import NON_NEGATIVE_INT, POSITIVE
from planner.cli.tuning import BUDGET_S, WORKER_MEMORY
from planner.core.errors import UsageError

if TYPE_CHECKING:  # the plan stack loads inside the command (fast --help, docs/startup.md)
    from planner.plan import PlanOptions
    from planner.plan.strategy import StrategyOptions
    from planner.tiles import TileOptions

__all__ = ["BUDGET_S", "WORKER_MEMORY", "add_tile_options", "strategy_options"]


def add_tile_options(p: argparse.ArgumentParser) -> None:
    """``--tiles``, ``--workers`` and ``--scheduler`` (the tiles' tuning keys: :mod:`planner.cli.tuning`)."""
    p.add_argument(
        "--tiles",
        type=_tiles,
        default="auto",
        metavar="M|auto|off",
        help="milp: plan by square tiles of M m (margins of S_max), stitched into one registered plan; "
        "auto (default): tiles for a large site, sized to the site and the tile-budget key "
        "(docs/large-sites.md); off: one model",
    )
    p.add_argument(
        "--workers",
        type=NON_NEGATIVE_INT,
        default=0,
        metavar="N",
        help="--tiles: run tiles on an embedded Dask LocalCluster of N processes (default 0: in this process)",
    )
    p.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        default=None,
        help="--tiles: run tiles on the Dask cluster at ADDRESS (tcp://HOST:PORT)",
    )


def _tiles(text: str) -> float | str:
    """--tiles: a core side in m, ``auto`` or ``off``."""
    word = text.strip().lower()
    return word if word in ("auto", "off") else POSITIVE(text)


#: the WindowOptions, TileOptions and StrategyOptions fields checked there, and the flags that give them
_FLAGS = {
    "workers": "--workers",
    "scheduler": "--scheduler",
    "worker_memory": "--set worker-memory",
    "budget_s": "--set tile-budget",
    "tiles": "--tiles",
    "radius_m": "--set tile-window-radius",
    "work_s": "--set tile-window-work",
    "passes": "--set tile-window-passes",
    "batch": "--set tile-window-batch",
    "local_search_moves": "--set tile-search-moves",
    "moves_per_piece": "--set tile-moves-per-piece",
    "search_seeds": "--set tile-search-seeds",
}


def strategy_options(args: argparse.Namespace, options: PlanOptions) -> StrategyOptions:
    """The run's strategy from ``--tiles`` (auto, off or a size with the tile keys), the ``tile-budget`` key and
    where the tiles run (``--workers``, ``--scheduler``, the ``worker-memory`` key)."""
    from planner.plan.strategy import StrategyOptions

    if args.workers < 0:
        raise UsageError("must be >= 0", field="--workers", value=args.workers)
    tiling = None
    if args.tiles not in ("auto", "off"):
        if options.method != "milp":
            raise UsageError("--tiles plans with the MILP", field="--method", value=options.method)
        tiling = _tiling(args, options)
    try:
        return StrategyOptions(
            single=args.tiles == "off",
            tiling=tiling,
            budget_s=args.tile_budget,
            workers=args.workers,
            scheduler=args.scheduler,
            worker_memory=args.worker_memory,
        )
    except UsageError as err:
        raise UsageError(err.message, field=option_flag(err.field), value=err.value) from None


def _tiling(args: argparse.Namespace, options: PlanOptions) -> TileOptions:
    """``--tiles M`` with the tile flags; the error of a bad value names the flag that gave it."""
    from planner.solve.windows import WindowOptions
    from planner.tiles import TileOptions

    try:
        windows = WindowOptions(
            radius_m=args.tile_window_radius,
            work_s=args.tile_window_work,
            passes=args.tile_window_passes,
            seed=options.milp.seed,
            batch=args.tile_window_batch,
        )
        tiling = TileOptions(
            tile_m=args.tiles,
            tile_time_limit_s=args.tile_time_limit,
            bound_time_limit_s=args.bound_time_limit,
            deterministic=not args.tile_wall_clock,
            lagrange_group=args.lagrange_group,
            local_search_moves=args.tile_search_moves,
            moves_per_piece=args.tile_moves_per_piece,
            cft=args.tile_cft_iters > 0,
            cft_iters=max(args.tile_cft_iters, 1),
            search_seeds=args.tile_search_seeds,
            windows=windows,
        )
    except UsageError as err:
        raise UsageError(err.message, field=option_flag(err.field), value=err.value) from None
    if args.lagrange_work is not None:
        if args.lagrange_work < 0:
            raise UsageError("must be >= 0", field="--set lagrange-work", value=args.lagrange_work)
        tiling = replace(tiling, lagrange=args.lagrange_work > 0, lagrange_work_s=args.lagrange_work or 1.0)
    return tiling


def option_flag(field: str | None) -> str | None:
    """The flag that gives an option's field (the field itself where none does)."""
    return _FLAGS.get(field or "", field)
