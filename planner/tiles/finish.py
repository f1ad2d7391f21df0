"""The :class:`planner.plan.Plan` of a tiled run: status, bound and its derivation, per-tile figures, the search's
record, the registration check and the 0.1 m verification, and the summary's lines."""

from __future__ import annotations

from typing import Any

import numpy as np

from planner.coverage.fingerprint import pool_of
from planner.coverage.matrix import CoverageProblem
from planner.plan import Plan, placed_stations
from planner.plan.problem import Problem
from planner.plan.verify import verify_stations
from planner.solve.cft import CftCover
from planner.solve.result import SolveResult, Status
from planner.tiles.bound import Bound
from planner.tiles.options import limits_line
from planner.tiles.stitch import Stitched
from planner.tiles.tasks import TileResult


def finish_plan(
    resolved: Problem,
    problem: CoverageProblem,
    results: list[TileResult],
    joined: Stitched,
    bound: Bound,
    times: dict[str, float],
    work_limited: bool = False,
    search: dict[str, Any] | None = None,
    windows: dict[str, Any] | None = None,
    cover: CftCover | None = None,
) -> Plan:
    """The :class:`Plan`: status, bound, per-tile figures, registration check and 0.1 m verification."""
    site, options = resolved.site, resolved.options
    n, value = len(joined.selected), bound.value
    status = Status.OPTIMAL if n == value and all(p <= 1 for p in joined.parts.values()) else Status.FEASIBLE
    capped = (
        [r.tile.name for r in results if r.wall_cap_hit]
        + (["bound"] if bound.wall_cap_hit else [])
        + (["Lagrangian bound"] if bound.lagrange is not None and bound.lagrange.capped else [])
        + (["windows"] if windows and windows.get("wall_cap_hit") else [])
    )
    info = {
        "tiles": [_tile_info(r) for r in results],
        "bound_scope": "pool",
        **_bound_info(bound, joined, cover),
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
    parts, partners = resolved.registration.check(problem, joined.selected)
    stations, tripods = placed_stations(site, problem, joined.selected, options, partners)
    size = {
        "candidates": len(problem.candidates),
        "targets": len(problem.targets),
        "pairs": int(problem.by_candidate.nnz),
        "tiles": len(results),
    }
    log = (
        _tiles_line(results, times, cover),
        limits_line(capped, work_limited),
        _search_line(joined, search, windows, cover),
        f"bound {value} over the pool, gap {result.gap:.1%}: {bound.how}",
    )
    return Plan(
        problem=resolved,
        result=result,
        stations=tuple(stations),
        verification=verify_stations(resolved.sight, stations, options.verify_spacing_m),
        problem_size=size,
        log=log,
        registration=parts,
        tripods=tripods,
        pool=pool_of(problem),
    )


def _tile_info(r: TileResult) -> dict[str, Any]:
    """One tile's figures in the result's info."""
    return {
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


def _bound_info(bound: Bound, joined: Stitched, cover: CftCover | None) -> dict[str, Any]:
    """The bound's derivation in the result's info (its terms, CFT's cover and the Lagrangian's where run) and
    how the tiles' plans were stitched."""
    lag = bound.lagrange
    return {
        "lp_bound": bound.lp,
        "cover_milp_bound": bound.milp,
        "stitch": {k: getattr(joined, k) for k in ("source", "tried", "union", "pruned", "added")},
        "bound_how": bound.how,
        "bound_decided_by": bound.decides,
        "bound_terms": [{"bound": name, "value": round(raw, 4), "stations": up} for name, raw, up in bound.terms()],
        "cover": None
        if cover is None
        else {
            "engine": "CFT (pycft)",
            "stations": len(cover.selected),
            "lower_bound": round(cover.lower_bound, 4),
            "time_s": round(cover.time_s, 3),
        },
        "lagrange": None
        if lag is None
        else {
            **{k: getattr(lag, k) for k in ("value", "raw", "lp", "iterations")},
            "per_tile": list(lag.per_tile),
            "proven": list(lag.proven),
            "upper": lag.upper,
            "time_s": round(lag.time_s, 3),
        },
    }


def _tiles_line(results: list[TileResult], times: dict[str, float], cover: CftCover | None) -> str:
    """The summary's line on the tiles: how many, their coverage and MILPs, and those that miss their core."""
    head = f"{len(results)} tiles of {times['tile_m']:g} m, margin {times['margin_m']:.1f} m: "
    if not any(r.status is not Status.NO_SOLUTION for r in results):
        plan = "the whole-site plain cover is CFT's" if cover is not None else "the whole-site search makes the plan"
        return head + f"coverage in {times['tiles_s']:.1f} s (no tile MILPs: {plan})"
    bad = [r.tile.name for r in results if not r.covers_core and r.status is not Status.NO_SOLUTION]
    cores = (
        f"; tiles whose plan does not cover their core: {', '.join(bad)}"
        if bad
        else "; every tile's plan covers its core"
    )
    return head + f"coverage and tile MILPs in {times['tiles_s']:.1f} s" + cores


def _search_line(
    joined: Stitched, search: dict[str, Any] | None, windows: dict[str, Any] | None, cover: CftCover | None
) -> str:
    """The summary's line on how the plan was found: the starts tried, the one kept, the local search and the
    window re-solves."""
    n = len(joined.selected)
    head = (
        f"whole-site plain cover by CFT {len(cover.selected)} stations ({cover.time_s:.0f} s, CFT's bound "
        f"{cover.lower_bound:.2f}); "
        if cover is not None
        else ""
    )
    if not joined.tried:  # a plain cover: no registration rule
        body = f"kept the {joined.source}"
    else:
        body = (
            "connected plans: "
            + ", ".join(f"{k} {v}" for k, v in joined.tried.items())
            + f"; kept the {joined.source} (union {joined.union}, pruned {joined.pruned}, linking stations added "
            f"{joined.added})"
        )
    ls = (
        f"; local search: {search['before']} -> {search['after']} in {search['moves']} moves"
        if search and search["moves"]
        else ""
    )
    win = (
        f"; windows: {windows['before']} -> {windows['after']} in {windows['windows']} windows of {windows['radius_m']:g} m"
        if windows and windows["windows"]
        else ""
    )
    return f"{head}{body}{ls}{win} -> {n} stations"
