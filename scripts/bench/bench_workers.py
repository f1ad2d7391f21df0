"""The tile phase of a plant on 1, 2, 4, 8 and 16 Dask workers (issue 34): speed-up of the distributed engine.

The pool, pieces and tiles of the plant are made once (:func:`planner.tiles.prepare.prepare`, as
:func:`planner.tiles.plan_by_tiles` makes them); then for each worker count an embedded ``LocalCluster`` starts
(one thread and ``--worker-memory`` each) and the tile tasks run on it: each tile's coverage and its MILP
(CP-SAT, one thread, ``--tile-work`` deterministic seconds, the plain command's split on a 2-core machine by
default), exactly the tasks the plain command sends. The same work limit on every count, so every count must give
the same tile plans (checked: the script fails otherwise) and the times compare like for like. Also the same
tasks in this process with no Dask ("0 workers"). Per count: cluster start, the tile phase (scatter, tasks,
gather), speed-up over 1 worker, the summed CPU seconds of the workers, the peak RSS of the client and of every
process (sampled every 0.2 s).

    python scripts/bench/bench_workers.py [--area 16] [--workers 0 1 2 4 8 16] [--tile-work 7.875]
        [--worker-memory 1.5GiB] [--json rows.json]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path
from typing import Any

from _timed import ROOT, TreeRss


def problem(area: float, tile_work_s: float) -> tuple[list[Any], dict[str, Any], float]:
    """The tile jobs and the shared values of the plant's plain tiled plan, and the seconds they took."""
    from planner.coverage.links import default_registration
    from planner.io.load import load_site
    from planner.plan import PlanOptions
    from planner.tiles import TileOptions
    from planner.tiles.prepare import prepare, tile_work

    t0 = time.perf_counter()
    site = load_site(ROOT / "instances" / f"plant_{area:g}ha.json")
    # the registration mode the plain command's tiles use: the single model's (the site's default)
    options = PlanOptions(method="milp", registration=default_registration(site).mode)
    jobs, shared = tile_work(TileOptions(tile_time_limit_s=tile_work_s), prepare(site, options))
    return jobs, shared, time.perf_counter() - t0


def one(workers: int, jobs: list[Any], shared: dict[str, Any], memory: str) -> tuple[dict[str, Any], list[Any]]:
    """The tile tasks on ``workers`` Dask workers (0: in this process); the row and the tiles' plans."""
    import psutil

    from planner.tiles import dask_client
    from planner.tiles.engine import run_tasks
    from planner.tiles.tasks import tile_task

    row: dict[str, Any] = {"workers": workers}
    with TreeRss() as tree:
        t0 = time.perf_counter()
        if workers == 0:
            cpu0 = time.process_time()
            results = run_tasks(tile_task, jobs, shared)
            row["cpu_s"] = time.process_time() - cpu0
        else:
            with dask_client(workers, memory_per_worker=memory) as client:
                client.wait_for_workers(workers)
                row["start_s"] = time.perf_counter() - t0
                t0 = time.perf_counter()
                results = run_tasks(tile_task, jobs, shared, client)
                pids = client.run(os.getpid)
                row["cpu_s"] = sum(sum(psutil.Process(p).cpu_times()[:2]) for p in pids.values())
        row["tiles_s"] = time.perf_counter() - t0
    row["tree_gib"] = tree.peak / 2**30
    row["client_gib"] = psutil.Process().memory_info().rss / 2**30
    # each tile's own seconds in its task (coverage + MILP): the largest is the phase's floor on any count
    own = [r.coverage_s + r.solve_s for r in results]
    row["tile_own_max_s"], row["tile_own_sum_s"] = max(own), sum(own)
    plans = [(r.tile.row, r.tile.col, r.selected) for r in results]
    row["stations"] = sum(len(p[2]) for p in plans)
    return row, plans


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--area", type=float, default=16)
    ap.add_argument("--workers", type=int, nargs="+", default=[0, 1, 2, 4, 8, 16])
    ap.add_argument("--tile-work", type=float, default=7.875, help="CP-SAT deterministic seconds per tile MILP")
    ap.add_argument("--worker-memory", default="1.5GiB")
    ap.add_argument("--json", type=Path, default=None)
    a = ap.parse_args()
    jobs, shared, prep_s = problem(a.area, a.tile_work)
    print(
        f"plant {a.area:g} ha: {len(jobs)} tiles, {len(shared['candidates']):,} candidates, prepared in {prep_s:.1f} s"
    )
    print(f"machine: {os.cpu_count()} cores")
    rows, first = [], None
    for w in a.workers:
        row, plans = one(w, jobs, shared, a.worker_memory)
        first = first or plans
        if plans != first:
            raise SystemExit(f"{w} workers gave other tile plans than {a.workers[0]}: the work limits did not hold")
        base = next((r["tiles_s"] for r in rows if r["workers"] == 1), row["tiles_s"] if w == 1 else None)
        row["speedup"] = base / row["tiles_s"] if base else None
        rows.append(row)
        print(json.dumps({k: round(v, 3) if isinstance(v, float) else v for k, v in row.items()}), flush=True)
        if a.json:
            a.json.write_text(json.dumps({"area_ha": a.area, "tiles": len(jobs), "prepare_s": prep_s, "rows": rows}))
    print(
        "| workers | cluster start s | tile phase s | speed-up over 1 worker | workers' CPU s | peak GiB, all processes |"
    )
    print("|---|---|---|---|---|---|")
    for r in rows:
        sp_ = f"{r['speedup']:.2f}" if r.get("speedup") else "-"
        print(
            f"| {r['workers'] or 'none (this process)'} | {r.get('start_s', 0):.1f} | {r['tiles_s']:.1f} | {sp_} | "
            f"{r['cpu_s']:.1f} | {r['tree_gib']:.2f} |"
        )
    print(f"tile plans equal on every count: {len(first or [])} tiles, {rows[0]['stations']} stations in all")


if __name__ == "__main__":
    main()
