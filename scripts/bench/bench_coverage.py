"""Benchmark of the coverage build: candidate-target pairs per second, and growth with site size.

Usage: python scripts/bench/bench_coverage.py [--copies 1 2 5 10] [--out FILE.md]
       python scripts/bench/bench_coverage.py --grid 10 5 2 1 0.5 [--sites building27 polygon_c] [--out FILE.md]

With ``--grid``, each (site, grid spacing) is built in a fresh process under ``/usr/bin/time -v``:
candidates, targets, pairs kept, build time and the process's peak RSS; then the slope of peak RSS
against pairs kept (bytes per pair, least squares over all rows of a site).

Protocol: the pool (closed form + field samples + corner rays + 10 m grid) and
1 m targets of each bundled instance are built once, then the coverage matrix
is built and timed (best of --repeat runs, one process, this machine). The
scaling sites are N copies of polygon C (concave, so sight lines are really
blocked) placed 450 m apart in one frame, so walls, candidates and blockers all
grow N-fold. "pairs/s" is candidates x targets divided by the build time; the
build only examines pairs within S_max of each candidate chunk, so this ratio
grows with site size while the pairs really tested grow about linearly.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from _timed import peak_rss_mb

from planner.candidates.pool import PoolOptions, candidate_pool
from planner.coverage.matrix import build_coverage
from planner.coverage.targets import make_targets
from planner.coverage.visibility import sight_limits
from planner.io import load_site
from planner.plan import closed_form_limits
from planner.site import Site, Zone
from planner.site.validate import validate_site

ROOT = Path(__file__).resolve().parents[2]


def copies_of(site: Site, n: int, spacing_m: float = 450.0) -> Site:
    z = site.zones[0]
    zones = tuple(
        Zone(f"{z.id}{k}", z.scan_side, tuple((x + k * spacing_m, y) for x, y in z.vertices), z.vertex_heights_m)
        for k in range(n)
    )
    return Site(f"{site.name} x{n}", zones, site.parameters, site.instrument)


def measure(site: Site, repeat: int) -> dict:
    v = validate_site(site)
    cands = candidate_pool(site, closed_form_limits(v), PoolOptions())
    targets = make_targets(site, 1.0)
    limits = sight_limits(v, False, True)
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        cov = build_coverage(site, cands, targets, limits)
        best = min(best, time.perf_counter() - t0)
    walls = sum(len(z.walls) for z in site.zones)
    return {
        "site": site.name,
        "walls": walls,
        "wall_m": sum(z.perimeter_m for z in site.zones),
        "candidates": len(cands),
        "targets": len(targets),
        "kept": cov.by_candidate.nnz,
        "time_s": best,
        "pairs_per_s": len(cands) * len(targets) / best,
        "kept_per_s": cov.by_candidate.nnz / best,
    }


def one_grid(name: str, spacing_m: float) -> dict:
    """Build the pool at ``spacing_m`` and its coverage; runs inside the child process."""
    site = load_site(ROOT / f"instances/{name}.json")
    v = validate_site(site)
    cands = candidate_pool(site, closed_form_limits(v), PoolOptions(grid_spacing_m=spacing_m))
    targets = make_targets(site, 1.0)
    t0 = time.perf_counter()
    cov = build_coverage(site, cands, targets, sight_limits(v, False, True))
    return {
        "candidates": len(cands),
        "targets": len(targets),
        "pairs": int(cov.by_candidate.nnz),
        "build_s": time.perf_counter() - t0,
    }


def grid_rows(names: list[str], spacings: list[float], limit_s: int) -> list[dict]:
    """One child process per (site, spacing), timed by /usr/bin/time -v for its peak RSS."""
    rows = []
    for name in names:
        for g in spacings:
            cmd = ["/usr/bin/time", "-v", sys.executable, __file__, "--child", name, str(g)]
            try:
                res = subprocess.run(cmd, capture_output=True, text=True, timeout=limit_s)
            except subprocess.TimeoutExpired:
                rows.append({"site": name, "grid_m": g, "note": f"over {limit_s} s"})
                continue
            rss = peak_rss_mb(res.stderr)
            if res.returncode != 0 or rss is None:
                rows.append({"site": name, "grid_m": g, "note": (res.stderr.strip().splitlines() or ["failed"])[-1]})
                continue
            rows.append({"site": name, "grid_m": g, **json.loads(res.stdout.strip().splitlines()[-1]), "peak_mb": rss})
    return rows


def grid_table(rows: list[dict]) -> str:
    out = [
        "| site | grid m | candidates | targets | pairs kept | build s | peak RSS MB |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if "note" in r:
            out.append(f"| {r['site']} | {r['grid_m']:g} | - | - | - | - | {r['note']} |")
        else:
            out.append(
                f"| {r['site']} | {r['grid_m']:g} | {r['candidates']:,} | {r['targets']:,} | {r['pairs']:,} | "
                f"{r['build_s']:.1f} | {r['peak_mb']:,.0f} |"
            )
    for site in dict.fromkeys(r["site"] for r in rows):
        ok = [r for r in rows if r["site"] == site and "note" not in r]
        if len(ok) > 1:
            slope, icpt = np.polyfit([r["pairs"] for r in ok], [r["peak_mb"] * 2**20 for r in ok], 1)
            out.append(
                f"\n{site}: peak RSS = {icpt / 2**20:,.0f} MB + {slope:.0f} bytes x pairs kept (least squares, {len(ok)} rows)"
            )
    return "\n".join(out)


def main() -> None:
    if len(sys.argv) == 4 and sys.argv[1] == "--child":
        print(json.dumps(one_grid(sys.argv[2], float(sys.argv[3]))))
        return
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grid", type=float, nargs="+", help="grid spacings (m): the memory benchmark")
    ap.add_argument("--sites", nargs="+", default=["building27", "polygon_c"])
    ap.add_argument("--limit-s", type=int, default=900)
    ap.add_argument("--copies", type=int, nargs="+", default=[1, 2, 5, 10])
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--out")
    args = ap.parse_args()
    if args.grid:
        text = grid_table(grid_rows(args.sites, args.grid, args.limit_s))
        print(text)
        if args.out:
            Path(args.out).write_text(text + "\n")
        return
    rows = [
        measure(load_site(ROOT / f"instances/{n}.json"), args.repeat)
        for n in ("polygon_a", "polygon_b", "polygon_c", "baalbek")
    ]
    c = load_site(ROOT / "instances/polygon_c.json")
    scale = [measure(copies_of(c, n), args.repeat) for n in args.copies]
    head = (
        "| site | walls | wall length m | candidates | targets | pairs kept | build s | C x T pairs/s | kept pairs/s |"
    )
    line = "|---|---|---|---|---|---|---|---|---|"

    def fmt(r: dict) -> str:
        return (
            f"| {r['site']} | {r['walls']} | {r['wall_m']:,.0f} | {r['candidates']:,} | {r['targets']:,} | "
            f"{r['kept']:,} | {r['time_s']:.2f} | {r['pairs_per_s']:,.0f} | {r['kept_per_s']:,.0f} |"
        )

    out = ["## Bundled instances", "", head, line] + [fmt(r) for r in rows]
    out += ["", "## Growth with site size (copies of polygon C)", "", head, line] + [fmt(r) for r in scale]
    t = np.array([r["time_s"] for r in scale])
    n = np.array([r["wall_m"] for r in scale])
    if len(scale) > 1:
        slope = np.polyfit(np.log(n), np.log(t), 1)[0]
        out += ["", f"log-log slope of build time against wall length: {slope:.2f} (1 = linear)"]
    text = "\n".join(out)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n")


if __name__ == "__main__":
    main()
