"""The search after the tiles: the best of the stitched, joined and greedy plans, then the local search and the
window re-solves on it (:func:`best_plan`, :func:`window_resolves`), each recorded for plan.json; for a plan
with no registration rule, the plain cover and its local search (:func:`plain_plan`)."""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

import numpy as np
import scipy.sparse as sp

from planner.solve.connectivity import connected_greedy
from planner.solve.greedy import greedy_cover
from planner.solve.local_search import Shrunk, unlinked
from planner.solve.steiner import steiner_join
from planner.solve.windows import WindowOptions, window_search
from planner.tiles.engine import TaskRunner, run_tasks
from planner.tiles.stitch import Stitched, group_parts, prune, stitch
from planner.tiles.tasks import shrink_task


def best_plan(
    a: sp.csr_matrix,
    adj: sp.csr_matrix,
    groups: tuple[str, ...],
    tiled: Stitched | None,
    cover: tuple[int, ...],
    moves: int = 0,
    floor: int = 1,
    seeds: int = 1,
    client: Any = None,
) -> tuple[Stitched, dict[str, Any]]:
    """The best of the connected plans given or found (fewest registration parts, then fewest stations; ties keep
    the earlier): the stitched tile plans (where ``tiled``), the whole-site plain ``cover`` joined (where given:
    :func:`joined_cover`), and the connected greedy on the whole site
    (:func:`planner.solve.connectivity.connected_greedy`, 20 starts) pruned; where none of them is, Chvatal's
    cover joined as far as the links go; ``tried`` records each. When the kept plan is one bundle per group and
    ``moves`` > 0, the local search (:func:`planner.solve.local_search.shrink`, down to ``floor`` stations, a
    proven bound; once per seed ``0 .. seeds - 1``, on ``client`` when given, the smallest kept, the lowest seed on
    ties) then looks for a smaller connected cover; the second value says what it did."""
    plans = [tiled] if tiled is not None else []
    if cover:
        plans.append(joined_cover(a, adj, groups, cover))
    grown = connected_greedy(a, adj, groups, np.ones(a.shape[0]), np.ones(a.shape[1], dtype=bool), 20)
    if grown is not None:
        plans.append(replace(stitch(a, adj, groups, [grown]), source="connected greedy"))
    if not plans:
        plain = greedy_cover(a).selected
        plans.append(replace(joined_cover(a, adj, groups, tuple(plain)), source="greedy cover, joined"))
    best = min(plans, key=lambda p: (sum(p.parts.values()), len(p.selected)))
    best = replace(best, tried={p.source: len(p.selected) for p in plans})
    return _search(a, adj, groups, best, moves, floor, seeds, client)


def joined_cover(a: sp.csr_matrix, adj: sp.csr_matrix, groups: tuple[str, ...], cover: tuple[int, ...]) -> Stitched:
    """The whole-site plain ``cover`` made one registered network: each group's parts joined by the fewest
    linking stations found (:func:`planner.solve.steiner.steiner_join`), then pruned (stations whose pieces
    others see, dropped while their group stays connected)."""
    grown = steiner_join(adj, groups, cover) or list(cover)  # None: some group cannot be joined at all
    final = prune(a, adj, groups, grown)
    return Stitched(
        selected=tuple(final),
        union=len(cover),
        pruned=len(grown) - len(final),
        added=len(grown) - len(cover),
        parts=group_parts(adj, groups, final),
        source="whole-site cover, joined",
    )


def plain_plan(a: sp.csr_matrix, cover: tuple[int, ...], moves: int, floor: int) -> tuple[Stitched, dict[str, Any]]:
    """The plan of a run with no registration rule: the whole-site plain ``cover``, then the local search with
    no links (:func:`planner.solve.local_search.shrink`, each candidate its own group) for ``moves`` moves, down
    to ``floor`` stations; the second value records the search."""
    start = Stitched(selected=tuple(cover), union=len(cover), pruned=0, added=0, parts={}, source="whole-site cover")
    found, record = _search(a, *unlinked(a.shape[0]), start, moves, floor)
    return replace(found, parts={}, tried=None), record  # no connected plans were tried


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
    n = len(kept.selected)
    record: dict[str, Any] = {"moves_budget": moves, "moves": 0, "before": n, "after": n, "removed": 0, "time_s": 0.0}
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
    return (_improved(kept, adj, groups, found.selected, "local search") if found.removed else kept), record


def window_resolves(
    a: sp.csr_matrix,
    adj: sp.csr_matrix,
    groups: tuple[str, ...],
    kept: Stitched,
    xy: np.ndarray,
    options: WindowOptions,
    floor: int,
    client: Any = None,
) -> tuple[Stitched, dict[str, Any]]:
    """The window re-solves on ``kept`` (a connected plan only) and their record for plan.json; with a ``client``
    and ``options.batch`` > 1 as Dask tasks, that many in flight (the same result as one at a time; not faster on
    few cores, so not the default: docs/studies/plant.md)."""
    on_dask = client is not None and options.batch > 1
    batch = options.batch if on_dask else 1
    n = len(kept.selected)
    record: dict[str, Any] = {"passes": options.passes, "radius_m": options.radius_m, "work_s": options.work_s}
    record.update(windows=0, batch=batch, before=n, after=n, time_s=0.0)
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
    return (_improved(kept, adj, groups, found.selected, "windows") if found.removed else kept), record


def _improved(
    kept: Stitched, adj: sp.csr_matrix, groups: tuple[str, ...], selected: tuple[int, ...], step: str
) -> Stitched:
    """``kept`` with the smaller plan ``selected`` that ``step`` found, its parts, source and ``tried`` entry."""
    return replace(
        kept,
        selected=selected,
        parts=group_parts(adj, groups, selected),
        source=f"{kept.source} + {step}",
        tried={**(kept.tried or {}), step: len(selected)},
    )
