"""Plans before and after issue 16 (the accuracy model that decides, stations that can be set up).

Run once with this checkout and once with the code before issue 16 on PYTHONPATH (the script uses
only what both have; what the older code lacks is shown as ``-``); each run prints one JSON line per
(instance, configuration, method):

    PYTHONPATH=. python scripts/bench/bench_accuracy.py --label after  > after.jsonl
    PYTHONPATH=/tmp/before python scripts/bench/bench_accuracy.py --label before > before.jsonl
    python scripts/bench/bench_accuracy.py --table before.jsonl after.jsonl   # the markdown table

Configurations: ``default`` (the instance as given: theta_max 68 deg, single precision), ``derive``
(theta_max derived from sigma_req with the table 2.3 model; after only), ``combined``
(``--precision combined``). Columns: stations; verification at 0.1 m in the plan's own mode (covered %);
the network check (a priori least squares, proposed control points) in the plan's mode after, by the
best single view before: failing pieces of all, worst point error; the smallest distance of a
station and of a proposed control point to a wall or obstacle edge; tripod discs that contain their
station; wall time of planning (1 thread), one run each on a shared 2-core machine.
"""

from __future__ import annotations

import argparse
import inspect
import json
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import shapely

from planner.engine import plan_site
from planner.io import load_site
from planner.network.check import run_network
from planner.plan import PlanOptions
from planner.solve.milp import MilpOptions

ROOT = Path(__file__).resolve().parents[2]
INSTANCES = ["polygon_a", "polygon_b", "polygon_c", "baalbek", "courtyard"]
CONFIGS = ["default", "derive", "combined"]


def clearance_m(site, xy, frame: str) -> float:
    """Distance to the nearest wall of a zone drawn in ``frame`` or (site frame) obstacle edge."""
    edges = [z.polygon.boundary for z in site.zones if z.frame == frame]
    edges += [shapely.Polygon(o.vertices).boundary for o in site.obstacles] if frame == "site" else []
    return min(shapely.distance(e, shapely.Point(xy)) for e in edges)


def run(name: str, config: str, method: str, limit_s: float, label: str) -> dict | None:
    site = load_site(ROOT / f"instances/{name}.json")
    p = site.parameters
    if config == "derive":
        if not hasattr(p, "derive_theta_max"):
            return None
        site = replace(site, parameters=replace(p, derive_theta_max=True))
    combined = config == "combined"
    milp = MilpOptions(time_limit_s=limit_s, precision="combined" if combined else "single")
    if combined and method != "milp" and not hasattr(PlanOptions, "combined"):
        return None  # before issue 16 only the MILP honoured combined precision
    options = PlanOptions(method=method, milp=milp, tripod=True)
    t0 = time.perf_counter()
    plan = plan_site(site, options)
    wall = time.perf_counter() - t0
    if not plan.stations:  # a solver that found no plan (before issue 16: reported, exit 0)
        return {
            "label": label,
            "instance": name,
            "config": config,
            "method": method,
            "error": f"no plan: {plan.result.status.value}, verified {plan.verification.percent:.3f} %",
        }
    kw = {"precision": "combined"} if combined and "precision" in inspect.signature(run_network).parameters else {}
    net = run_network(site, list(plan.stations), **kw)
    check = net.check
    proposed = [c for c in net.control if c.proposed]
    discs = plan.tripods
    return {
        "label": label,
        "instance": name,
        "config": config,
        "method": method,
        "stations": len(plan.stations),
        "status": plan.result.status.value,
        "time_s": round(wall, 2),
        "verify_percent": plan.verification.percent,
        "verify_mode": getattr(plan.verification, "precision", "single (combined dropped)" if combined else "single"),
        "network_mode": check.get("precision", "single"),
        "failing": check["failing_targets"],
        "targets": check["targets"],
        "worst_e_mm": round(check["worst_e_m"] * 1000, 2) if check["worst_e_m"] is not None else None,
        "station_clearance_m": round(min(clearance_m(site, s.xy, s.frame) for s in plan.stations), 3)
        if plan.stations
        else None,
        "control_clearance_m": round(min(clearance_m(site, (c.x, c.y), c.frame) for c in proposed), 3)
        if proposed
        else None,
        "discs_containing": sum(math.dist(s.xy, d.centre) <= d.radius_m + 1e-9 for s, d in zip(plan.stations, discs)),
        "discs_zero": sum(d.radius_m == 0.0 for d in discs),
        "accuracy_line": next((ln for ln in plan.summary().splitlines() if ln.startswith("accuracy:")), ""),
    }


def table(paths: list[str]) -> str:
    rows = [json.loads(line) for path in paths for line in Path(path).read_text().splitlines() if line.strip()]
    head = (
        "| instance | config | method | code | stations | verified % (mode) | network check: failing / pieces (mode) "
        "| worst e mm | station clearance m | control clearance m | discs containing station (zero radius) | time s |"
    )
    out = [head, "|" + "---|" * (head.count("|") - 1)]
    key = {c: i for i, c in enumerate(CONFIGS)}
    for r in sorted(
        rows, key=lambda r: (INSTANCES.index(r["instance"]), key[r["config"]], r["method"], r["label"] != "before")
    ):
        if "error" in r:
            out.append(
                f"| {r['instance']} | {r['config']} | {r['method']} | {r['label']} | failed: {r['error'][:80]} |"
                + " |" * 7
            )
            continue
        out.append(
            f"| {r['instance']} | {r['config']} | {r['method']} | {r['label']} | {r['stations']} | "
            f"{r['verify_percent']:.3f} ({r['verify_mode']}) | {r['failing']} / {r['targets']} ({r['network_mode']}) | "
            f"{r['worst_e_mm'] if r['worst_e_mm'] is not None else '-'} | {r['station_clearance_m'] if r['station_clearance_m'] is not None else '-'} | "
            f"{r['control_clearance_m'] if r['control_clearance_m'] is not None else '-'} | "
            f"{r['discs_containing']} of {r['stations']} ({r['discs_zero']}) | {r['time_s']} |"
        )
    return "\n".join(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--label", default="after")
    ap.add_argument("--instances", nargs="*", default=INSTANCES)
    ap.add_argument("--configs", nargs="*", default=CONFIGS)
    ap.add_argument("--methods", nargs="*", default=["greedy", "milp"])
    ap.add_argument("--time-limit", type=float, default=60.0)
    ap.add_argument("--table", nargs="*", metavar="JSONL", help="print the markdown table of earlier runs")
    args = ap.parse_args()
    if args.table:
        print(table(args.table))
        return
    for name in args.instances:
        for config in args.configs:
            for method in args.methods:
                try:
                    r = run(name, config, method, args.time_limit, args.label)
                except Exception as exc:  # a configuration the code cannot plan: recorded, not fatal
                    r = {"label": args.label, "instance": name, "config": config, "method": method, "error": repr(exc)}
                if r is not None:
                    print(json.dumps(r), flush=True)
                    print(f"{name} {config} {method}: {r.get('stations', r.get('error'))}", file=sys.stderr)


if __name__ == "__main__":
    main()
