"""Memory and time against the candidate-target pairs (issue 32): the full default MILP at finer and finer grids.

For each site and candidate grid spacing, the plain ``planner plan SITE --grid-spacing G --out DIR`` (connected
MILP under the site's overlap, regions and pricing on, 1 thread) runs as its own process under
``/usr/bin/time -v``. Columns: candidates and pairs (the pool after pricing, from plan.json), stations and
status, wall time, peak RSS, and the memory guard's estimate (``planner.plan.memory_guard.estimate_work``: what
``--memory-limit`` compares). Then the log-log slope of peak RSS against pairs (least squares over the rows
of each site), and a figure.

    python scripts/bench/bench_memory.py [--sites building polygon_c] [--grids 3 2 1.5 1 0.5] [--out docs/benchmarks/memory.md]

``building`` is ``scripts/make/make_building.py --seed 0`` (28 zones: 27 rooms 2-7 m across in an L-shaped
outline 44 x 42 m, walls 4.2 m; the same as instances/building27.json).
"""

from __future__ import annotations

import argparse
import json
import math
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

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
    from planner.plan.memory_guard import estimate_work
    from planner.site import load_site
    from planner.site.validate import validate_site

    s = load_site(site)
    reach = validate_site(s).range_limit.max_slant_range_m
    return estimate_work(s, 1.0, grid, reach).bytes


def run(site: Path, grid: float, out: Path, limit_s: int) -> dict:
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(
            [
                "/usr/bin/time",
                "-v",
                sys.executable,
                "-m",
                "planner",
                "plan",
                str(site),
                "--grid-spacing",
                str(grid),
                "--out",
                str(out),
                "--quiet",
            ],
            capture_output=True,
            text=True,
            cwd=ROOT,
            timeout=limit_s,
            check=False,
        )
    except subprocess.TimeoutExpired:  # a row that says so, and the next grid goes on
        return {
            "wall_s": time.perf_counter() - t0,
            "peak_gib": math.nan,
            "exit": "stopped",
            "error": f"stopped at the {limit_s}-s limit",
        }
    wall = time.perf_counter() - t0
    rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", proc.stderr)
    row = {"wall_s": wall, "peak_gib": int(rss.group(1)) / 2**20 if rss else math.nan, "exit": proc.returncode}
    if proc.returncode == 0:
        plan = json.loads((out / "plan.json").read_text())
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
    else:
        row["error"] = proc.stderr.strip().splitlines()[-1][:200] if proc.stderr.strip() else ""
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
    ax.set_xlabel("candidate-target pairs (pool after pricing)")
    ax.set_ylabel("peak RSS of planner plan (GiB)")
    ax.set_title("Default MILP, finer candidate grids (1 thread)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sites", nargs="+", default=["building", "polygon_c"])
    ap.add_argument("--grids", nargs="+", type=float, default=[3.0, 2.0, 1.5, 1.0, 0.5])
    ap.add_argument("--limit", type=int, default=1800, help="seconds per run before it is stopped")
    ap.add_argument("--out", help="markdown table; the figure goes beside it as .png")
    a = ap.parse_args()
    lines = [
        (
            "| site | grid m | candidates | pairs | kept | presolve s | stations | status | scope | wall s | peak GiB | "
            "guard estimate GiB | estimate / peak |"
        ),
        "|---" * 13 + "|",
    ]
    results: dict[str, list[dict]] = {}
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        for name in a.sites:
            site = site_path(name, tmp)
            for g in a.grids:
                r = run(site, g, tmp / f"{name}-{g}", a.limit) | {"grid": g}
                r["estimate_gib"] = estimate_bytes(site, g) / 2**30
                results.setdefault(name, []).append(r)
                if r["exit"] == 0:
                    lines.append(
                        f"| {name} | {g:g} | {r['candidates']:,} | {r['pairs']:,} | {r['kept']:,} | "
                        f"{r['presolve_s']:.1f} | {r['stations']} | {r['status']} | {r['scope']} | "
                        f"{r['wall_s']:.1f} | {r['peak_gib']:.2f} | {r['estimate_gib']:.2f} | "
                        f"{r['estimate_gib'] / r['peak_gib']:.2f} |"
                    )
                else:
                    lines.append(
                        f"| {name} | {g:g} | - | - | - | - | - | exit {r['exit']}: {r.get('error', '')} | - | "
                        f"{r['wall_s']:.1f} | {r['peak_gib']:.2f} | {r['estimate_gib']:.2f} | - |"
                    )
                print(lines[-1], flush=True)
            lines.append(
                f"| {name} | log-log slopes against pairs: peak memory {slope(results[name]):.2f}, wall time "
                f"{slope(results[name], 'wall_s'):.2f} |||||||||||| "
            )
            print(lines[-1], flush=True)
    if a.out:
        Path(a.out).write_text("\n".join(lines) + "\n")
        figure(results, Path(a.out).with_suffix(".png"))


if __name__ == "__main__":
    main()
