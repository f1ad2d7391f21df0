"""The ``plan`` command's large-site options: ``--tiles M`` plans by tiles, on Dask with ``--workers N``
(an embedded LocalCluster) or ``--scheduler tcp://HOST:PORT`` (an existing cluster)."""

from __future__ import annotations

import argparse
from dataclasses import replace
from typing import TYPE_CHECKING

from planner.cli.option_types import NON_NEGATIVE, NON_NEGATIVE_INT, POSITIVE, POSITIVE_INT
from planner.errors import UsageError

if TYPE_CHECKING:  # the plan stack loads inside the command (fast --help, docs/startup.md)
    from planner.plan import Plan, PlanOptions
    from planner.site.model import Site
    from planner.site.validate import ValidationReport
    from planner.tiles import TileOptions
    from planner.tiles.auto import Strategy


#: the time budget of a tiled plan under --tiles auto, s (a 16-ha plant planned within about 10 minutes, with
#: reading, coverage and verification)
BUDGET_S = 420.0
#: the memory limit of each Dask worker unless --worker-memory says otherwise
WORKER_MEMORY = "1.5GiB"


def add_tile_options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--tiles",
        type=_tiles,
        default="auto",
        metavar="M|auto|off",
        help="milp: plan by square tiles of M m (margins of S_max), stitched into one registered plan; "
        "auto (default): tiles for a large site, sized to the site and --tile-budget "
        "(docs/large-sites.md); off: one model",
    )
    p.add_argument(
        "--tile-budget",
        type=POSITIVE,
        default=BUDGET_S,
        metavar="S",
        help=f"--tiles auto: the time budget the tiles' work is split from (default {BUDGET_S:g} s)",
    )
    p.add_argument(
        "--tile-time-limit",
        type=POSITIVE,
        default=30.0,
        metavar="S",
        help="--tiles: MILP work per tile, CP-SAT deterministic seconds, wall cap 4x (default 30)",
    )
    p.add_argument(
        "--bound-time-limit",
        type=NON_NEGATIVE,
        default=60.0,
        metavar="S",
        help="--tiles: work of the whole-site cover MILP for the lower bound (default 60; 0: LP bound only)",
    )
    p.add_argument(
        "--lagrange-work",
        type=NON_NEGATIVE,
        default=None,
        metavar="S",
        help="--tiles: also the Lagrangian bound over the tiles, S CP-SAT deterministic seconds per tile "
        "(0: off; default 10)",
    )
    p.add_argument(
        "--lagrange-group",
        type=POSITIVE_INT,
        default=1,
        metavar="N",
        help="--tiles: Lagrangian parts of N x N tiles (default 1)",
    )
    p.add_argument(
        "--tile-search-moves",
        type=NON_NEGATIVE_INT,
        default=20_000,
        metavar="N",
        help="--tiles: move budget of the local search that shrinks the kept connected plan (default 20000; 0: none)",
    )
    p.add_argument(
        "--tile-search-seeds",
        type=POSITIVE_INT,
        default=1,
        metavar="N",
        help="--tiles: run the local search with seeds 0..N-1 (as Dask tasks with --workers) and keep the "
        "smallest plan (default 1)",
    )
    p.add_argument(
        "--tile-window-passes",
        type=NON_NEGATIVE_INT,
        default=1,
        metavar="N",
        help="--tiles: passes of the exact window re-solves after the local search (default 1; 0: none)",
    )
    p.add_argument(
        "--tile-window-radius",
        type=POSITIVE,
        default=60.0,
        metavar="M",
        help="--tiles: radius of a re-solve window around each station (default 60 m)",
    )
    p.add_argument(
        "--tile-window-work",
        type=POSITIVE,
        default=3.0,
        metavar="S",
        help="--tiles: CP-SAT deterministic seconds per window, wall cap 4x (default 3)",
    )
    p.add_argument(
        "--tile-window-batch",
        type=POSITIVE_INT,
        default=1,
        metavar="N",
        help="--tiles on Dask: N windows in flight as tasks, their answers taken in order (default 1: one "
        "at a time in this process; same plan either way)",
    )
    p.add_argument(
        "--tile-wall-clock",
        action="store_true",
        help="--tiles: the two limits above in wall-clock seconds (the plan may then depend on the load)",
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
    p.add_argument(
        "--worker-memory",
        default=WORKER_MEMORY,
        metavar="SIZE",
        help=f"--tiles --workers: memory limit of each worker (default {WORKER_MEMORY})",
    )


def _tiles(text: str) -> float | str:
    """--tiles: a core side in m, ``auto`` or ``off``."""
    word = text.strip().lower()
    return word if word in ("auto", "off") else POSITIVE(text)


#: the WindowOptions and TileOptions fields checked there, and the flags that give them
_FLAGS = {
    "radius_m": "--tile-window-radius",
    "work_s": "--tile-window-work",
    "passes": "--tile-window-passes",
    "batch": "--tile-window-batch",
    "local_search_moves": "--tile-search-moves",
    "search_seeds": "--tile-search-seeds",
}


def plan_command(site: Site, options: PlanOptions, args: argparse.Namespace, validation: ValidationReport) -> Plan:
    """``plan_site`` or, with ``--tiles``, ``plan_by_tiles`` (serially or on Dask)."""
    from planner.plan import plan_site

    if args.workers < 0:
        raise UsageError("must be >= 0", field="--workers", value=args.workers)
    strategy = None
    if args.tiles in ("auto", "off"):
        strategy = _auto(site, options, args, validation)
        if strategy.tiling is None:
            given = [
                (f, v)
                for f, v in (
                    ("--scheduler", args.scheduler),
                    ("--workers", args.workers),
                    ("--worker-memory", args.worker_memory != WORKER_MEMORY and args.worker_memory),
                )
                if v
            ]
            if given:
                raise UsageError(
                    f"--workers, --worker-memory and --scheduler run tiles, and this plan is one model "
                    f"({strategy.reason}); give --tiles M",
                    field=given[0][0],
                    value=given[0][1],
                )
            return _with_strategy(plan_site(site, options, validation), strategy)
        return _with_strategy(_by_tiles(site, options, args, strategy, validation), strategy)
    if options.method != "milp":
        raise UsageError("--tiles plans with the MILP", field="--method", value=options.method)
    from planner.solve.windows import WindowOptions
    from planner.tiles import TileOptions

    try:  # WindowOptions and TileOptions check the values; the error names the flag that gave the bad one
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
            search_seeds=args.tile_search_seeds,
            windows=windows,
        )
    except UsageError as err:
        raise UsageError(err.message, field=_FLAGS.get(err.field or "", err.field), value=err.value) from None
    if args.lagrange_work is not None:
        if args.lagrange_work < 0:
            raise UsageError("must be >= 0", field="--lagrange-work", value=args.lagrange_work)
        tiling = replace(tiling, lagrange=args.lagrange_work > 0, lagrange_work_s=args.lagrange_work or 1.0)
    return _run_tiles(site, options, tiling, args.workers, args, validation)


def _run_tiles(
    site: Site,
    options: PlanOptions,
    tiling: TileOptions,
    workers: int,
    args: argparse.Namespace,
    validation: ValidationReport,
) -> Plan:
    from planner.tiles import dask_client, plan_by_tiles

    if not workers and not args.scheduler:
        return plan_by_tiles(site, options, tiling, validation=validation)
    with dask_client(workers, args.scheduler, args.worker_memory) as client:
        return plan_by_tiles(site, options, tiling, client=client, validation=validation)


def _auto(site: Site, options: PlanOptions, args: argparse.Namespace, validation: ValidationReport) -> Strategy:
    """``--tiles auto`` (or ``off``): the strategy :func:`planner.tiles.auto.strategy_for` picks for this site,
    on the ``--workers`` given (else the machine's choice)."""
    from planner.tiles.auto import Strategy, strategy_for

    if args.tiles == "off":
        return Strategy(None, 0, "--tiles off")
    return strategy_for(site, options, validation, budget_s=args.tile_budget, workers=args.workers or None)


def _by_tiles(
    site: Site, options: PlanOptions, args: argparse.Namespace, strategy: Strategy, validation: ValidationReport
) -> Plan:
    """The tiles the strategy chose, on its workers (``--workers`` when given) or ``--scheduler``, in the
    registration mode the single model would use."""
    from planner.coverage.links import default_registration

    assert strategy.tiling is not None
    options = replace(options, registration=options.registration or default_registration(site))
    return _run_tiles(site, options, strategy.tiling, strategy.workers, args, validation)


def _with_strategy(plan: Plan, strategy: Strategy) -> Plan:
    """The plan with the strategy in its log (summary) and in its result's info (plan.json), and the gap to the
    best plan known for the site (:mod:`planner.plan.best_known`) where the file lists one."""
    from planner.coverage.links import default_registration
    from planner.plan.best_known import best_known

    info = {**plan.result.info, "strategy": strategy.to_dict()}
    log = [*plan.log, strategy.line()]
    rule = plan.options.checked_rule(plan.site)
    mode = plan.options.registration or default_registration(plan.site)
    known = best_known(plan.site.name, mode, rule.overlap if plan.options.milp.rule else 0.0)
    if known is not None:
        info["best_known"] = {
            "stations": known.stations,
            "problem": known.problem,
            "command": known.command,
            "gap": (len(plan.stations) - known.stations) / max(len(plan.stations), 1),
        }
        log.append(known.line(len(plan.stations)))
    return replace(plan, result=replace(plan.result, info=info), log=tuple(log))
