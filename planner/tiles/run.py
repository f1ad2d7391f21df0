"""Planning a large site by tiles: pool, tiles with S_max margins, per-tile coverage and MILP
(serially or on Dask), stitching on the whole matrix, a global lower bound, verification.

What holds and why:

- coverage: exact (see :mod:`planner.tiles.layout`): the tiles' columns are the site's matrix;
- each tile's plan is re-checked to cover its core pieces, so their union covers the site;
- registration: the stitched plan is checked on the site's overlap relation (shared wall over every
  piece a station sees) with the groups of :func:`planner.coverage.links.registration_groups` (``site`` mode by default: one
  bundle per accessible area);
- bound: max of the whole-matrix LP and cover-MILP bounds (:mod:`planner.tiles.stitch`) and, with
  ``TileOptions.lagrange``, the Lagrangian bound over the tiles (:mod:`planner.bounds.lagrange`), over
  the pool; the gap is (stations - bound) / stations;
- local search: the kept plan is shrunk by :func:`planner.solve.local_search.shrink` within
  ``TileOptions.local_search_moves`` moves (a count: the plan does not depend on the load); each plan it
  returns is a connected cover, re-verified like any other, and ``info["local_search"]`` records it;
- windows: then the plan is re-solved exactly window by window (:mod:`planner.solve.windows`,
  ``TileOptions.windows``; CP-SAT work per window, so again the same plan under any load), checked the
  same way and recorded in ``info["windows"]``.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np
import scipy.sparse as sp

from planner.bounds.lagrange import group_parts
from planner.candidates.complete import complete_candidates
from planner.core import progress
from planner.core.errors import UsageError
from planner.coverage.matrix import CoverageProblem
from planner.coverage.overlap import OverlapRule
from planner.coverage.regions import regions_apply
from planner.plan import Plan, PlanOptions, unseen_error
from planner.plan.problem import Problem
from planner.plan.verify import verify_stations
from planner.site.candidate import Candidate
from planner.site.model import Site
from planner.solve.milp import WALL_CAP
from planner.solve.result import SolveResult, Status
from planner.tiles.engine import run_tasks
from planner.tiles.options import TileOptions, deterministic_limits, limits_line
from planner.tiles.prepare import prepare, tile_work, tiles_problem
from planner.tiles.search import best_plan, window_resolves
from planner.tiles.stitch import Bound, Stitched, global_bound, stitch
from planner.tiles.tasks import TileResult, tile_task


def _assemble(
    n_cand: int, n_targ: int, results: list[TileResult]
) -> tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix]:
    """The site's matrices (by candidate; slant and incidence on the same pattern) from the tiles' pairs."""
    rows = np.concatenate([r.rows for r in results])
    cols = np.concatenate([r.cols for r in results])
    shape = (n_cand, n_targ)

    def mat(data: np.ndarray) -> sp.csr_matrix:
        m = sp.csr_matrix((data, (rows, cols)), shape=shape)
        m.sort_indices()
        return m

    return (
        mat(np.ones(len(rows), dtype=bool)),
        mat(np.concatenate([r.slant_m for r in results])),
        mat(np.concatenate([r.incidence_deg for r in results])),
    )


def plan_by_tiles(
    site: Site | Problem,
    options: PlanOptions | None = None,
    tiling: TileOptions | None = None,
    client: Any = None,
    extra: tuple[Candidate, ...] = (),
) -> Plan:
    """Plan a resolved problem (or a site, :func:`planner.tiles.prepare.tiles_problem`) by tiles with the MILP
    options of its options (module docstring); on ``client`` (a ``dask.distributed.Client``) when given, else
    in this process. Same seed, same plan either way.

    Raises
    ------
    UsageError
        When the zones are not all in one frame (tiles are squares of one coordinate frame).
    InfeasibleError
        When some piece is seen from no position (its coverage region is empty). A piece that no candidate of
        the pool sees gets one from its region (:func:`planner.candidates.complete.complete_candidates`), and
        the tiles run once more with those candidates added (``extra``).
    """
    resolved = tiles_problem(site, options)
    site, options = resolved.site, resolved.options
    tiling = tiling or TileOptions()
    if len({z.frame for z in site.zones}) != 1:
        raise UsageError("tiles need every zone in one coordinate frame", field="tiles")
    start = time.perf_counter()
    prep = prepare(resolved, extra=extra)
    limits, pool, targets, groups = prep.limits, prep.pool, prep.targets, prep.groups
    jobs, shared = tile_work(tiling, prep)
    t_pool = time.perf_counter() - start
    results = run_tasks(tile_task, jobs, shared, client, describe=_tile_line(len(jobs)))
    t_tiles = time.perf_counter() - start - t_pool
    by_cand, slant, inc = _assemble(len(pool), len(targets), results)
    problem = CoverageProblem(
        candidates=pool,
        targets=targets,
        by_candidate=by_cand,
        by_target=by_cand.T.tocsr(),
        slant_m=slant,
        incidence_deg=inc,
        excluded={int(k): "stands nowhere" for k in np.flatnonzero(~prep.usable)},
        limits=limits,
    )
    unseen = problem.uncoverable()
    if unseen.size:
        done, reasons = (
            complete_candidates(resolved.sight, problem) if options.regions and regions_apply(limits) else (problem, {})
        )
        found = tuple(done.candidates[len(pool) :])
        if found and not extra:  # the tiles again, with a candidate from the region of every unseen piece
            return plan_by_tiles(resolved, None, tiling, client, found)
        err = unseen_error(done, done.uncoverable(), reasons)
        raise err.located(site.source) if site.source else err
    adj = prep.overlap(by_cand)
    joined = stitch(by_cand, adj, groups, [r.selected for r in results])
    t_stitch = time.perf_counter() - start - t_pool - t_tiles
    progress.note(_standing("stitched", joined, None))
    parts = group_parts([(j.tile.row, j.tile.col) for j in jobs], [j.targets for j in jobs], tiling.lagrange_group)
    bound = global_bound(
        by_cand,
        tiling.bound_time_limit_s,
        options.milp.seed,
        work_limited=deterministic_limits(options.milp, tiling),
        wall_cap=WALL_CAP,
        parts=parts if tiling.lagrange else None,
        lagrange_iterations=tiling.lagrange_iterations,
        lagrange_work_s=tiling.lagrange_work_s,
        client=client,
    )
    t_bound = time.perf_counter() - start - t_pool - t_tiles - t_stitch
    progress.note(_standing(f"bound {bound.value} over the pool ({bound.how})", joined, bound.value))
    t_search = time.perf_counter()
    joined, search = best_plan(
        by_cand, adj, groups, joined, bound.cover, tiling.local_search_moves, bound.value, tiling.search_seeds, client
    )
    progress.note(_standing("best plan and local search", joined, bound.value))
    t_windows = time.perf_counter()
    joined, windows = window_resolves(by_cand, adj, groups, joined, prep.xy, tiling.windows, bound.value, client)
    progress.note(_standing("window re-solves", joined, bound.value))
    return _finish(
        resolved,
        problem,
        results,
        joined,
        bound,
        prep.rule,
        (prep.mode, prep.reach_m),
        {
            "pool_s": t_pool,
            "tiles_s": t_tiles,
            "stitch_s": t_stitch,
            "bound_s": t_bound,
            "best_plan_s": t_windows - t_search,
            "windows_s": time.perf_counter() - t_windows,
            "total_s": time.perf_counter() - start,
            "margin_m": tiling.margin_for(limits.max_slant_range_m),
            "tile_m": tiling.tile_m,
        },
        deterministic_limits(options.milp, tiling),
        search,
        windows,
    )


def _tile_line(total: int) -> Callable[[int, TileResult], str]:
    """Each finished tile's progress line: its plan, the tile MILP's bound and status."""

    def line(k: int, r: TileResult) -> str:
        bound = "-" if r.bound is None else f"{r.bound:g}"
        return (
            f"tile {k + 1}/{total} (row {r.tile.row}, col {r.tile.col}): {len(r.selected)} stations, "
            f"tile bound {bound}, {r.status.value}"
        )

    return line


def _standing(phase: str, plan: Stitched, bound: int | None) -> str:
    """Where the tiled run stands after ``phase``: the incumbent (connected or not), and the bound and gap."""
    n, parts = len(plan.selected), sum(plan.parts.values())
    conn = "connected" if all(p <= 1 for p in plan.parts.values()) else f"{parts} registration parts"
    head = f"{phase}: incumbent {n} stations ({conn})"
    return head if bound is None else f"{head}, bound {bound} over the pool, gap {(n - bound) / max(n, 1):.1%}"


def _finish(
    resolved: Problem,
    problem: CoverageProblem,
    results: list[TileResult],
    joined: Stitched,
    bound: Bound,
    rule: OverlapRule,
    registration: tuple[str, float],
    times: dict[str, float],
    work_limited: bool = False,
    search: dict[str, Any] | None = None,
    windows: dict[str, Any] | None = None,
) -> Plan:
    """The :class:`Plan`: status, bound, per-tile figures, registration check and 0.1 m verification."""
    from planner.plan import placed_stations, registration_check

    site, options = resolved.site, resolved.options
    n = len(joined.selected)
    value = bound.value
    status = Status.OPTIMAL if n == value and all(p <= 1 for p in joined.parts.values()) else Status.FEASIBLE
    tiles_info = [
        {
            "tile": r.tile.name,
            "core_m": [r.tile.x0_m, r.tile.y0_m, r.tile.size_m],
            "candidates": int(len(np.unique(r.rows))),
            "targets": r.n_targets,
            "status": r.status.value,
            "stations": len(r.selected),
            "bound": r.bound,
            "covers_core": r.covers_core,
            "coverage_s": round(r.coverage_s, 3),
            "solve_s": round(r.solve_s, 3),
        }
        for r in results
    ]
    capped = (
        [r.tile.name for r in results if r.wall_cap_hit]
        + (["bound"] if bound.wall_cap_hit else [])
        + (["Lagrangian bound"] if bound.lagrange is not None and bound.lagrange.capped else [])
        + (["windows"] if windows and windows.get("wall_cap_hit") else [])
    )
    info = {
        "tiles": tiles_info,
        "bound_scope": "pool",
        "lp_bound": bound.lp,
        "cover_milp_bound": bound.milp,
        "stitch": {
            "source": joined.source,
            "tried": joined.tried,
            "union": joined.union,
            "pruned": joined.pruned,
            "added": joined.added,
        },
        "bound_how": bound.how,
        "lagrange": None
        if bound.lagrange is None
        else {
            "value": bound.lagrange.value,
            "raw": bound.lagrange.raw,
            "lp": bound.lagrange.lp,
            "iterations": bound.lagrange.iterations,
            "per_tile": list(bound.lagrange.per_tile),
            "proven": list(bound.lagrange.proven),
            "upper": bound.lagrange.upper,
            "time_s": round(bound.lagrange.time_s, 3),
        },
        "limits": "CP-SAT work (deterministic s)" if work_limited else "wall clock (s)",
        "wall_cap_hit": capped,
        "local_search": search or {},
        "windows": windows or {},
        "times": {k: round(v, 3) if isinstance(v, float) else v for k, v in times.items()},
    }
    result = SolveResult(
        method="milp-tiles",
        status=status,
        selected=joined.selected,
        objective=float(n),
        bound=float(value),
        time_s=times["total_s"],
        backend=options.milp.backend,
        info=info,
    )
    parts, partners = registration_check(problem, joined.selected, rule, site, *registration)
    stations, tripods = placed_stations(site, problem, joined.selected, options, partners)
    verification = verify_stations(resolved.sight, stations, options.verify_spacing_m)
    size = {
        "candidates": len(problem.candidates),
        "targets": len(problem.targets),
        "pairs": int(problem.by_candidate.nnz),
        "tiles": len(results),
    }
    bad = [r.tile.name for r in results if not r.covers_core]
    log = (
        f"{len(results)} tiles of {times['tile_m']:g} m, margin {times['margin_m']:.1f} m: coverage and tile MILPs "
        f"in {times['tiles_s']:.1f} s"
        + (
            f"; tiles whose plan does not cover their core: {', '.join(bad)}"
            if bad
            else "; every tile's plan covers its core"
        ),
        limits_line(capped, work_limited),
        "connected plans: "
        + ", ".join(f"{k} {v}" for k, v in (joined.tried or {}).items())
        + f"; kept the {joined.source} (union {joined.union}, pruned {joined.pruned}, chains added {joined.added}) -> {n} stations"
        + (
            f"; local search: {search['before']} -> {search['after']} in {search['moves']} moves"
            if search and search["moves"]
            else ""
        )
        + (
            f"; windows: {windows['before']} -> {windows['after']} in {windows['windows']} windows of {windows['radius_m']:g} m"
            if windows and windows["windows"]
            else ""
        ),
        f"bound {value} (LP {bound.lp:.2f}"
        + (
            f", cover MILP {bound.milp:g} {bound.milp_status.value}"
            if bound.milp is not None and bound.milp_status is not None
            else ""
        )
        + (f", Lagrangian over {len(bound.lagrange.per_tile)} parts {bound.lagrange.raw:.2f}" if bound.lagrange else "")
        + f"; registration rule dropped, so it bounds the connected plan too), gap {result.gap:.1%}",
    )
    return Plan(
        problem=resolved,
        result=result,
        stations=tuple(stations),
        verification=verification,
        problem_size=size,
        log=log,
        registration=parts,
        tripods=tripods,
    )
