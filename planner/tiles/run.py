"""Planning a large site by tiles: pool, tiles with S_max margins, per-tile coverage and MILP
(serially or on Dask), stitching on the whole matrix, a global lower bound, verification.

What holds and why:

- coverage: exact (see :mod:`planner.tiles.layout`): the tiles' columns are the site's matrix;
- each tile's plan is re-checked to cover its core pieces, so their union covers the site;
- registration: the stitched plan is checked on the site's overlap relation (shared wall over every
  piece a station sees) with the groups of :func:`planner.coverage.links.registration_groups` (``site`` mode by default: one
  bundle per accessible area);
- bound: max of the whole-matrix LP and cover-MILP bounds (:mod:`planner.tiles.stitch`) and, with
  ``TileOptions.lagrange``, the Lagrangian bound over the tiles (:mod:`planner.tiles.lagrange`), over
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
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import scipy.sparse as sp

from planner.candidates.complete import complete_candidates
from planner.coverage.matrix import CoverageProblem
from planner.coverage.overlap import OverlapRule
from planner.coverage.regions import regions_apply
from planner.errors import UsageError
from planner.plan import Plan, PlanOptions, unseen_error
from planner.plan.verify import verify_stations
from planner.site.candidate import Candidate
from planner.site.model import Site
from planner.site.validate import ValidationReport
from planner.solve.connectivity import components, connected_greedy, group_members
from planner.solve.local_search import Shrunk
from planner.solve.milp import WALL_CAP, MilpOptions
from planner.solve.result import SolveResult, Status
from planner.solve.windows import WindowOptions, window_search
from planner.tiles.engine import TaskRunner, run_tasks
from planner.tiles.lagrange import group_parts
from planner.tiles.layout import make_tiles, tile_job, zone_anchors
from planner.tiles.prepare import prepare
from planner.tiles.stitch import Bound, Stitched, global_bound, stitch
from planner.tiles.tasks import TileResult, shrink_task, tile_task


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
    LP-dual split only, 10 s: 75-116 s on the 16-ha plant, docs/benchmarks/plant.md). ``windows``: the
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
    site: Site,
    options: PlanOptions | None = None,
    tiling: TileOptions | None = None,
    client: Any = None,
    extra: tuple[Candidate, ...] = (),
    validation: ValidationReport | None = None,
) -> Plan:
    """Plan ``site`` by tiles with the MILP options of ``options`` (module docstring); on ``client``
    (a ``dask.distributed.Client``) when given, else in this process. Same seed, same plan either way.

    Raises
    ------
    UsageError
        When the zones are not all in one frame (tiles are squares of one coordinate frame).
    InfeasibleError
        When some piece is seen from no position (its coverage region is empty). A piece that no candidate of
        the pool sees gets one from its region (:func:`planner.candidates.complete.complete_candidates`), and
        the tiles run once more with those candidates added (``extra``).
    """
    options = (options or PlanOptions(method="milp")).for_site(site)
    tiling = tiling or TileOptions()
    if len({z.frame for z in site.zones}) != 1:
        raise UsageError("tiles need every zone in one coordinate frame", field="tiles")
    start = time.perf_counter()
    prep = prepare(site, options, validation, extra=extra)
    limits, pool, targets, groups = prep.limits, prep.pool, prep.targets, prep.groups
    margin = limits.max_slant_range_m if tiling.margin_m is None else tiling.margin_m
    anchor = zone_anchors(site, targets)
    tiles = make_tiles(anchor, tiling.tile_m, margin)
    jobs = [tile_job(t, anchor, targets, prep.xy, prep.usable) for t in tiles]
    t_pool = time.perf_counter() - start
    shared = {
        "site": site,
        "candidates": pool,
        "targets": targets,
        "limits": limits,
        "groups": groups,
        "milp": _tile_milp(options, tiling),
    }
    results = run_tasks(tile_task, jobs, shared, client)
    t_tiles = time.perf_counter() - start - t_pool
    by_cand, slant, inc = _assemble(len(pool), len(targets), results)
    problem = CoverageProblem(
        pool,
        targets,
        by_cand,
        by_cand.T.tocsr(),
        slant,
        inc,
        {int(k): "stands nowhere" for k in np.flatnonzero(~prep.usable)},
        limits,
    )
    unseen = problem.uncoverable()
    if unseen.size:
        done, reasons = (
            complete_candidates(site, problem, limits) if options.regions and regions_apply(limits) else (problem, {})
        )
        found = tuple(done.candidates[len(pool) :])
        if found and not extra:  # the tiles again, with a candidate from the region of every unseen piece
            return plan_by_tiles(site, options, tiling, client, found, prep.validation)
        err = unseen_error(done, done.uncoverable(), reasons)
        raise err.located(site.source) if site.source else err
    adj = prep.overlap(by_cand)
    joined = stitch(by_cand, adj, groups, [r.selected for r in results])
    t_stitch = time.perf_counter() - start - t_pool - t_tiles
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
    t_search = time.perf_counter()
    joined, search = best_plan(
        by_cand, adj, groups, joined, bound.cover, tiling.local_search_moves, bound.value, tiling.search_seeds, client
    )
    t_windows = time.perf_counter()
    joined, windows = _windows(by_cand, adj, groups, joined, prep.xy, tiling.windows, bound.value, client)
    return _finish(
        site,
        options,
        prep.validation,
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
            "margin_m": margin,
            "tile_m": tiling.tile_m,
        },
        deterministic_limits(options.milp, tiling),
        search,
        windows,
    )


def best_plan(
    a: sp.csr_matrix,
    adj: sp.csr_matrix,
    groups: tuple[str, ...],
    tiled: Stitched,
    cover: tuple[int, ...],
    moves: int = 0,
    floor: int = 1,
    seeds: int = 1,
    client: Any = None,
) -> tuple[Stitched, dict[str, Any]]:
    """The best of three connected plans (fewest registration parts, then fewest stations; ties keep the
    earlier): the stitched tile plans, the whole-site cover joined, and the connected greedy on the whole
    site (:func:`planner.solve.connectivity.connected_greedy`, 20 starts) pruned; ``tried`` records all
    three. When the kept plan is one bundle per group and ``moves`` > 0, the local search
    (:func:`planner.solve.local_search.shrink`, down to ``floor`` stations, a proven bound; once per seed
    ``0 .. seeds - 1``, on ``client`` when given, the smallest kept, the lowest seed on ties)
    then looks for a smaller connected cover; the second value says what it did."""
    plans = [tiled]
    if cover:
        plans.append(replace(stitch(a, adj, groups, [cover]), source="whole-site cover, joined"))
    grown = connected_greedy(a, adj, groups, np.ones(a.shape[0]), np.ones(a.shape[1], dtype=bool), 20)
    if grown is not None:
        plans.append(replace(stitch(a, adj, groups, [grown]), source="connected greedy"))
    best = min(plans, key=lambda p: (sum(p.parts.values()), len(p.selected)))
    best = replace(best, tried={p.source: len(p.selected) for p in plans})
    return _search(a, adj, groups, best, moves, floor, seeds, client)


def _search(
    a: sp.csr_matrix,
    adj: sp.csr_matrix,
    groups: tuple[str, ...],
    kept: Stitched,
    moves: int,
    floor: int,
    seeds: int = 1,
    client: Any = None,
) -> tuple[Stitched, dict[str, Any]]:
    """The local search on ``kept`` (see :func:`best_plan`) and its record for plan.json."""
    record: dict[str, Any] = {
        "moves_budget": moves,
        "moves": 0,
        "before": len(kept.selected),
        "after": len(kept.selected),
        "removed": 0,
        "time_s": 0.0,
    }
    if moves <= 0 or any(p > 1 for p in kept.parts.values()):  # it starts from a connected cover only
        return kept, record
    t0 = time.perf_counter()
    shared = {"a": a, "adj": adj, "groups": groups, "plan": kept.selected, "moves": moves, "floor": floor}
    runs: list[Shrunk] = run_tasks(
        shrink_task, list(range(seeds)), shared, client if seeds > 1 else None, step="search"
    )
    seed = min(range(seeds), key=lambda k: (len(runs[k].selected), k))
    found = runs[seed]
    record.update(
        moves=found.moves,
        after=len(found.selected),
        removed=found.removed,
        time_s=round(time.perf_counter() - t0, 3),
        history=[list(h) for h in found.history],
        seeds=seeds,
        seed=seed,
        per_seed=[len(r.selected) for r in runs],
    )
    if not found.removed:
        return kept, record
    return _improved(kept, adj, groups, found.selected, "local search"), record


def _windows(
    a: sp.csr_matrix,
    adj: sp.csr_matrix,
    groups: tuple[str, ...],
    kept: Stitched,
    xy: np.ndarray,
    options: WindowOptions,
    floor: int,
    client: Any = None,
) -> tuple[Stitched, dict[str, Any]]:
    """The window re-solves on ``kept`` (a connected plan only) and their record for plan.json; with a
    ``client`` and ``options.batch`` > 1 as Dask tasks, that many in flight (the same result as one at a
    time; on the 2-core machine no faster, so not the default: docs/benchmarks/plant.md)."""
    on_dask = client is not None and options.batch > 1
    batch = options.batch if on_dask else 1
    record: dict[str, Any] = {
        "passes": options.passes,
        "radius_m": options.radius_m,
        "work_s": options.work_s,
        "windows": 0,
        "batch": batch,
        "before": len(kept.selected),
        "after": len(kept.selected),
        "time_s": 0.0,
    }
    if options.passes <= 0 or any(p > 1 for p in kept.parts.values()):
        return kept, record
    found = window_search(a, adj, groups, kept.selected, xy, options, floor, TaskRunner(client) if on_dask else None)
    record.update(
        windows=found.windows,
        proven=found.proven,
        wall_cap_hit=found.wall_cap_hit,
        after=len(found.selected),
        time_s=round(found.time_s, 3),
        history=[list(h) for h in found.history],
    )
    if not found.removed:
        return kept, record
    return _improved(kept, adj, groups, found.selected, "windows"), record


def _improved(
    kept: Stitched, adj: sp.csr_matrix, groups: tuple[str, ...], selected: tuple[int, ...], step: str
) -> Stitched:
    """``kept`` with the smaller plan ``selected`` that ``step`` found: its parts per group, its source and
    ``tried`` entry."""
    parts = {g: len(components(adj, m)) for g, m in group_members(groups, selected).items()}
    return replace(
        kept,
        selected=selected,
        parts=parts,
        source=f"{kept.source} + {step}",
        tried={**(kept.tried or {}), step: len(selected)},
    )


def deterministic_limits(milp: MilpOptions, tiling: TileOptions) -> bool:
    """Whether the tile and bound MILPs run on CP-SAT work limits (see :class:`TileOptions`)."""
    return tiling.deterministic and milp.backend == "cpsat" and milp.threads == 1


def _limits_line(capped: list[str], work_limited: bool) -> str:
    if not work_limited:
        return "MILP limits: wall clock (a time-limited tile may end at another plan under another load)"
    return "MILP limits: CP-SAT work in deterministic seconds (same plan under any load, serial or on Dask)" + (
        f"; wall-clock cap reached in {', '.join(capped)}: those answers may depend on the load" if capped else ""
    )


def _tile_milp(options: PlanOptions, tiling: TileOptions) -> MilpOptions:
    limit = tiling.tile_time_limit_s
    if deterministic_limits(options.milp, tiling):
        return options.milp.with_work_limit(limit, WALL_CAP)
    return replace(options.milp, time_limit_s=limit)


def _finish(
    site: Site,
    options: PlanOptions,
    validation: ValidationReport,
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
        "milp-tiles",
        status,
        joined.selected,
        float(n),
        bound=float(value),
        time_s=times["total_s"],
        backend=options.milp.backend,
        info=info,
    )
    parts, partners = registration_check(problem, joined.selected, rule, site, *registration)
    stations, tripods = placed_stations(site, problem, joined.selected, options, partners)
    verification = verify_stations(site, stations, problem.limits, options.verify_spacing_m)
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
        _limits_line(capped, work_limited),
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
    return Plan(site, options, validation, result, tuple(stations), verification, size, log, parts, tripods)
