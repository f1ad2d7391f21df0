"""Benchmark of the Lagrangian bound over tiles on the generated plants (issue 14).

Each setting runs as a child under ``/usr/bin/time -v`` (peak RSS of the child: the whole-site coverage
matrix, built as the tiles code builds it, the old bound and the Lagrangian bound). Per run: LP of the
whole cover, the old bound (max(ceil LP, cover-MILP bound at ``--bound-work`` CP-SAT deterministic
seconds)) and its time, the Lagrangian bound (raw and rounded up), its time and how many parts were proven.

    python scripts/bench/bench_lagrange.py --area 4 --group 1 --iterations 0 --work 10 [--csv out.csv]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from _timed import append_csv, json_child

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

FIELDS = [
    "area_ha",
    "group",
    "parts",
    "iterations",
    "work_s",
    "candidates",
    "pieces",
    "lp",
    "old_bound",
    "old_bound_s",
    "lagrange_raw",
    "lagrange",
    "lagrange_s",
    "parts_proven",
    "upper",
    "peak_rss_mb",
]


def one(area: float, group: int, iterations: int, work: float, bound_work: float) -> dict:
    """Matrix as :func:`planner.tiles.run.plan_by_tiles` has it (the tiles' columns are the site's), then bounds."""
    import numpy as np

    from planner.bounds.lagrange import group_parts
    from planner.candidates.pool import PoolOptions
    from planner.io.load import load_site
    from planner.plan import PlanOptions
    from planner.tiles.bound import global_bound
    from planner.tiles.layout import make_tiles, zone_anchors
    from planner.tiles.prepare import prepare

    site = load_site(ROOT / "instances" / f"plant_{area:g}ha.json")
    prep = prepare(
        site, PlanOptions(method="milp", pricing=False, pool=PoolOptions(grid_spacing_m=10.0))
    )  # the 10-m grid of the published figures (the plain command's 16-ha pool is 4 m since issue 44's finer grid)
    a, targets, limits = prep.coverage(), prep.targets, prep.limits
    anchor = zone_anchors(site, targets)
    tiles = make_tiles(anchor, 100.0, limits.max_slant_range_m)
    parts = group_parts([(t.row, t.col) for t in tiles], [np.flatnonzero(t.in_core(anchor)) for t in tiles], group)
    t0 = time.perf_counter()
    old = global_bound(a, bound_work, work_limited=True)
    t1 = time.perf_counter()
    new = global_bound(a, 0, parts=parts, lagrange_iterations=iterations, lagrange_work_s=work).lagrange
    assert new is not None
    return {
        "area_ha": area,
        "group": group,
        "parts": len(parts),
        "iterations": new.iterations,
        "work_s": work,
        "candidates": a.shape[0],
        "pieces": a.shape[1],
        "lp": round(old.lp, 3),
        "old_bound": old.value,
        "old_bound_s": round(t1 - t0, 1),
        "lagrange_raw": round(new.raw, 3),
        "lagrange": new.value,
        "lagrange_s": round(new.time_s, 1),
        "parts_proven": sum(new.proven),
        "upper": new.upper,
    }


def run(args: argparse.Namespace) -> dict:
    return json_child(
        __file__,
        [
            "--one",
            "--area",
            f"{args.area:g}",
            "--group",
            str(args.group),
            "--iterations",
            str(args.iterations),
            "--work",
            str(args.work),
            "--bound-work",
            str(args.bound_work),
        ],
        "run",
    )


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--area", type=float, default=4)
    ap.add_argument("--group", type=int, default=1)
    ap.add_argument("--iterations", type=int, default=0)
    ap.add_argument("--work", type=float, default=10.0)
    ap.add_argument("--bound-work", type=float, default=15.0)
    ap.add_argument("--csv", type=Path, default=None, help="append the row to this CSV")
    ap.add_argument("--one", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--json", type=Path, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        args.json.write_text(json.dumps(one(args.area, args.group, args.iterations, args.work, args.bound_work)))
        return 0
    row = run(args)
    print(json.dumps(row), flush=True)
    if args.csv:
        append_csv(args.csv, FIELDS, [row])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
