"""Memory and time against the candidate-target pairs (issue 32): the full default MILP at finer and finer grids.

For each site and candidate grid spacing, the plain ``planner plan SITE --grid-spacing G --out DIR`` (connected
MILP under the site's overlap, regions and pricing on, 1 thread) runs as its own process under
``/usr/bin/time -v``. Columns: candidates and pairs (the pool after pricing, from plan.json), the candidates the
MILP's presolve keeps and its seconds, stations and status, wall time, peak RSS, and the memory guard's estimate
(``planner.plan.memory_guard.estimate_work``: what ``--memory-limit`` compares). Then the log-log slopes of peak
RSS and of wall time against pairs (least squares over the rows of each site), and a figure.

    python scripts/bench/bench_memory.py [--sites building polygon_c] [--grids 3 2 1.5 1 0.5] [--limit S]
        [--out docs/benchmarks/memory.md] [--merge earlier.json ...]

The rows also go to the .json beside ``--out``; ``--merge`` shows earlier runs' rows in the table and the figure
too (a row of this run replaces one of the same site and grid); ``--sites`` with no site redraws them alone.

``building`` is ``scripts/make/make_building.py --seed 0`` (28 zones: 27 rooms 2-7 m across in an L-shaped
outline 44 x 42 m, walls 4.2 m; the same as instances/building27.json).
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
from _timed import timed_plan

ROOT = Path(__file__).resolve().parents[2]


def site_path(name: str, tmp: Path) -> Path:
    if name == "building":
        out = tmp / "building.json"
        subprocess.run(
            [sys.executable, str(ROOT / "scripts/make/make_building.py"), "--seed", "0", "--out", str(out)],
            check=True,
            capture_output=True,
        )
        return out
    return ROOT / f"instances/{name}.json"


def estimate_bytes(site: Path, grid: float) -> int:
    from planner.io import load_site
    from planner.plan.memory_guard import estimate_work
    from planner.site.validate import validate_site

    s = load_site(site)
    reach = validate_site(s).range_limit.max_slant_range_m
    return estimate_work(s, 1.0, grid, reach).bytes


def run(site: Path, grid: float, out: Path, limit_s: int, memory_limit: str | None = None) -> dict:
    """One ``planner plan SITE --grid-spacing G`` under ``/usr/bin/time -v`` (:func:`_timed.timed_plan`), with
    the pool's size, the plan's and the presolve's figures from its plan.json."""
    given = ["--memory-limit", memory_limit] if memory_limit else []
    row, plan = timed_plan([str(site), "--grid-spacing", str(grid), *given], out, limit_s)
    if plan is not None:
        pre = plan.get("presolve") or {}
        row.update(
            candidates=plan["problem"]["candidates"],
            pairs=plan["problem"]["pairs"],
            stations=plan["counts"]["total"],
            status=plan["status"],
            scope=plan["bound_scope"],
            kept=pre.get("candidates_out", math.nan),
            presolve_s=pre.get("time_s", math.nan),
        )
    return row


def slope(rows: list[dict], key: str = "peak_gib") -> float:
    """Least-squares slope of log ``key`` against log pairs over the rows that finished."""
    ok = [r for r in rows if r.get("pairs")]
    if len(ok) < 2:
        return math.nan
    x = np.log([r["pairs"] for r in ok])
    y = np.log([r[key] for r in ok])
    return float(np.polyfit(x, y, 1)[0])


def figure(results: dict[str, list[dict]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for name, rows in results.items():
        ok = [r for r in rows if r.get("pairs")]
        ax.loglog(
            [r["pairs"] for r in ok], [r["peak_gib"] for r in ok], "o-", label=f"{name} (slope {slope(rows):.2f})"
        )
        for r in ok:
            ax.annotate(
                f"{r['grid']:g} m", (r["pairs"], r["peak_gib"]), fontsize=7, xytext=(3, -8), textcoords="offset points"
            )
    from matplotlib.ticker import NullFormatter

    for axis in (ax.xaxis, ax.yaxis):
        axis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("candidate-target pairs (pool after pricing)")
    ax.set_ylabel("peak RSS of planner plan (GiB)")
    ax.set_title("Default MILP, finer candidate grids (1 thread)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)


HEADER = [
    (
        "| site | grid m | candidates | pairs | kept | presolve s | stations | status | scope | wall s | CPU s | peak GiB | "
        "guard estimate GiB | estimate / peak |"
    ),
    "|---" * 14 + "|",
]


def cell(value: Any, fmt: str) -> str:
    """``value`` formatted, or "-" where it is missing (NaN: a row of a run that did not measure it)."""
    return "-" if value is None or (isinstance(value, float) and math.isnan(value)) else format(value, fmt)


def row_line(name: str, r: dict) -> str:
    """One row of the table."""
    g, cpu = r["grid"], cell(r.get("cpu_s"), ".1f")
    if r["exit"] != 0:
        return (
            f"| {name} | {g:g} | - | - | - | - | - | exit {r['exit']}: {r.get('error', '')} | - | "
            f"{r['wall_s']:.1f} | {cpu} | {cell(r['peak_gib'], '.2f')} | {r['estimate_gib']:.2f} | - |"
        )
    return (
        f"| {name} | {g:g} | {r['candidates']:,} | {r['pairs']:,} | {cell(r['kept'], ',')} | "
        f"{cell(r['presolve_s'], '.1f')} | {r['stations']} | {r['status']} | {r['scope']} | "
        f"{r['wall_s']:.1f} | {cpu} | {r['peak_gib']:.2f} | {r['estimate_gib']:.2f} | "
        f"{r['estimate_gib'] / r['peak_gib']:.2f} |"
    )


def slope_line(name: str, rows: list[dict]) -> str:
    """The site's slopes, as a row of the table."""
    return (
        f"| {name} | log-log slopes against pairs: peak memory {slope(rows):.2f}, wall time "
        f"{slope(rows, 'wall_s'):.2f} ||||||||||||| "
    )


def merged(earlier: list[Path], results: dict[str, list[dict]]) -> dict[str, list[dict]]:
    """The rows of earlier runs (their .json) with this run's: a row of this run replaces one of the same site
    and grid; rows by site, then grid from coarse to fine."""
    out: dict[str, dict[float, dict]] = {}
    for path in earlier:
        for name, rows in json.loads(path.read_text()).items():
            for r in rows:
                out.setdefault(name, {})[r["grid"]] = r
    for name, rows in results.items():
        for r in rows:
            out.setdefault(name, {})[r["grid"]] = r
    return {name: [by[g] for g in sorted(by, reverse=True)] for name, by in out.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sites", nargs="*", default=["building", "polygon_c"], help="none: redraw --merge's rows")
    ap.add_argument("--grids", nargs="+", type=float, default=[3.0, 2.0, 1.5, 1.0, 0.5])
    ap.add_argument("--limit", type=int, default=1800, help="seconds per run before it is stopped")
    ap.add_argument("--memory-limit", help="the planner's --memory-limit (default: its own, half the available memory)")
    ap.add_argument("--out", help="markdown table; the figure (.png) and the rows (.json) go beside it")
    ap.add_argument("--merge", nargs="*", type=Path, default=[], help="rows (.json) of earlier runs to show too")
    a = ap.parse_args()
    results: dict[str, list[dict]] = {}
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        for name in a.sites:
            site = site_path(name, tmp)
            for g in a.grids:
                r = run(site, g, tmp / f"{name}-{g}", a.limit, a.memory_limit) | {"grid": g}
                r["estimate_gib"] = estimate_bytes(site, g) / 2**30
                results.setdefault(name, []).append(r)
                print(row_line(name, r), flush=True)
            print(slope_line(name, results[name]), flush=True)
    if a.out:
        out = Path(a.out)
        if results:
            out.with_suffix(".json").write_text(json.dumps(results, indent=1) + "\n")
        rows = merged(a.merge, results)
        lines = [line for name, rs in rows.items() for line in [*(row_line(name, r) for r in rs), slope_line(name, rs)]]
        out.write_text("\n".join(HEADER + lines) + "\n")
        figure(rows, out.with_suffix(".png"))


if __name__ == "__main__":
    main()
