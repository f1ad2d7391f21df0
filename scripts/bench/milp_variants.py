"""The MILP alone on one site's cover instance, under solver variants: where its time goes and what each variant buys.

    python scripts/bench/milp_variants.py instances/baalbek_site_doors.json --save /tmp/doors.pkl
    python scripts/bench/milp_variants.py /tmp/doors.pkl "" "work_limit=50" "layer_cuts=False"

The first form plans the site once (the default options) and pickles the cover instance and MILP options that the
plan hands the solver; the second loads such a pickle and solves it once per variant (``MilpOptions`` keywords,
comma-separated; "" the plan's own options), printing per variant: status, stations, bound, CP-SAT work used, rounds,
cuts, why it stopped, the floor probes (``floor_probe=False`` turns them off), the process CPU time of the solve (CPU, not
wall: the machine may be shared) and the gap's reason in words. Each block's cut-loop rounds
are printed as they run with ``--rounds``.
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))


def capture(site: str, out: Path) -> None:
    """Plan ``site`` with the default options and pickle what the MILP is handed."""
    import planner.plan.methods as methods
    from planner.engine import plan_site

    real = methods.solve

    def keep(instance, options):  # type: ignore[no-untyped-def]
        out.write_bytes(pickle.dumps((instance, options)))
        return real(instance, options)

    methods.solve = keep
    plan_site(site)
    print(f"saved the cover instance of {site} to {out}")


def variant(text: str) -> dict:
    """``"a=1, b='x'"`` as keywords (literals only)."""
    import ast

    if not text.strip():
        return {}
    call = ast.parse(f"f({text})", mode="eval").body
    assert isinstance(call, ast.Call)
    return {k.arg: ast.literal_eval(k.value) for k in call.keywords if k.arg}


def run(path: Path, variants: list[str], rounds: bool) -> None:
    from planner.solve import block
    from planner.solve.milp import solve

    instance, options = pickle.loads(path.read_bytes())
    if rounds:
        first = block.BlockSolver.run

        def logged(self, deadline, work_until=None):  # type: ignore[no-untyped-def]
            inner = self.backend.solve

            def solve_logged(*a, **k):  # type: ignore[no-untyped-def]
                res = inner(*a, **k)
                inc = None if self.incumbent is None else float(self.cost[self.incumbent].sum())
                print(
                    f"  round {self.rounds}: {res.outcome.value} {res.objective} bound {res.bound} incumbent {inc}"
                    f" work {self.work_used:.2f} cuts {self.cuts}",
                    flush=True,
                )
                return res

            self.backend.solve = solve_logged
            first(self, deadline, work_until)

        block.BlockSolver.run = logged  # type: ignore[method-assign]
    for text in variants:
        o = replace(options, **variant(text))
        cpu = time.process_time()
        r = solve(instance, o)
        cpu = time.process_time() - cpu
        w = r.info.get("work", {})
        probes = "; ".join(
            f"probe {p['level']}: {p['outcome']} on {p['candidates']} of {p['of']} candidates, {p['work']:g} work-s"
            for p in r.info.get("floor", ())
        )
        print(
            f"[{text or 'plan options'}] {r.status.value}, {r.objective:g} stations, bound {r.bound:g}, work "
            f"{w.get('used')} of {w.get('limit')} (stop: {r.info.get('stop')}), rounds {r.info.get('rounds')}, cuts "
            f"{r.info.get('cuts')}, cpu {cpu:.1f} s" + (f"; {probes}" if probes else ""),
            flush=True,
        )
        if r.info.get("gap_reason"):
            print(f"  {r.info['gap_reason']}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("source", help="a site file (with --save) or a pickle that --save wrote")
    ap.add_argument("variants", nargs="*", default=[""], help='MilpOptions keywords per run, e.g. "work_limit=50"')
    ap.add_argument("--save", type=Path, help="plan the site and pickle its cover instance here")
    ap.add_argument("--rounds", action="store_true", help="print each cut-loop round")
    args = ap.parse_args()
    if args.save:
        capture(args.source, args.save)
    else:
        run(Path(args.source), args.variants or [""], args.rounds)


if __name__ == "__main__":
    main()
