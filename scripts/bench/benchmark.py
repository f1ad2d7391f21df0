"""Greedy against optimal (and the dissertation's closed form) on the bundled instances.

Usage: python scripts/bench/benchmark.py [--instances polygon_a ...] [--backends cpsat scip ...]
                                   [--time-limit 60] [--out-dir docs/benchmarks]

Protocol: each instance is read from instances/NAME.json (S_max 95.913 m,
theta_max 68 deg, overlap 30 %); pool = closed form + field samples + corner
rays + 10 m grid (seed 0), 1 m targets. Runs the closed form, the greedy, and
the MILP on every backend with and without the registration-overlap
constraint, each once, one thread, seed 0, the given time limit. Every plan
is re-verified at 0.1 m and its registration connectivity recomputed with
networkx. "method s" is the method alone; "total s" includes the coverage
build, the tripod discs (MILP) and the verification. Writes benchmark.csv and
benchmark.md.
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import planner
from planner.coverage.overlap import OverlapRule
from planner.engine import plan_site
from planner.io import load_site
from planner.plan import PlanOptions
from planner.solve.backends import BACKENDS
from planner.solve.milp import MilpOptions

ROOT = Path(__file__).resolve().parents[2]
FIELDS = [
    "instance",
    "method",
    "backend",
    "overlap",
    "stations",
    "inside",
    "outside",
    "bound",
    "gap",
    "status",
    "time_s",
    "total_s",
    "verified_percent",
    "connected",
    "candidates",
    "targets",
]


def run(name: str, method: str, backend: str = "", overlap: bool = False, time_limit: float = 60.0) -> dict:
    site = load_site(ROOT / f"instances/{name}.json")
    milp = MilpOptions(
        backend=backend or "cpsat",
        time_limit_s=time_limit,
        overlap=OverlapRule(site.parameters.overlap) if overlap else None,
    )
    t0 = time.perf_counter()
    plan = plan_site(site, PlanOptions(method=method, milp=milp, tripod=method == "milp"))
    sides = plan.count_by_side()
    r = plan.result
    return {
        "instance": name,
        "method": method,
        "backend": r.backend or "",
        "overlap": "yes" if overlap else "no",
        "connected": "yes" if plan.connected else "no",
        "stations": len(plan.stations),
        "inside": sides.get("inside", 0),
        "outside": sides.get("outside", 0),
        "bound": "" if r.bound is None else f"{r.bound:g}",
        "gap": "" if r.gap is None else f"{r.gap:.3f}",
        "status": r.status.value,
        "time_s": f"{r.time_s:.2f}",
        "total_s": f"{time.perf_counter() - t0:.2f}",
        "verified_percent": f"{plan.verification.percent:.3f}",
        "candidates": plan.problem_size["candidates"],
        "targets": plan.problem_size["targets"],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--instances", nargs="+", default=["polygon_a", "polygon_b", "polygon_c", "baalbek"])
    ap.add_argument("--backends", nargs="+", default=list(BACKENDS), choices=BACKENDS)
    ap.add_argument("--time-limit", type=float, default=60.0)
    ap.add_argument("--out-dir", default=str(ROOT / "docs/benchmarks"))
    args = ap.parse_args()
    rows = []
    for n in args.instances:
        rows += [run(n, "closed-form"), run(n, "greedy")]
        for overlap in (False, True):
            for b in args.backends:
                rows.append(run(n, "milp", b, overlap, args.time_limit))
                print(rows[-1], flush=True)
    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    (out / "results").mkdir(parents=True, exist_ok=True)
    with (out / "results" / "benchmark.csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(rows)
    lines = [
        "| instance | method | backend | overlap | stations (in + out) | bound | gap | status | method s | total s | verified % | connected |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    lines += [
        f"| {r['instance']} | {r['method']} | {r['backend']} | {r['overlap']} | {r['stations']} ({r['inside']} + {r['outside']}) | "
        f"{r['bound']} | {r['gap']} | {r['status']} | {r['time_s']} | {r['total_s']} | {r['verified_percent']} | {r['connected']} |"
        for r in rows
    ]
    (out / "benchmark.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    fig = planner.comparison_figure(rows, f"closed form vs greedy vs optimal (MILP limit {args.time_limit:g} s)")
    fig.savefig(out / "benchmark.png", dpi=110, bbox_inches="tight")
    print(f"wrote {out / 'benchmark.png'}")


if __name__ == "__main__":
    main()
