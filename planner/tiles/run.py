"""Planning a large site by tiles: pool, tiles with S_max margins, per-tile coverage and MILP
(serially or on Dask), the whole-site plain cover, a global lower bound, the search, verification.

What holds and why:

- coverage: exact (:mod:`planner.tiles.layout`): the tiles' columns are the site's matrix;
- each tile's plan is re-checked to cover its core pieces, so their union covers the site;
- the whole-site plain cover: CFT (:mod:`planner.solve.cft`; ``TileOptions.cft``), its own iteration counts, no
  clock;
- registration: the stitched plan is checked on the site's overlap relation (shared wall over every piece a
  station sees) in the groups of the problem's registration; with no registration rule (``--no-overlap``) the
  plan is the plain cover and its local search (:func:`planner.tiles.search.plain_plan`), registration reported;
- bound: the largest of the bounds of :mod:`planner.tiles.bound`, over the pool, with the one that decides; the
  gap is (stations - bound) / stations;
- starts of a connected plan and the local search after them: :func:`planner.tiles.search.best_plan` (its move
  budget ``TileOptions.moves_for(pieces)``, a count set by the site's size, so the plan does not depend on the
  load); each plan it returns is a connected cover, re-verified like any other (``info["local_search"]``);
- windows: then the plan is re-solved exactly window by window (:mod:`planner.solve.windows`,
  ``TileOptions.windows``; CP-SAT work per window), checked the same way and recorded in ``info["windows"]``.
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
from planner.coverage.regions import regions_apply
from planner.plan import Plan, PlanOptions, unseen_error
from planner.plan.problem import Problem
from planner.site.candidate import Candidate
from planner.site.model import Site
from planner.solve.cft import CftCover, cft_cover
from planner.solve.milp import WALL_CAP
from planner.tiles.bound import Bound, global_bound
from planner.tiles.engine import run_tasks
from planner.tiles.finish import finish_plan
from planner.tiles.layout import TileJob
from planner.tiles.options import TileOptions, deterministic_limits
from planner.tiles.prepare import Prepared, prepare, tile_work, tiles_problem
from planner.tiles.search import best_plan, plain_plan, window_resolves
from planner.tiles.stitch import Stitched, stitch
from planner.tiles.tasks import TileResult, tile_task


def plan_by_tiles(
    site: Site | Problem,
    options: PlanOptions | None = None,
    tiling: TileOptions | None = None,
    client: Any = None,
    extra: tuple[Candidate, ...] = (),
) -> Plan:
    """Plan a resolved problem (or a site, :func:`planner.tiles.prepare.tiles_problem`) by tiles (module
    docstring); on ``client`` (a ``dask.distributed.Client``) when given, else in this process, the same plan.

    A piece that no candidate of the pool sees gets one from its region
    (:func:`planner.candidates.complete.complete_candidates`), and the tiles run once more with those candidates
    added (``extra``); InfeasibleError where its region is empty. UsageError where the zones are not all in one
    frame (tiles are squares of one coordinate frame).
    """
    resolved = tiles_problem(site, options, tiling)
    site, options = resolved.site, resolved.options
    tiling = tiling or TileOptions()
    if len({z.frame for z in site.zones}) != 1:
        raise UsageError("tiles need every zone in one coordinate frame", field="tiles")
    laps = _Laps()
    prep = prepare(resolved, extra=extra)
    jobs, shared = tile_work(tiling, prep)
    laps("pool_s")
    results = run_tasks(tile_task, jobs, shared, client, describe=_tile_line(len(jobs)))
    laps("tiles_s")
    problem = _site_coverage(prep, results)
    unseen = problem.uncoverable()
    if unseen.size:
        apply = options.regions and regions_apply(prep.limits)
        done, reasons = complete_candidates(resolved.sight, problem) if apply else (problem, {})
        found = tuple(done.candidates[len(prep.pool) :])
        if found and not extra:  # the tiles again, with a candidate from the region of every unseen piece
            return plan_by_tiles(resolved, None, tiling, client, found)
        err = unseen_error(done, done.uncoverable(), reasons)
        raise err.located(site.source) if site.source else err
    kept, bound, search, windows, cover = _search(prep, problem.by_candidate, results, jobs, tiling, client, laps)
    margin = tiling.margin_for(prep.limits.max_slant_range_m)
    times = {**laps.times, "total_s": time.perf_counter() - laps.start, "margin_m": margin, "tile_m": tiling.tile_m}
    limited = deterministic_limits(options.milp, tiling)
    return finish_plan(resolved, problem, results, kept, bound, times, limited, search, windows, cover)


class _Laps:
    """The seconds of each step of a run, each from the end of the one before."""

    def __init__(self) -> None:
        self.start = self.last = time.perf_counter()
        self.times: dict[str, float] = {}

    def __call__(self, name: str) -> None:
        now = time.perf_counter()
        self.times[name], self.last = now - self.last, now


def _site_coverage(prep: Prepared, results: list[TileResult]) -> CoverageProblem:
    """The whole site's coverage problem assembled from the tiles' pairs (slant and incidence on the same pattern)."""
    rows = np.concatenate([r.rows for r in results])
    cols = np.concatenate([r.cols for r in results])

    def mat(data: np.ndarray) -> sp.csr_matrix:
        m = sp.csr_matrix((data, (rows, cols)), shape=(len(prep.pool), len(prep.targets)))
        m.sort_indices()
        return m

    by_cand = mat(np.ones(len(rows), dtype=bool))
    return CoverageProblem(
        candidates=prep.pool,
        targets=prep.targets,
        by_candidate=by_cand,
        by_target=by_cand.T.tocsr(),
        slant_m=mat(np.concatenate([r.slant_m for r in results])),
        incidence_deg=mat(np.concatenate([r.incidence_deg for r in results])),
        excluded={int(k): "stands nowhere" for k in np.flatnonzero(~prep.usable)},
        limits=prep.limits,
    )


def _search(
    prep: Prepared,
    by_cand: sp.csr_matrix,
    results: list[TileResult],
    jobs: list[TileJob],
    tiling: TileOptions,
    client: Any,
    laps: _Laps,
) -> tuple[Stitched, Bound, dict[str, Any], dict[str, Any], CftCover | None]:
    """The plan from the tiles' coverage: the stitched tile plans, CFT's plain cover, the global bound, then the
    best start with its local search and, under a registration rule, the window re-solves."""
    options, groups = prep.problem.options, prep.groups
    plain = prep.problem.rule is None  # --no-overlap: a plain cover, no registration to meet
    adj = None if plain else prep.overlap(by_cand)
    tile_plans = [r.selected for r in results if r.selected]
    joined = stitch(by_cand, adj, groups, tile_plans) if adj is not None and tile_plans else None
    laps("stitch_s")
    if joined is not None:
        progress.note(_standing("stitched", joined, None))
    cover = cft_cover(by_cand, seed=options.milp.seed, heur_iters=tiling.cft_iters) if tiling.cft else None
    laps("cover_s")
    if cover is not None:
        progress.note(f"whole-site plain cover (CFT): {len(cover.selected)} stations in {cover.time_s:.1f} s")
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
        cft=cover.lower_bound if cover is not None else None,
    )
    laps("bound_s")
    progress.note(f"bound {bound.value} over the pool: {bound.how}")
    whole = cover.selected if cover is not None else bound.cover
    moves = tiling.moves_for(len(prep.targets))
    windows: dict[str, Any] = {}
    if adj is None:
        start_cover = whole or tuple(sorted({int(i) for p in tile_plans for i in p}))
        kept, search = plain_plan(by_cand, start_cover, moves, bound.value)
        progress.note(f"plain cover and local search: {len(kept.selected)} stations, bound {bound.value}")
        laps("best_plan_s")
    else:
        kept, search = best_plan(by_cand, adj, groups, joined, whole, moves, bound.value, tiling.search_seeds, client)
        progress.note(_standing("best plan and local search", kept, bound.value))
        laps("best_plan_s")
        kept, windows = window_resolves(by_cand, adj, groups, kept, prep.xy, tiling.windows, bound.value, client)
        progress.note(_standing("window re-solves", kept, bound.value))
    laps("windows_s")
    return kept, bound, search, windows, cover


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
