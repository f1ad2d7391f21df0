"""Registration connectivity: branch-and-cut, flow model and cut loop side by side, with both greedies.

Usage: python scripts/bench/bench_connectivity.py [--instances polygon_a ...] [--time-limit 60]
                                            [--cache out/bench_connectivity] [--out-dir docs/benchmarks]

Protocol: each instance's cover problem is built once as ``planner plan`` builds it with default
options (pool with region-derived candidates, geometric pricing; ``--no-pricing`` for the pool
without priced columns) and cached as a pickle. Every run is then a fresh process under
``/usr/bin/time -v`` (peak RSS) that loads the cached problem and solves it: the connected greedy
(overlap rule, 50 starts per zone-side), the plain greedy (Chvatal, rule ignored), and the MILP with
the 30 % overlap rule per (backend, connectivity method) at 1 and 2 threads, seed 0, with the ring bound
(``planner.solve.ring``) on, and the default method once more with it off ("ring" column). "time s" is the
solve alone (presolve included; the pool and pricing are not). Every plan is checked for coverage of
every target and recomputed registration connectivity. Writes connectivity.csv and connectivity.md.
"""

from __future__ import annotations

import argparse
import csv
import json
import pickle
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
from _timed import peak_rss_mb

ROOT = Path(__file__).resolve().parents[2]
FIELDS = [
    "instance",
    "pool",
    "method",
    "backend",
    "connectivity",
    "ring",
    "threads",
    "stations",
    "bound",
    "gap",
    "status",
    "time_s",
    "connected",
    "covered",
    "peak_rss_mb",
]
PROTOCOL = (
    "bound: the MILP's lower bound over the pool; gap = (stations - bound) / stations; time s: the solve "
    "alone; connected: every zone-side one bundle under the 30 % rule, recomputed; covered: every target seen; "
    "peak RSS of the solving process (/usr/bin/time -v). greedy-plain ignores the rule; pyscipopt runs one thread."
)
#: (backend, connectivity, threads, ring bound) of the MILP runs
MILP_RUNS = [
    ("cpsat", "loop", 1, "on"),
    ("cpsat", "loop", 2, "on"),
    ("cpsat", "loop", 1, "off"),
    ("cpsat", "loop", 2, "off"),
    ("cpsat", "flow", 1, "on"),
    ("cpsat", "flow", 2, "on"),
    ("pyscipopt", "bc", 1, "on"),
    ("scip", "flow", 1, "on"),
]


def build(name: str, cache: Path, pricing: bool) -> Path:
    """The solver's instance of a bundled site, built as plan_site builds it, pickled once."""
    path = cache / f"{name}{'' if pricing else '-nopricing'}.pkl"
    if path.exists():
        return path
    from planner import plan as P
    from planner.bounds.plane import price_plane
    from planner.io import load_site
    from planner.site.validate import validate_site
    from planner.solve.instance import cover_instance

    site = load_site(ROOT / f"instances/{name}.json")
    options = replace(P.PlanOptions(method="milp"), pricing=pricing)
    validation = validate_site(site)
    problem = P.build_problem(site, options, validation)
    if pricing:
        problem, _ = price_plane(
            site, problem, P.plan_limits(validation, options), time_limit_s=options.pricing_time_limit_s
        )
    p = site.parameters
    inst = cover_instance(problem, scanner=validation.scanner, budget=p.budget, sigma_req_m=p.sigma_req_m, name=name)
    cache.mkdir(parents=True, exist_ok=True)
    path.write_bytes(pickle.dumps(inst))
    return path


def child(path: str, method: str, backend: str, connectivity: str, threads: int, time_limit: float, ring: str) -> None:
    """One solve in this process; prints one JSON line."""
    from planner.coverage.overlap import OverlapRule, overlap_adjacency
    from planner.solve.connectivity import disconnected_groups
    from planner.solve.greedy import connected_greedy_plan, greedy_cover
    from planner.solve.milp import MilpOptions, solve

    inst = pickle.loads(Path(path).read_bytes())
    rule = OverlapRule(0.3)
    if method == "greedy-connected":
        r = connected_greedy_plan(inst, rule)
    elif method == "greedy-plain":
        r = greedy_cover(inst.by_candidate)
    else:
        r = solve(
            inst,
            MilpOptions(
                backend=backend,
                connectivity=connectivity,
                threads=threads,
                time_limit_s=time_limit,
                ring_bound=ring == "on",
            ),
        )
    a = inst.by_candidate.tocsr()
    adj, _ = overlap_adjacency(a, inst.target_length_m, rule, inst.groups, inst.xy)
    covered = bool(np.asarray(a[list(r.selected)].sum(axis=0)).ravel().all()) if r.selected else False
    print(
        json.dumps(
            {
                "stations": len(r.selected),
                "bound": r.bound,
                "status": r.status.value,
                "time_s": round(r.time_s, 2),
                "connected": not disconnected_groups(adj, inst.groups, r.selected),
                "covered": covered,
            }
        )
    )


def measure(
    path: Path, method: str, backend: str, connectivity: str, threads: int, time_limit: float, ring: str
) -> dict:
    cmd = [
        "/usr/bin/time",
        "-v",
        sys.executable,
        __file__,
        "--child",
        str(path),
        method,
        backend,
        connectivity,
        str(threads),
        str(time_limit),
        ring,
    ]
    res = subprocess.run(cmd, capture_output=True, text=True, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    lines = [ln for ln in res.stdout.splitlines() if ln.startswith("{")]
    if res.returncode != 0 or not lines:
        return {"status": f"error rc {res.returncode}: {res.stderr.strip().splitlines()[-1:]}"}
    row = json.loads(lines[-1])
    row["peak_rss_mb"] = peak_rss_mb(res.stderr)
    b = row["bound"]
    row["gap"] = "" if b is None or not row["stations"] else f"{100 * (row['stations'] - b) / row['stations']:.1f}"
    row["bound"] = "" if b is None else round(b, 2)
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--instances", nargs="+", default=["polygon_a", "polygon_b", "polygon_c", "baalbek", "building27"])
    ap.add_argument("--time-limit", type=float, default=60.0)
    ap.add_argument("--no-pricing", action="store_true", help="the pool without priced columns")
    ap.add_argument("--cache", type=Path, default=ROOT / "out/bench_connectivity")
    ap.add_argument("--out-dir", type=Path, default=ROOT / "docs/benchmarks")
    ap.add_argument(
        "--only",
        nargs="+",
        metavar="METHOD",
        help="run only these methods (greedy-connected, greedy-plain, milp) and replace their rows "
        "of the instances run in the existing CSV, keeping the others",
    )
    ap.add_argument(
        "--milp-runs",
        nargs="+",
        metavar="BACKEND:CONNECTIVITY:THREADS[:off]",
        help="only these MILP runs (default: every row of MILP_RUNS), e.g. cpsat:loop:1 cpsat:loop:1:off "
        "(off: without the ring bound)",
    )
    ap.add_argument("--child", nargs=7, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        p, method, backend, conn, threads, limit, ring = args.child
        child(p, method, backend, conn, int(threads), float(limit), ring)
        return
    pool = "regions" if args.no_pricing else "regions+pricing"
    rows = []
    for name in args.instances:
        path = build(name, args.cache, not args.no_pricing)
        milp_runs = (
            [(b, c, int(t), (rest or ["on"])[0]) for b, c, t, *rest in (r.split(":") for r in args.milp_runs)]
            if args.milp_runs
            else MILP_RUNS
        )
        runs = [("greedy-connected", "", "", 1, ""), ("greedy-plain", "", "", 1, "")] + [
            ("milp", *r) for r in milp_runs
        ]
        runs = [r for r in runs if not args.only or r[0] in args.only]
        for method, backend, conn, threads, ring in runs:
            row = {
                "instance": name,
                "pool": pool,
                "method": method,
                "backend": backend,
                "connectivity": conn,
                "ring": ring,
                "threads": threads,
                **measure(path, method, backend or "cpsat", conn or "auto", threads, args.time_limit, ring or "on"),
            }
            rows.append(row)
            print(" | ".join(str(row.get(f, "")) for f in FIELDS), flush=True)
    (args.out_dir / "results").mkdir(parents=True, exist_ok=True)
    stem = "connectivity" + ("-nopricing" if args.no_pricing else "")
    if args.only and (args.out_dir / "results" / f"{stem}.csv").exists():
        key = ("instance", "method", "backend", "connectivity", "ring", "threads")
        fresh = {tuple(str(r[k]) for k in key): r for r in rows}
        with open(args.out_dir / "results" / f"{stem}.csv", newline="") as f:
            old = list(csv.DictReader(f))
        rows = [fresh.pop(tuple(r.get(k, "") for k in key), r) for r in old] + list(fresh.values())
    with open(args.out_dir / "results" / f"{stem}.csv", "w", newline="") as f:
        w = csv.DictWriter(f, FIELDS, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    lines = [
        f"# Registration connectivity: methods side by side ({pool} pool)",
        "",
        f"Written by `python scripts/bench/bench_connectivity.py{' --no-pricing' if args.no_pricing else ''}` "
        f"(time limit {args.time_limit:g} s, seed 0, one run per row, this machine). " + PROTOCOL,
        "",
        "| " + " | ".join(FIELDS) + " |",
        "|" + "---|" * len(FIELDS),
    ]
    lines += ["| " + " | ".join(str(r.get(f, "")) for f in FIELDS) + " |" for r in rows]
    (args.out_dir / f"{stem}.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
