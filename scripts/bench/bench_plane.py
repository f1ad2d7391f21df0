"""Today's pool against the pool grown from coverage regions (issue 12), on the bundled instances.

For each instance and each rule (plain cover; 30 % overlap connected) the MILP runs twice in this one
process: with the pool as before (closed form, samples, corner rays, centres, 10 m grid: ``--set variant=no-regions
--set variant=no-pricing``) and with the whole-zone-side candidates and geometric pricing. Columns: stations, the
MILP's bound, the bound's scope (``pool``: over the candidate pool; ``plane``: over every position,
from pricing), the plane bound, pricing rounds and columns, and wall time (1 thread), one run each.

    python scripts/bench/bench_plane.py [--time-limit 60] [--instances polygon_a ...] [--out docs/benchmarks/plane.md]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from planner.engine import plan_site
from planner.io import load_site
from planner.plan import PlanOptions
from planner.solve.milp import MilpOptions

ROOT = Path(__file__).resolve().parents[2]
INSTANCES = ["polygon_a", "polygon_b", "polygon_c", "baalbek", "building27"]


def row(name: str, connected: bool, new_pool: bool, limit_s: float) -> str:
    site = load_site(ROOT / f"instances/{name}.json")
    milp = MilpOptions(time_limit_s=limit_s) if connected else MilpOptions(time_limit_s=limit_s, overlap=None)
    options = PlanOptions(method="milp", milp=milp, regions=new_pool, pricing=new_pool)
    t0 = time.perf_counter()
    plan = plan_site(site, options)
    wall = time.perf_counter() - t0
    r, info = plan.result, plan.result.info
    pricing = info.get("pricing") or {}
    scope = info.get("bound_scope", "pool")
    plane = info.get("plane_bound")
    return (
        f"| {name} | {'30 % connected' if connected else 'plain cover'} | {'regions + pricing' if new_pool else 'as before'} | "
        f"{len(plan.stations)} | {r.status.value} | {r.bound if r.bound is not None else '-'} | {scope} | "
        f"{plane if plane is not None else '-'} | {pricing.get('rounds', '-')} | {pricing.get('columns_added', '-')} | "
        f"{plan.problem_size['candidates']:,} | {wall:.1f} | {plan.verification.percent:.3f} |"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--time-limit", type=float, default=60.0)
    ap.add_argument("--instances", nargs="+", default=INSTANCES)
    ap.add_argument("--rules", nargs="+", default=["plain", "connected"], choices=["plain", "connected"])
    ap.add_argument("--out")
    a = ap.parse_args()
    lines = [
        "| instance | rule | pool | stations | status | MILP bound | bound scope | plane bound | pricing rounds | "
        "columns added | candidates | wall s | verified % |",
        "|---" * 13 + "|",
    ]
    for name in a.instances:
        for rule in a.rules:
            for new_pool in (False, True):
                lines.append(row(name, rule == "connected", new_pool, a.time_limit))
                print(lines[-1], flush=True)
    if a.out:
        Path(a.out).write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
