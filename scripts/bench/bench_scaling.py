"""Time and memory of the plain ``planner plan`` against the plant's area (issue 34): 1, 4, 16 and 64 ha.

Each area is the command a user types, ``planner plan instances/plant_Nha.json --out DIR``, as its own process
under ``/usr/bin/time -v`` (:func:`_timed.timed_plan`). Where the plain command's strategy for the site is tiles
(:func:`planner.plan.strategy.strategy_for`), ``--workers N --set worker-memory=M`` are added, so that the tiles run on
Dask with a bounded memory per worker; a site the strategy plans as one model gets no Dask flag (the command
refuses them there). Per row: the strategy, candidates, pieces and pairs, stations (connected), the bound over the
pool and its derivation, the gap, the verified share, wall and CPU seconds, the peak RSS of the largest process
and of the planner with all its workers together. Then the log-log slopes of wall time, CPU time and both peaks
against the area (least squares over the rows), and a figure.

    python scripts/bench/bench_scaling.py [--areas 1 4 16 64] [--workers 1] [--worker-memory 3GiB] [--limit S]
        [--out docs/benchmarks/scaling.md]
    python scripts/bench/bench_scaling.py --areas --merge docs/benchmarks/results/scaling.json --out ...  # redraw

The rows go to ``docs/benchmarks/results/scaling.json`` (beside ``--out``'s folder: ``results/<name>.json``)
after each area, so that a long run keeps what it measured; ``--merge`` shows earlier rows too (a row of this
run replaces one of the same area).
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
from _timed import ROOT, timed_plan

HEADER = [
    "| area ha | strategy | workers (memory each) | candidates | pieces | pairs | stations (connected) | verified | "
    "bound over the pool (derivation) | gap | wall s | CPU s | peak GiB, largest process | peak GiB, all processes |",
    "|---" * 14 + "|",
]


def plant(area: float) -> Path:
    return ROOT / "instances" / f"plant_{area:g}ha.json"


def dask_flags(site_path: Path, workers: int, memory: str) -> list[str]:
    """``--workers`` and the worker-memory key where the plain command's strategy for the site is tiles, else none."""
    from planner.io.load import load_site
    from planner.plan import PlanOptions
    from planner.plan.strategy import BUDGET_S, strategy_for
    from planner.site.validate import validate_site

    site = load_site(site_path)
    strategy = strategy_for(site, PlanOptions(method="milp"), validate_site(site), BUDGET_S, workers=workers)
    return ["--workers", str(workers), "--set", f"worker-memory={memory}"] if strategy.tiles and workers else []


def run(area: float, workers: int, memory: str, out: Path, limit_s: int) -> dict[str, Any]:
    flags = dask_flags(plant(area), workers, memory)
    row, plan = timed_plan([str(plant(area)), *flags], out, limit_s)
    row |= {"area_ha": area, "flags": " ".join(flags)}
    if plan is not None:
        strategy = plan["solver"]["strategy"]
        row |= {
            "strategy": strategy["kind"],
            "workers": strategy["workers"],
            "memory": memory if flags else "",
            "candidates": plan["problem"]["candidates"],
            "pieces": plan["problem"]["targets"],
            "pairs": plan["problem"]["pairs"],
            "stations": plan["counts"]["total"],
            "connected": plan["registration"]["connected"],
            "verified": plan["verification"]["percent"],
            "bound": plan["bound"],
            "bound_scope": plan["bound_scope"],
            "bound_how": _how(plan),
            "gap": plan["gap"],
        }
    return row


def _how(plan: dict[str, Any]) -> str:
    """How the bound over the pool was made: the tiles' derivation, else the single model's status."""
    return str(plan["solver"].get("bound_how") or f"{plan['method']} {plan['status']}")


def slope(rows: list[dict[str, Any]], key: str) -> float:
    """Least-squares slope of log ``key`` against log area over the rows that finished and measured it."""
    ok = [r for r in rows if r.get("stations") and r.get(key)]
    if len(ok) < 2:
        return math.nan
    return float(np.polyfit(np.log([r["area_ha"] for r in ok]), np.log([r[key] for r in ok]), 1)[0])


def row_line(r: dict[str, Any]) -> str:
    if not r.get("stations"):
        return f"| {r['area_ha']:g} | exit {r['exit']}: {r.get('error', '')} |||||||||| {r['wall_s']:.1f} | - | - | - |"
    workers = f"{r['workers']} ({r['memory']})" if r["memory"] else "none (in the planner's process)"
    pairs, tree = r.get("pairs"), r.get("tree_gib")  # absent from a row copied from an earlier run's notes
    return (
        f"| {r['area_ha']:g}{r.get('note', '')} | {r['strategy']} | {workers} | {r['candidates']:,} | {r['pieces']:,} | "
        f"{'-' if pairs is None else format(pairs, ',')} | {r['stations']} ({'yes' if r['connected'] else 'no'}) | "
        f"{r['verified']:.3f} % | {r['bound']:g} ({r['bound_how']}) | {r['gap']:.1%} | {r['wall_s']:.1f} | "
        f"{r['cpu_s']:.1f} | {r['peak_gib']:.2f} | {'-' if tree is None else format(tree, '.2f')} |"
    )


def slope_line(rows: list[dict[str, Any]]) -> str:
    return (
        "log-log slopes against area: "
        + ", ".join(
            f"{name} {slope(rows, key):.2f}"
            for name, key in (
                ("wall time", "wall_s"),
                ("CPU time", "cpu_s"),
                ("peak RSS (largest process)", "peak_gib"),
                ("peak RSS (all processes)", "tree_gib"),
                ("pairs", "pairs"),
            )
        )
        + "."
    )


def figure(rows: list[dict[str, Any]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter

    ok = [r for r in rows if r.get("stations")]
    fig, (ax_t, ax_m) = plt.subplots(1, 2, figsize=(10, 4))
    for ax, key, label in (
        (ax_t, "wall_s", "wall s"),
        (ax_t, "cpu_s", "CPU s"),
        (ax_m, "peak_gib", "largest process"),
        (ax_m, "tree_gib", "all processes"),
    ):
        have = [r for r in ok if r.get(key)]
        ax.loglog(
            [r["area_ha"] for r in have], [r[key] for r in have], "o-", label=f"{label} (slope {slope(rows, key):.2f})"
        )
    for r in ok:
        ax_t.annotate(
            f"{r['stations']} st., {r['strategy']}", (r["area_ha"], r["wall_s"]), fontsize=7, xytext=(3, 5),
            textcoords="offset points",
        )  # fmt: skip
    for ax, ylabel in ((ax_t, "seconds"), (ax_m, "peak RSS (GiB)")):
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_minor_formatter(NullFormatter())
        ax.set_xlabel("plant area (ha)")
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("planner plan instances/plant_N ha.json (the plain command), one run each", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def merged(earlier: list[Path], rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Earlier runs' rows with this run's (which replace those of the same area), by area."""
    by = {r["area_ha"]: r for path in earlier for r in json.loads(path.read_text())}
    by |= {r["area_ha"]: r for r in rows}
    return [by[a] for a in sorted(by)]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--areas", nargs="*", type=float, default=[1, 4, 16, 64], help="none: redraw --merge's rows")
    ap.add_argument("--workers", type=int, default=1, help="Dask workers where the strategy is tiles (0: none)")
    ap.add_argument("--worker-memory", default="3GiB", help="memory limit of each Dask worker")
    ap.add_argument("--limit", type=int, default=3600, help="seconds per run before it is stopped")
    ap.add_argument("--out", type=Path, help="markdown table; the figure (.png) beside it, the rows in results/")
    ap.add_argument("--merge", nargs="*", type=Path, default=[], help="rows (.json) of earlier runs to show too")
    a = ap.parse_args()
    rows: list[dict[str, Any]] = []
    results = a.out.parent / "results" / f"{a.out.stem}.json" if a.out else None
    with tempfile.TemporaryDirectory() as d:
        for area in a.areas:
            rows.append(run(area, a.workers, a.worker_memory, Path(d) / f"{area:g}", a.limit))
            print(row_line(rows[-1]), flush=True)
            if results is not None:
                results.write_text(json.dumps(merged(a.merge, rows), indent=1) + "\n")
    every = merged(a.merge, rows)
    print(slope_line(every))
    if a.out:
        a.out.write_text("\n".join([*HEADER, *(row_line(r) for r in every), "", slope_line(every)]) + "\n")
        figure(every, a.out.with_suffix(".png"))


if __name__ == "__main__":
    main()
