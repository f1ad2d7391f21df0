"""Benchmark of the generated plants planned by tiles on Dask: 1, 4 and 16 ha, 1 vs 2 workers.

Each run is a child process under ``/usr/bin/time -v`` (its "Maximum resident set size" is the
largest single process: the client or one worker); the child also samples the summed RSS of its
whole process tree (client + Dask workers) every 0.2 s. Per run: candidates, targets, pairs, the
tile phase (coverage + tile MILPs), stitch and bound times, stations, bound, gap, registration
parts, verified %, and the plain greedy (not connected) on the same matrix beside it.

    python scripts/bench/bench_plant.py [--areas 1 4 16] [--workers 1 2] [--tile 100] [--tile-time-limit 20]
        [--search-moves 20000] [--search-seeds 1] [--window-passes 1] [--window-batch 1] [--csv docs/benchmarks/plant.csv] [--figure docs/benchmarks/plant_16ha.png]
    python scripts/bench/bench_plant.py --from-csv a.csv b.csv     # the table and slopes of earlier runs
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import json
import math
import re
import sys
import time
from pathlib import Path

from _timed import TreeRss, json_child

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

FIELDS = [
    "area_ha",
    "workers",
    "tiles",
    "candidates",
    "targets",
    "pairs",
    "tiles_s",
    "stitch_s",
    "bound_s",
    "total_s",
    "stations",
    "bound",
    "lp_bound",
    "gap",
    "parts",
    "verified_percent",
    "greedy",
    "peak_rss_mb",
    "tree_rss_mb",
    "plan_sha1",
    "limits",
    "wall_cap_hit",
    "search_before",
    "search_moves",
    "search_s",
    "windows_before",
    "windows",
    "windows_proven",
    "windows_s",
    "windows_batch",
    "search_seeds",
    "search_per_seed",
]


def one(
    area: float,
    workers: int,
    tile_m: float,
    tile_limit: float,
    bound_limit: float,
    out: Path,
    figure: Path | None,
    search_moves: int = 20_000,
    window_passes: int = 1,
    window_batch: int = 1,
    search_seeds: int = 1,
) -> None:
    """Plan one plant by tiles on ``workers`` Dask workers; write the figures as JSON to ``out``."""
    from planner.candidates.pool import PoolOptions
    from planner.io.load import load_site
    from planner.plan import PlanOptions
    from planner.solve.greedy import greedy_cover
    from planner.solve.windows import WindowOptions
    from planner.tiles import TileOptions, dask_client, plan_by_tiles

    site = load_site(ROOT / "instances" / f"plant_{area:g}ha.json")
    options = PlanOptions(
        method="milp", pricing=False, pool=PoolOptions(grid_spacing_m=10.0)
    )  # the 10-m grid of the published figures (the plain command's 16-ha pool is 4 m since issue 44's finer grid)
    tiling = TileOptions(
        tile_m=tile_m,
        tile_time_limit_s=tile_limit,
        bound_time_limit_s=bound_limit,
        local_search_moves=search_moves,
        search_seeds=search_seeds,
        windows=WindowOptions(passes=window_passes, batch=window_batch),
    )
    with TreeRss() as rss:
        with dask_client(workers) as client:
            plan = plan_by_tiles(site, options, tiling, client=client)
    info = plan.result.info
    row = {
        "area_ha": area,
        "workers": workers,
        "tiles": plan.problem_size["tiles"],
        "candidates": plan.problem_size["candidates"],
        "targets": plan.problem_size["targets"],
        "pairs": plan.problem_size["pairs"],
        **{k: info["times"][k] for k in ("tiles_s", "stitch_s", "bound_s", "total_s")},
        "stations": len(plan.stations),
        "bound": plan.result.bound,
        "lp_bound": round(info["lp_bound"], 2),
        "gap": round(plan.result.gap, 4),
        "parts": sum(plan.registration.values()),
        "verified_percent": round(plan.verification.percent, 3),
        "tree_rss_mb": round(rss.peak / 2**20),
        # which plan: a short hash of the sorted station ids (equal hashes: the same plan), and the limits
        "plan_sha1": hashlib.sha1(",".join(sorted(s.id for s in plan.stations)).encode()).hexdigest()[:10],
        "limits": info.get("limits", ""),
        "wall_cap_hit": " ".join(info.get("wall_cap_hit", [])) or "none",
        # the local search on the kept plan: stations before it, its moves and time
        **{
            k: info.get("local_search", {}).get(f)
            for k, f in (
                ("search_before", "before"),
                ("search_moves", "moves"),
                ("search_s", "time_s"),
                ("search_seeds", "seeds"),
            )
        },
        "search_per_seed": " ".join(str(n) for n in info.get("local_search", {}).get("per_seed", [])),
        # the window re-solves after it: stations before them, windows solved (proven), their time, and
        # how many ran at a time (2 per worker thread on Dask)
        **{
            k: info.get("windows", {}).get(f)
            for k, f in (
                ("windows_before", "before"),
                ("windows", "windows"),
                ("windows_proven", "proven"),
                ("windows_s", "time_s"),
                ("windows_batch", "batch"),
            )
        },
    }
    row["greedy"] = _greedy(site, options, plan, greedy_cover)
    out.write_text(json.dumps(row))
    if figure is not None:
        _figure(plan, tiling, figure)


def _greedy(site, options, plan, greedy_cover) -> int:
    """Chvatal's greedy on the whole pool (no registration rule), for comparison."""
    from planner.plan import build_problem

    return len(greedy_cover(build_problem(site, options).by_candidate).selected)


def _figure(plan, tiling, path: Path) -> None:
    """The plan: objects, obstacles, no-go areas, stations, registration links, tile cores."""
    import matplotlib

    matplotlib.use("Agg")
    import numpy as np
    from matplotlib.figure import Figure
    from matplotlib.patches import Polygon

    from planner.coverage.matrix import build_coverage
    from planner.coverage.overlap import OverlapRule, overlap_graph, piece_lengths
    from planner.coverage.targets import make_targets

    site = plan.site
    targets = make_targets(site, plan.options.target_spacing_m)
    cov = build_coverage(site, plan.stations, targets, _limits(plan))
    g = overlap_graph(
        cov.by_candidate,
        piece_lengths(targets.s0_m, targets.s1_m),
        range(len(plan.stations)),
        OverlapRule(site.parameters.overlap),
    )
    fig = Figure(figsize=(9, 9))
    ax = fig.add_subplot()
    for z in site.zones:
        ax.add_patch(Polygon(z.xy, closed=True, fc="0.85", ec="0.2", lw=0.6))
    for ob in site.obstacles:
        ax.add_patch(Polygon(ob.vertices, closed=True, fc="0.5", ec="0.3", lw=0.4))
    for n in site.no_go_areas:
        ax.add_patch(Polygon(n.vertices, closed=True, fc="mistyrose", ec="red", lw=0.4))
    ax.add_patch(Polygon(site.boundary, closed=True, fill=False, ec="k", lw=1.0))
    xy = np.array([s.xy for s in plan.stations])
    for u, v in g.edges:
        ax.plot(*xy[[u, v]].T, color="tab:blue", lw=0.6, alpha=0.7)
    ax.plot(*xy.T, "o", color="tab:red", ms=3.5, label=f"{len(xy)} stations")
    for t in plan.result.info["tiles"]:  # tile cores (a zone's pieces go to the tile holding its centre)
        x0, y0, size = t["core_m"]
        ax.add_patch(
            Polygon(
                [(x0, y0), (x0 + size, y0), (x0 + size, y0 + size), (x0, y0 + size)],
                closed=True,
                fill=False,
                ec="tab:green",
                ls=":",
                lw=0.8,
            )
        )
    r = plan.result
    ax.set_title(
        f"{site.name}: {len(xy)} stations, bound {r.bound:g} (gap {r.gap:.1%}), "
        f"{sum(plan.registration.values())} registration bundle(s); blue: overlap links, green: tiles",
        fontsize=9,
    )
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.legend(loc="upper right", fontsize=8)
    fig.savefig(path, dpi=110, bbox_inches="tight")


def _limits(plan):
    from planner.plan import plan_limits as limits

    return limits(plan.validation, plan.options)


def run(area: float, workers: int, args: argparse.Namespace, figure: Path | None) -> dict:
    args_ = [
        "--one",
        f"{area:g}",
        "--workers",
        str(workers),
        "--tile",
        str(args.tile),
        "--tile-time-limit",
        str(args.tile_time_limit),
        "--bound-time-limit",
        str(args.bound_time_limit),
        "--search-moves",
        str(args.search_moves),
        "--window-passes",
        str(args.window_passes),
        "--window-batch",
        str(args.window_batch),
        "--search-seeds",
        str(args.search_seeds),
    ]
    args_ += ["--figure", str(figure)] if figure is not None else []
    t0 = time.perf_counter()
    row = json_child(__file__, args_, f"run {area} ha x {workers}")
    row["wall_s"] = round(time.perf_counter() - t0, 1)
    return row


def slopes(rows: list[dict], key: str) -> str:
    """Log-log slope of ``key`` against area between consecutive areas (at the largest worker count; of
    several runs of one area, e.g. other window batches, the first)."""
    w = max(r["workers"] for r in rows)
    first: dict[float, float] = {}
    for r in rows:
        if r["workers"] == w and r[key]:
            first.setdefault(r["area_ha"], r[key])
    pts = sorted(first.items())
    return ", ".join(
        f"{a0:g}->{a1:g} ha: {math.log(v1 / v0) / math.log(a1 / a0):.2f}" for (a0, v0), (a1, v1) in zip(pts, pts[1:])
    )


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--areas", type=float, nargs="+", default=[1, 4, 16])
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--tile", type=float, default=100.0)
    ap.add_argument("--tile-time-limit", type=float, default=20.0)
    ap.add_argument("--bound-time-limit", type=float, default=60.0)
    ap.add_argument("--search-moves", type=int, default=20_000, help="local search moves on the kept plan (0: none)")
    ap.add_argument("--search-seeds", type=int, default=1, help="local searches with seeds 0..N-1, the smallest kept")
    ap.add_argument(
        "--window-passes", type=int, default=1, help="passes of window re-solves after the search (0: none)"
    )
    ap.add_argument(
        "--window-batch", type=int, default=1, help="windows in flight as Dask tasks (1: one at a time in the client)"
    )
    ap.add_argument("--csv", type=Path, default=None)
    ap.add_argument(
        "--figure", type=Path, default=None, help="figure of the largest plant's plan (at the most workers)"
    )
    ap.add_argument(
        "--from-csv",
        type=Path,
        nargs="+",
        default=None,
        help="print the table and slopes of CSVs written earlier (runs nothing)",
    )
    ap.add_argument("--one", type=float, default=None, help=argparse.SUPPRESS)
    ap.add_argument("--json", type=Path, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one is not None:
        one(
            args.one,
            args.workers[0],
            args.tile,
            args.tile_time_limit,
            args.bound_time_limit,
            args.json,
            args.figure,
            args.search_moves,
            args.window_passes,
            args.window_batch,
            args.search_seeds,
        )
        return 0
    rows = []
    if args.from_csv:
        for path in args.from_csv:
            with path.open() as f:
                rows += [
                    {k: (float(v) if re.fullmatch(r"-?[0-9.]+", v or "") else v) for k, v in r.items()}
                    for r in csv.DictReader(f)
                ]
    else:
        for area in args.areas:
            for w in args.workers:
                fig = args.figure if (area == max(args.areas) and w == max(args.workers)) else None
                rows.append(run(area, w, args, fig))
                print(json.dumps(rows[-1]), flush=True)
    print("| " + " | ".join(FIELDS + ["wall_s"]) + " |")
    print("|" + "---|" * (len(FIELDS) + 1))
    for r in rows:
        print("| " + " | ".join(str(r.get(k, "")) for k in FIELDS + ["wall_s"]) + " |")
    print(f"log-log slope of the tile phase time against area: {slopes(rows, 'tiles_s')}")
    print(f"log-log slope of the summed peak RSS against area: {slopes(rows, 'tree_rss_mb')}")
    if args.csv and not args.from_csv:
        with args.csv.open("w", newline="") as f:
            wr = csv.DictWriter(f, fieldnames=FIELDS + ["wall_s"])
            wr.writeheader()
            wr.writerows(rows)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
