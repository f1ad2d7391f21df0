"""Plans with floors (``--surfaces walls,floors``) timed end to end: where the time goes and whether the floor verifies.

    python scripts/bench/surfaces.py                      # a 10 x 8 m room and polygon B (.csv and .json), 600 s each
    python scripts/bench/surfaces.py instances/polygon_b.csv --limit 300 --csv /tmp/surfaces.csv

Each site is planned by ``python -m planner plan SITE --surfaces walls,floors`` under ``/usr/bin/time -v``
(:func:`_timed.timed_plan`: a run past ``--limit`` is stopped and its row says so). A row holds the wall time, CPU,
peak RSS, the phases the plan's log times (coverage, surface columns, surface verification) and the solve's own
time, the pool (candidates), the patches, the stations, the patches left out (seen by no candidate: NOT covered) and
the floor verification (its spacing, points and covered share). Sizes only: no assertion on time (a shared machine).

Measured on 2 shared cores (polygon B: 9,678 m2 of floor, 10,015 patches of 1 m; P30, floor seen from 1.05 to 3.71 m):

================================  =======  ========  ======  ========  ============================================
run                               wall     peak RSS  pool    stations  floor verification
================================  =======  ========  ======  ========  ============================================
before, milp                      > 600 s  3.0 GiB   7,811   -         - (stopped in the MILP's set-up)
after, milp                       > 600 s  0.86 GiB  4,892   -         - (stopped in the MILP's ring bound)
after, greedy                     116 s    0.85 GiB  4,892   890       100.000 % of 967,770 points at 0.1 m, 3.3 s
10 x 8 m room, milp               9 s      0.21 GiB  100     8         100 % of 8,000 points at 0.1 m (unchanged)
B.json (IH 1.5, no cone), milp    491 s    0.53 GiB  2,399   486       100.000 % of 967,770 points at 0.1 m, 1.5 s
B.json (IH 1.5, no cone), greedy  68 s     0.45 GiB  2,399   565       100.000 % of 967,770 points at 0.1 m, 2.1 s
================================  =======  ========  ======  ========  ============================================

The floor grid of B went from 4,926 to 2,007 points (the thinning keeps 3 seers per patch: no patch lost), the
surface columns from 107,497 to 46,609 pairs (1.95 s to 0.47 s). What is left is quadratic in stations and
candidates outside the floors: the MILP (ring bound, local search), the registration relation (one sparse lookup per
station pair) and the plan's registration links when plan.json is written.
"""

from __future__ import annotations

import argparse
import re
import sys
import tempfile
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _timed import ROOT, append_csv, timed_plan

FIELDS = [
    "site",
    "exit",
    "wall_s",
    "cpu_s",
    "peak_gib",
    "coverage_s",
    "surface_cover_s",
    "solve_s",
    "verify_s",
    "candidates",
    "patches",
    "stations",
    "left_out",
    "left_out_m2",
    "verify_spacing_m",
    "floor_points",
    "floor_covered_pct",
    "state",
    "error",
]
ROOM = "R,inside,{i},{length},3,90,3"
HEADER = "zone,scan_side,index,side_length_m,wall_height_m,interior_angle_deg,vertex_height_m"


def room_csv(folder: Path) -> Path:
    """A 10 x 8 m room, 3 m high: the small case beside the large one."""
    path = folder / "room_10x8.csv"
    rows = [ROOM.format(i=i, length=length) for i, length in enumerate((10, 8, 10, 8), 1)]
    path.write_text("\n".join([HEADER, *rows]) + "\n")
    return path


def _seconds(log: list[str], pattern: str) -> float | None:
    """The seconds a log line matching ``pattern`` (one group) gives, None where none does."""
    for line in log:
        m = re.search(pattern, line)
        if m:
            return float(m.group(1))
    return None


def row_of(site: str, timed: dict[str, Any], plan: dict[str, Any] | None) -> dict[str, Any]:
    """The bench row of one run: the timing of ``timed`` and what the plan.json says."""
    row = {"site": site, **timed}
    if plan is None:
        return row
    log = list(plan.get("log", []))
    surfaces = plan.get("surfaces") or {}
    ver = surfaces.get("verification", {})
    floors = [z for z in ver.get("zones", []) if z["type"] == "floor"]
    unseen = surfaces.get("unseen_patches") or {}
    points = sum(z["points"] for z in floors)
    row |= {
        "coverage_s": _seconds(log, r"coverage built in ([\d.]+) s"),
        "surface_cover_s": _seconds(log, r"^surface cover: .*\(([\d.]+) s\)$"),
        "verify_s": _seconds(log, r"surfaces verified in ([\d.]+) s"),
        "solve_s": plan.get("time_s"),
        "candidates": (plan.get("pool") or plan.get("problem") or {}).get("candidates"),
        "patches": surfaces.get("patches"),
        "stations": len(plan.get("stations", [])),
        "left_out": unseen.get("count"),
        "left_out_m2": unseen.get("area_m2"),
        "verify_spacing_m": min((z["spacing_m"] for z in floors), default=None),
        "floor_points": points,
        "floor_covered_pct": 100.0 * sum(z["covered"] for z in floors) / points if points else None,
        "state": ver.get("state"),
    }
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sites", nargs="*", help="sites (default: a 10 x 8 m room, polygon_b.csv, polygon_b.json)")
    ap.add_argument("--limit", type=int, default=600, help="seconds per run before it is stopped (default 600)")
    ap.add_argument("--csv", type=Path, help="append the rows to this CSV")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        sites = args.sites or [
            str(room_csv(Path(tmp))),
            str(ROOT / "instances/polygon_b.csv"),
            str(ROOT / "instances/polygon_b.json"),
        ]
        for k, site in enumerate(sites):
            out = Path(tmp) / f"out{k}"
            timed, plan = timed_plan([site, "--surfaces", "walls,floors"], out, args.limit)
            row = row_of(Path(site).name, timed, plan)
            rows.append(row)
            print(
                "  ".join(
                    f"{f}={row[f]:.3g}" if isinstance(row.get(f), float) else f"{f}={row.get(f)}"
                    for f in FIELDS
                    if row.get(f) is not None
                ),
                flush=True,
            )
    if args.csv:
        append_csv(args.csv, FIELDS, rows)


if __name__ == "__main__":
    main()
