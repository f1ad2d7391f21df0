"""Benchmark of the coverage build: candidate-target pairs per second, and growth with site size.

Usage: python scripts/bench_coverage.py [--copies 1 2 5 10] [--out FILE.md]

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
import time
from pathlib import Path

import numpy as np

from planner.candidates.pool import PoolOptions, candidate_pool
from planner.coverage.matrix import build_coverage
from planner.coverage.targets import make_targets
from planner.plan import closed_form_limits, sight_limits
from planner.site import Site, Zone, load_site
from planner.validate import validate_site

ROOT = Path(__file__).resolve().parent.parent


def copies_of(site: Site, n: int, spacing_m: float = 450.0) -> Site:
    z = site.zones[0]
    zones = tuple(Zone(f"{z.id}{k}", z.scan_side, tuple((x + k * spacing_m, y) for x, y in z.vertices), z.vertex_heights_m)
                  for k in range(n))
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
    return {"site": site.name, "walls": walls, "wall_m": sum(z.perimeter_m for z in site.zones),
            "candidates": len(cands), "targets": len(targets), "kept": cov.by_candidate.nnz, "time_s": best,
            "pairs_per_s": len(cands) * len(targets) / best, "kept_per_s": cov.by_candidate.nnz / best}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--copies", type=int, nargs="+", default=[1, 2, 5, 10])
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--out")
    args = ap.parse_args()
    rows = [measure(load_site(ROOT / f"instances/{n}.json"), args.repeat) for n in ("polygon_a", "polygon_b", "polygon_c", "baalbek")]
    c = load_site(ROOT / "instances/polygon_c.json")
    scale = [measure(copies_of(c, n), args.repeat) for n in args.copies]
    head = "| site | walls | wall length m | candidates | targets | pairs kept | build s | C x T pairs/s | kept pairs/s |"
    line = "|---|---|---|---|---|---|---|---|---|"
    fmt = lambda r: (f"| {r['site']} | {r['walls']} | {r['wall_m']:,.0f} | {r['candidates']:,} | {r['targets']:,} | "
                     f"{r['kept']:,} | {r['time_s']:.2f} | {r['pairs_per_s']:,.0f} | {r['kept_per_s']:,.0f} |")
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
