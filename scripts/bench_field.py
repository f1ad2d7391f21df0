"""Benchmark of the field sheet (issue 35): writes docs/benchmarks/field.md.

For each site a plan.json is made once (``planner plan SITE --out DIR``, default MILP, 60 s), then
``planner field`` runs in both modes under ``/usr/bin/time -v`` (wall time and peak RSS of the whole
command). Usage: ``python scripts/bench_field.py [--work DIR] [--sites house_doors ...]``.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SITES = ("house_doors", "baalbek_site_doors", "plant_1ha")


def timed(cmd: list[str]) -> tuple[float, float, str]:
    """(wall s, peak RSS MiB, stderr) of ``cmd`` under /usr/bin/time -v."""
    t0 = time.perf_counter()
    run = subprocess.run(["/usr/bin/time", "-v", *cmd], check=False, cwd=ROOT, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if run.returncode != 0:
        sys.exit(f"failed ({run.returncode}): {' '.join(cmd)}\n{run.stdout}\n{run.stderr}")
    rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", run.stderr)
    return wall, int(rss.group(1)) / 1024 if rss else float("nan"), run.stderr


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--work", default="/tmp/bench_field")
    ap.add_argument("--sites", nargs="+", default=list(SITES))
    args = ap.parse_args()
    py = sys.executable
    rows = []
    for site in args.sites:
        folder = Path(args.work) / site
        if not (folder / "plan.json").is_file():
            subprocess.run([py, "-m", "planner", "plan", f"instances/{site}.json", "--out", str(folder), "--quiet"],
                           cwd=ROOT, check=True, capture_output=True)
        for mode in ("shortest", "registration"):
            out = folder / mode
            wall, rss, _ = timed([py, "-m", "planner", "field", str(folder / "plan.json"), "--out", str(out),
                                  "--mode", mode, "--session", "4h", "--quiet"])
            d = json.loads((out / "field.json").read_text())
            weak = sum(1 for lk in d["links"] if lk["weak"])
            rows.append((site, len(d["order"]), mode, d["route_length_m"], d["nearest_neighbour_m"], d["lower_bound_m"],
                         d["gap"], d["bound_method"], d["registration_order_honoured"],
                         d["field_time_s"] / 3600, len(d["sessions"]), len(d["targets"]), weak, wall, rss))
    lines = ["# Field sheet benchmark (issue 35)", "",
             ("`python scripts/bench_field.py` (one run each; wall time and peak RSS of the whole `planner field` "
             "command under `/usr/bin/time -v`, Python start, site load and coverage included). Plans: "
             "`planner plan SITE --out DIR` (default MILP, 60 s). Route: OR-Tools routing (guided local search, "
             "1000 solutions, from the nearest-neighbour order), then in registration mode (and in shortest "
             "mode where the Held-Karp bound leaves a gap) the CP-SAT circuit model with the registration rule "
             "(one worker, seed 0, deterministic-time limit 20), whose order is taken when shorter. Bound: the "
             "largest of the exact Held-Karp programme (shortest route, up to 13 nodes) or the Held-Karp "
             "1-tree with subgradient ascent (shortest route, above), and CP-SAT's proven objective bound "
             "(the mode's own route; distances in cm rounded down, so a proven optimum shows a gap of a few "
             "cm). Field time at the P30's default setting (6.3 mm @ 10 m), sessions of 4 h. Machine: 2 "
             "shared cores."), "",
             ("| site | stations | mode | route m | nearest-neighbour m | lower bound m | gap | bound | registration "
              "order | field time h | sessions | targets | weak links left | wall s | peak RSS MiB |"),
             "|---|---:|---|---:|---:|---:|---:|---|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        lines.append(f"| {r[0]} | {r[1]} | {r[2]} | {r[3]:.1f} | {r[4]:.1f} | {r[5]:.1f} | {100 * r[6]:.2f} % | {r[7]} "
                     f"| {'yes' if r[8] else 'no'} | {r[9]:.2f} | {r[10]} | {r[11]} | {r[12]} | {r[13]:.1f} | {r[14]:.0f} |")
    path = ROOT / "docs" / "benchmarks" / "field.md"
    path.write_text("\n".join(lines) + "\n")
    print("\n".join(lines[-len(rows) - 2:]))
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
