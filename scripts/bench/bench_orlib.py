"""OR-Library set-cover instances: every backend against the published optimum, and the greedy.

Usage: python scripts/bench/bench_orlib.py [--instances scp41 scp51 scpa1 scpnre1] [--time-limit 60]

Protocol: each instance read from ../shared/benchmarks/orlib_scp, solved once per backend,
one thread, seed 0, warm start from Chvatal's greedy (not for HiGHS, see docs/milp.md).
Prints a Markdown table: instance, published optimum, greedy, per backend objective / bound /
status / seconds.
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

from planner.solve.backends import BACKENDS
from planner.solve.greedy import greedy_cover
from planner.solve.milp import MilpOptions, solve
from planner.solve.orlib import read_orlib

ORLIB = Path(__file__).resolve().parents[3] / "shared" / "benchmarks" / "orlib_scp"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--instances", nargs="+", default=["scp41", "scp51", "scpa1", "scpnre1"])
    ap.add_argument("--time-limit", type=float, default=60.0)
    ap.add_argument("--dir", default=str(ORLIB))
    args = ap.parse_args()
    optima = {
        r["instance"]: r["published_optimum"] for r in csv.DictReader((Path(args.dir) / "known_optima.csv").open())
    }
    print("| instance | optimum | greedy | " + " | ".join(BACKENDS) + " |")
    print("|---|---|---|" + "---|" * len(BACKENDS))
    for name in args.instances:
        inst = read_orlib(Path(args.dir) / f"{name}.txt")
        g = greedy_cover(inst.by_candidate, weights=inst.cost)
        cells = []
        for b in BACKENDS:
            t0 = time.perf_counter()
            r = solve(inst, MilpOptions(backend=b, time_limit_s=args.time_limit, overlap=None))
            bound = "-" if r.bound is None else f"{r.bound:.1f}"
            cells.append(f"{r.objective:g} / {bound} {r.status.value} {time.perf_counter() - t0:.1f} s")
        print(f"| {name} | {optima[name]} | {g.objective:g} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
