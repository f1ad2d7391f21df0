"""Benchmark of the field sheet (issue 35): writes docs/benchmarks/field.md.

For each site a plan.json is made once (``planner plan SITE --out DIR``, default MILP, 60 s), then
``planner field`` runs in both modes under ``/usr/bin/time -v`` (wall time and peak RSS of the whole
command). Usage: ``python scripts/bench/bench_field.py [--work DIR] [--sites house_doors ...]``.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SITES = ("house_doors", "baalbek_site_doors", "plant_1ha")
RANDOM_SIZES = (22, 50, 100)


def random_instance(n: int, seed: int = 0):  # type: ignore[no-untyped-def]
    """A random order problem of ``n`` stations (node 0 the start): points uniform in a square of side
    10 sqrt(n) m, walking distance = Euclidean, and an overlap relation joining each pair within 16 m with
    probability 1/2, plus the edges of the Euclidean minimum spanning tree (one registration part)."""
    import numpy as np
    from scipy.sparse.csgraph import minimum_spanning_tree

    rng = np.random.default_rng(seed)
    p = rng.uniform(0.0, 10.0 * np.sqrt(n), (n, 2))
    d = np.hypot(*(p[:, None] - p[None]).transpose(2, 0, 1))
    near = (d <= 16.0) & (rng.uniform(size=d.shape) < 0.5)
    near = np.triu(near, 1)
    mst = minimum_spanning_tree(d).toarray() > 0
    rel = near | near.T | mst | mst.T
    nbrs = [set(np.flatnonzero(rel[j]).tolist()) - {j} for j in range(n)]
    return d, nbrs, [0] * n


def timed(cmd: list[str]) -> tuple[float, float, str]:
    """(wall s, peak RSS MiB, stderr) of ``cmd`` under /usr/bin/time -v."""
    t0 = time.perf_counter()
    run = subprocess.run(["/usr/bin/time", "-v", *cmd], check=False, cwd=ROOT, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if run.returncode != 0:
        sys.exit(f"failed ({run.returncode}): {' '.join(cmd)}\n{run.stdout}\n{run.stderr}")
    rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", run.stderr)
    return wall, int(rss.group(1)) / 1024 if rss else float("nan"), run.stderr


def random_rows(sizes: tuple[int, ...]) -> list[str]:
    """Route, bounds and gap on :func:`random_instance` (seed 0) of each size, both modes: routing, then
    :func:`planner.field.certify.certify` (Held-Karp 1-tree, then the branch-and-cut), timed in-process."""
    sys.path.insert(0, str(ROOT))
    from planner.field.certify import certify
    from planner.field.order import registration_violations, solve_order

    out = []
    for n in sizes:
        d, nbrs, parts = random_instance(n)
        for mode in ("shortest", "registration"):
            t0 = time.perf_counter()
            r = solve_order(d, mode, nbrs, parts, True, False)
            t1 = time.perf_counter()
            c = certify(d, r, mode, nbrs, parts, True, False)
            t2 = time.perf_counter()
            b = dict(c.bounds)
            ok = not registration_violations(c.result.order, nbrs, parts, True)
            gap = (c.result.length_m - c.bound_m) / c.result.length_m
            out.append(
                f"| {n} | {mode} | {r.length_m:.1f} | {c.result.length_m:.1f} | "
                f"{b.get('Held-Karp 1-tree, subgradient ascent', float('nan')):.1f} | {c.bound_m:.1f} | "
                f"{100 * gap:.2f} % | {c.method} | {'yes' if ok else 'no'} | {t1 - t0:.1f} | {t2 - t1:.1f} |"
            )
            print(out[-1], flush=True)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--work", default="/tmp/bench_field")
    ap.add_argument("--sites", nargs="+", default=list(SITES))
    ap.add_argument(
        "--random",
        nargs="*",
        type=int,
        default=list(RANDOM_SIZES),
        help="sizes of random instances to certify (none: skip)",
    )
    args = ap.parse_args()
    py = sys.executable
    rows = []
    for site in args.sites:
        folder = Path(args.work) / site
        if not (folder / "plan.json").is_file():
            subprocess.run(
                [py, "-m", "planner", "plan", f"instances/{site}.json", "--out", str(folder), "--quiet"],
                cwd=ROOT,
                check=True,
                capture_output=True,
            )
        for mode in ("shortest", "registration"):
            out = folder / mode
            wall, rss, _ = timed(
                [
                    py,
                    "-m",
                    "planner",
                    "field",
                    str(folder / "plan.json"),
                    "--out",
                    str(out),
                    "--mode",
                    mode,
                    "--session",
                    "4h",
                    "--quiet",
                ]
            )
            d = json.loads((out / "field.json").read_text())
            weak = sum(1 for lk in d["links"] if lk["weak"])
            rows.append(
                (
                    site,
                    len(d["order"]),
                    mode,
                    d["route_length_m"],
                    d["nearest_neighbour_m"],
                    d["lower_bound_m"],
                    d["gap"],
                    d["bound_method"],
                    d["registration_order_honoured"],
                    d["field_time_s"] / 3600,
                    len(d["sessions"]),
                    len(d["targets"]),
                    weak,
                    wall,
                    rss,
                )
            )
    lines = [
        "# Field sheet benchmark",
        "",
        (
            "`python scripts/bench/bench_field.py` (one run each; wall time and peak RSS of the whole `planner field` "
            "command under `/usr/bin/time -v`, Python start, site load and coverage included). Plans: "
            "`planner plan SITE --out DIR` (default MILP, 60 s). Route: OR-Tools routing (guided local search, "
            "1000 solutions, from the nearest-neighbour order), then in registration mode (and in shortest "
            "mode where the Held-Karp bound leaves a gap) the branch-and-cut (SCIP: subtour and registration "
            "cuts; one thread, seed 0, node limit 2000), whose order is taken when shorter. Bound: the "
            "largest of the exact Held-Karp programme (shortest route, up to 13 nodes) or the Held-Karp "
            "1-tree with subgradient ascent (shortest route, above), and the branch-and-cut's dual bound "
            "(the mode's own route; distances in mm rounded down, so a proven optimum shows a gap of a few "
            "mm). Field time at the P30's default setting (6.3 mm @ 10 m), sessions of 4 h. Machine: 2 "
            "shared cores."
        ),
        "",
        (
            "| site | stations | mode | route m | nearest-neighbour m | lower bound m | gap | bound | registration "
            "order | field time h | sessions | targets | weak links left | wall s | peak RSS MiB |"
        ),
        "|---|---:|---|---:|---:|---:|---:|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(
            f"| {r[0]} | {r[1]} | {r[2]} | {r[3]:.1f} | {r[4]:.1f} | {r[5]:.1f} | {100 * r[6]:.2f} % | {r[7]} "
            f"| {'yes' if r[8] else 'no'} | {r[9]:.2f} | {r[10]} | {r[11]} | {r[12]} | {r[13]:.1f} | {r[14]:.0f} |"
        )
    print("\n".join(lines[-len(rows) - 2 :]))
    if args.random:
        lines += [
            "",
            "## Random instances",
            "",
            (
                "`random_instance(n)` (seed 0): n points uniform in a square of side 10 sqrt(n) m, walking distance = "
                "Euclidean, start = point 0, an overlap relation joining pairs within 16 m with probability 1/2 plus "
                "the Euclidean minimum spanning tree (one part); open path. Routing (1000 solutions), then the "
                "certificate: Held-Karp 1-tree (shortest route), then the branch-and-cut (SCIP, one thread, "
                "node limit 2000) in registration mode and where the 1-tree leaves a gap; times in-process."
            ),
            "",
            (
                "| stations | mode | routing m | route m | 1-tree m | lower bound m | gap | bound | registration "
                "order | routing s | certificate s |"
            ),
            "|---:|---|---:|---:|---:|---:|---:|---|---|---:|---:|",
            *random_rows(tuple(args.random)),
        ]
    path = ROOT / "docs" / "benchmarks" / "field.md"
    path.write_text("\n".join(lines) + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
