"""One block of the connected MILP, round by round: what each round of the cut loop costs and finds.

Usage: python scripts/bench/bench_block.py polygon_a --block 1 [--time-limit 60] [--floor] [--core]
                                     [--cache out/bench_connectivity]

Protocol: the instance's cover problem is the cached pickle of ``scripts/bench/bench_connectivity.py``
(build it there first); presolve and blocks as ``planner.solve.milp.solve`` makes them (blocks
smallest first, ``--block`` counts from 0); CP-SAT, cut loop, one thread, seed 0, 30 % overlap rule,
local search on, the ring bound off unless ``--ring`` (it closes every block of A, B, C and Baalbek before
the first round). Each round prints its time, outcome, objective, CP-SAT's bound, the incumbent and
the sizes of the answer's registration parts. Experiments, off by default:

* ``--floor``: once a round has proven a bound L, every later round gets ``sum x >= ceil(L)``
  (valid: each round's model only gains cuts, so its optimum never drops below an earlier bound);
* ``--core``: CP-SAT's core-based search (``optimize_with_core``) instead of its default.
"""

from __future__ import annotations

import argparse
import json
import pickle
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))


def block_solver(path: Path, which: int, ring: bool = False) -> Any:
    """The ``which``-th block of the cached instance, as ``solve`` would run it."""
    from planner.solve.milp import MilpOptions, block_solvers

    o = MilpOptions(backend="cpsat", connectivity="loop", threads=1, seed=0, ring_bound=ring)
    return block_solvers(pickle.loads(path.read_bytes()), o)[1][which]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("instance")
    ap.add_argument("--block", type=int, default=0)
    ap.add_argument("--time-limit", type=float, default=60.0)
    ap.add_argument("--floor", action="store_true")
    ap.add_argument("--core", action="store_true")
    ap.add_argument(
        "--ring",
        action="store_true",
        help="with the ring bound (off here: it closes A, B, C and Baalbek's blocks before any round)",
    )
    ap.add_argument("--cache", type=Path, default=ROOT / "out/bench_connectivity")
    args = ap.parse_args()
    from planner.solve.connectivity import components

    b = block_solver(args.cache / f"{args.instance}.pkl", args.block, args.ring)
    print(
        f"block {args.block}: {b.sub.shape[0]} candidates x {b.sub.shape[1]} targets, "
        f"connected greedy {len(b.incumbent or [])}",
        flush=True,
    )
    backend, solve_round = b.backend, b.backend.solve
    floor = [0]

    def traced(limit: float, threads: int, seed: int, hint: Any) -> Any:
        if args.floor and b.bound > 0 and int(np.ceil(b.bound - 1e-6)) > floor[0]:
            floor[0] = int(np.ceil(b.bound - 1e-6))
            backend.model.Add(sum(backend.x[: backend.n]) >= floor[0])
        t = time.perf_counter()
        res = solve_round(limit, threads, seed, hint)
        parts = sorted(len(c) for c in components(b.adj, list(res.selected))) if res.selected else []
        print(
            f"  round {b.rounds + 1}: {time.perf_counter() - t:.1f} s {res.outcome.name} objective {res.objective} "
            f"bound {res.bound} incumbent {len(b.incumbent or [])} parts {parts}",
            flush=True,
        )
        return res

    backend.solve = traced
    if args.core:
        cp = backend._cp
        base = cp.CpSolver

        class CoreSolver(base):  # type: ignore[misc,valid-type]
            def Solve(self, *a: Any, **k: Any) -> Any:
                self.parameters.optimize_with_core = True
                return base.Solve(self, *a, **k)

        cp.CpSolver = CoreSolver
    start = time.perf_counter()
    b.run(start + args.time_limit)
    print(
        json.dumps(
            {
                "instance": args.instance,
                "block": args.block,
                "floor": args.floor,
                "core": args.core,
                "rounds": b.rounds,
                "cuts": b.cuts,
                "incumbent": len(b.incumbent or []),
                "bound": b.bound,
                "proven": b.done,
                "time_s": round(time.perf_counter() - start, 1),
            }
        )
    )


if __name__ == "__main__":
    main()
