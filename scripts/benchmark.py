"""Greedy against optimal (and the dissertation's closed form) on the bundled instances.

Usage: python scripts/benchmark.py [--instances polygon_a ...] [--methods closed-form greedy]
                                   [--out-dir docs/benchmarks]

Protocol: each instance is read from instances/NAME.json (S_max 95.913 m,
theta_max 68 deg, overlap 30 %); one pool per instance (closed form + field
samples + corner rays + 10 m grid, seed 0) and 1 m targets; each method runs
once in this process, single-threaded; every plan is re-verified at 0.1 m.
Times are wall-clock seconds of the method alone (the coverage build is
reported separately). Writes benchmark.csv and benchmark.md.
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

from planner.plan import METHODS, PlanOptions, plan_site
from planner.site import load_site

ROOT = Path(__file__).resolve().parent.parent
FIELDS = ["instance", "method", "backend", "stations", "inside", "outside", "bound", "gap", "status", "time_s",
          "total_s", "verified_percent", "candidates", "targets"]


def run(name: str, method: str) -> dict:
    site = load_site(ROOT / f"instances/{name}.json")
    t0 = time.perf_counter()
    plan = plan_site(site, PlanOptions(method=method))
    sides = plan.count_by_side()
    r = plan.result
    return {"instance": name, "method": method, "backend": r.backend or "", "stations": len(plan.stations),
            "inside": sides.get("inside", 0), "outside": sides.get("outside", 0),
            "bound": "" if r.bound is None else f"{r.bound:g}", "gap": "" if r.gap is None else f"{r.gap:.3f}",
            "status": r.status.value, "time_s": f"{r.time_s:.2f}", "total_s": f"{time.perf_counter() - t0:.2f}",
            "verified_percent": f"{plan.verification.percent:.3f}", "candidates": plan.problem_size["candidates"],
            "targets": plan.problem_size["targets"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--instances", nargs="+", default=["polygon_a", "polygon_b", "polygon_c", "baalbek"])
    ap.add_argument("--methods", nargs="+", default=list(METHODS), choices=METHODS)
    ap.add_argument("--out-dir", default=str(ROOT / "docs/benchmarks"))
    args = ap.parse_args()
    rows = [run(n, m) for n in args.instances for m in args.methods]
    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    with (out / "benchmark.csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(rows)
    lines = ["| instance | method | backend | stations (in + out) | bound | gap | status | method s | total s | verified % |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    lines += [f"| {r['instance']} | {r['method']} | {r['backend']} | {r['stations']} ({r['inside']} + {r['outside']}) | "
              f"{r['bound']} | {r['gap']} | {r['status']} | {r['time_s']} | {r['total_s']} | {r['verified_percent']} |"
              for r in rows]
    (out / "benchmark.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
