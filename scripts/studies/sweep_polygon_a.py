"""Parameter sweep on polygon A with the public API only: theta_max 60/68/75 deg x overlap 20/30/40 %.

For each setting: the closed form, the greedy, and the MILP with the registration-overlap
constraint (CP-SAT, one thread, seed 0, ``--time-limit`` per solve), printing stations, the
MILP bound and status. Usage::

    python scripts/studies/sweep_polygon_a.py [--time-limit 30] [--site instances/polygon_a.json]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import planner

ROOT = Path(__file__).resolve().parents[2]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--site", default=str(ROOT / "instances/polygon_a.json"))
    ap.add_argument("--time-limit", type=float, default=30.0)
    ap.add_argument("--thetas", type=float, nargs="+", default=[60.0, 68.0, 75.0])
    ap.add_argument("--overlaps", type=float, nargs="+", default=[0.20, 0.30, 0.40])
    args = ap.parse_args()
    base = planner.load_site(args.site)
    print("| theta_max deg | overlap | closed form | greedy | MILP + overlap | bound | status | MILP s | verified % |")
    print("|---|---|---|---|---|---|---|---|---|")
    for theta in args.thetas:
        for overlap in args.overlaps:
            site = base.with_parameters(theta_max_deg=theta, overlap=overlap)
            counts = {}
            for method in ("closed-form", "greedy"):
                counts[method] = len(planner.plan_site(site, planner.PlanOptions(method=method)).stations)
            milp = planner.MilpOptions(time_limit_s=args.time_limit, overlap=planner.OverlapRule(overlap))
            t0 = time.perf_counter()
            plan = planner.plan_site(site, planner.PlanOptions(method="milp", milp=milp))
            r = plan.result
            bound = "-" if r.bound is None else f"{r.bound:g}"
            print(
                f"| {theta:g} | {overlap:.0%} | {counts['closed-form']} | {counts['greedy']} | {len(plan.stations)} | "
                f"{bound} | {r.status.value} | {time.perf_counter() - t0:.1f} | {plan.verification.percent:.3f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
