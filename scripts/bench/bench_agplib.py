"""Art-gallery polygons (AGPLIB) with range and incidence limits switched off: station counts vs the
published point-guard optimum.

Protocol: each .pol polygon is scaled to a 100 m extent, walls 3 m; S_max 10^5 m (off), theta_max
89.99 deg (off), no precision limit, no registration overlap; candidate grid ``--grid`` m (default 2),
wall pieces ``--pieces`` m (default 1); MILP on CP-SAT, one thread, seed 0, ``--time-limit`` s. Every
plan is re-verified at 0.1 m. Seeing the walls needs at most as many stations as guarding the
interior (a guard set sees every boundary point), so a higher count comes from the discretisation
(finite candidates, grid points at least 0.1 m off the walls, whole-piece coverage) or the stricter sight
test, and is listed. Where some piece is seen by no candidate the grid is refined to 1 m, then 0.5 m.

    python scripts/bench/bench_agplib.py [--per-class 5] [--sizes 20 40 60] [--out docs/benchmarks]
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import time
from pathlib import Path

import planner

ROOT = Path(__file__).resolve().parents[2]
AGP = ROOT.parent / "shared/benchmarks/agplib"
CLASSES = (
    "agp2009a-simplerand",
    "agp2009a-orthorand",
    "agp2009a-rvk",
    "agp2009a-cvk",
    "spike",
    "agp2013-gB-simple-simple",
)


def known() -> dict[str, dict[str, str]]:
    with (AGP / "known_optima.csv").open() as f:
        return {r["instance"]: r for r in csv.DictReader(f)}


def pick(per_class: int, sizes: list[int], table: dict[str, dict[str, str]]) -> list[dict[str, str]]:
    """The first ``per_class`` polygons (by name) of each size in ``sizes`` for the random classes; the
    smallest ``per_class`` with a known optimum for the classes with holes; von Koch up to 500 vertices."""
    out = []
    for cls in CLASSES:
        rows = sorted(
            (r for r in table.values() if r["class"] == cls and r["opt_point_guards"]),
            key=lambda r: (int(r["total_vertices"]), r["instance"]),
        )
        if cls in ("spike", "agp2013-gB-simple-simple"):
            out += rows[:per_class]
        elif cls == "agp2009a-cvk":
            out += [r for r in rows if int(r["total_vertices"]) <= 500]
        else:
            for size in sizes:
                out += [r for r in rows if int(r["outer_vertices"]) == size][:per_class]
    return out


def run(row: dict[str, str], grid: float, pieces: float, time_limit: float, standoff: float = 0.1) -> dict[str, object]:
    path = AGP / "instances" / row["class"] / f"{row['instance']}.pol"
    site = planner.load_site(path)
    params = dataclasses.replace(site.parameters, max_slant_range_m=1e4, theta_max_deg=89.99)
    site = dataclasses.replace(site, parameters=params)
    options = planner.PlanOptions(
        method="milp",
        target_spacing_m=pieces,
        precision=False,
        pool=planner.PoolOptions(grid_spacing_m=grid, min_standoff_m=standoff),
        milp=planner.MilpOptions(time_limit_s=time_limit, overlap=None),
    )
    t0 = time.perf_counter()
    for g in (grid, grid / 2, grid / 4):  # a sliver no grid point reaches: refine (the grid used is reported)
        options = dataclasses.replace(options, pool=dataclasses.replace(options.pool, grid_spacing_m=g))
        try:
            plan = planner.plan_site(site, options)
            break
        except planner.InfeasibleError as exc:
            err = exc
    else:
        return {
            "class": row["class"],
            "instance": row["instance"],
            "vertices": row["total_vertices"],
            "holes": row["holes"],
            "opt_point_guards": int(row["opt_point_guards"]),
            "stations": -1,
            "status": f"infeasible: {err.message[:80]}",
            "grid_m": g,
            "total_s": round(time.perf_counter() - t0, 2),
        }
    n, opt = len(plan.stations), int(row["opt_point_guards"])
    return {
        "class": row["class"],
        "instance": row["instance"],
        "vertices": row["total_vertices"],
        "holes": row["holes"],
        "opt_point_guards": opt,
        "opt_vertex_guards": row["opt_vertex_guards"],
        "stations": n,
        "bound": plan.result.bound,
        "status": plan.result.status.value,
        "grid_m": g,
        "verified_percent": round(plan.verification.percent, 3),
        "complete": plan.verification.complete,
        "candidates": plan.problem_size["candidates"],
        "targets": plan.problem_size["targets"],
        "total_s": round(time.perf_counter() - t0, 2),
        "versus_optimum": f"{n - opt:+d}",
    }


#: the heading of the written part of agplib.md, kept when the table is rewritten
NOTES = "## What the comparison shows"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-class", type=int, default=5)
    ap.add_argument("--sizes", type=int, nargs="+", default=[20, 40, 60])
    ap.add_argument("--grid", type=float, default=2.0)
    ap.add_argument("--pieces", type=float, default=1.0)
    ap.add_argument("--time-limit", type=float, default=60.0)
    ap.add_argument("--out", default=str(ROOT / "docs/benchmarks"))
    args = ap.parse_args()
    rows = []
    for r in pick(args.per_class, args.sizes, known()):
        rows.append(run(r, args.grid, args.pieces, args.time_limit))
        if isinstance(rows[-1].get("versus_optimum"), str) and rows[-1]["versus_optimum"] != "+0":
            # higher than the optimum: is it the discretisation? rerun with a twice finer grid, 4x shorter pieces
            fine = run(r, args.grid / 2, args.pieces / 4, args.time_limit)
            rows[-1]["fine_stations"] = (
                fine["stations"] if fine["status"] == "optimal" else f"{fine['stations']} ({fine['status'][:40]})"
            )
        print(rows[-1], flush=True)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "results").mkdir(parents=True, exist_ok=True)
    with (out / "results" / "agplib.csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(max(rows, key=len)))
        w.writeheader()
        w.writerows(rows)
    lines = [
        "| class | instance | vertices | holes | point-guard optimum | stations | difference | finer (grid/2, pieces/4) "
        "| status | grid m | verified % | s |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    lines += [
        f"| {r['class']} | {r['instance']} | {r['vertices']} | {r['holes']} | {r['opt_point_guards']} | {r['stations']} | "
        f"{r.get('versus_optimum', '-')} | {r.get('fine_stations', '')} | {r['status']} | {r['grid_m']:g} | "
        f"{r.get('verified_percent', '-')} | {r['total_s']} |"
        for r in rows
    ]
    head = [
        "# Art-gallery polygons (AGPLIB), limits off",
        "",
        "Written by `python scripts/bench/bench_agplib.py`. " + " ".join(__doc__.split("\n\n")[1].split()),
        "",
        "`finer`: the station count when a plan above the optimum is rerun with a twice finer grid and four times",
        "shorter wall pieces. `-1`: no plan, some wall piece seen by no candidate (status gives the first).",
        "",
    ]
    # the written analysis below the table is kept (everything from "## What the comparison shows" on)
    old = (out / "agplib.md").read_text() if (out / "agplib.md").exists() else ""
    notes = old[old.index(NOTES) :] if NOTES in old else ""
    (out / "agplib.md").write_text("\n".join(head + lines) + "\n" + ("\n" + notes if notes else ""))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
