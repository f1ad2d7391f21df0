"""Plan IFC building models per storey and draw each storey with its rooms and stations.

Usage::

    python scripts/studies/plan_ifc.py [--fzk PATH] [--out docs/figures] [--registration zone|site]

Plans instances/house2.ifc (written by scripts/make/make_ifc_house.py) storey by storey and, when it
is present, the ground floor (Erdgeschoss) of the KIT AC20-FZK-Haus (not committed, docs/ifc.md),
with the default options (MILP on CP-SAT, 1 thread); prints a markdown table and the stations per
room, and writes one PNG per storey.
"""

from __future__ import annotations

import argparse
import time
from collections import Counter
from pathlib import Path

import planner
from planner.coverage.links import default_registration
from planner.figures.base import png_bytes
from planner.figures.storey_fig import storey_figure
from planner.io.ifc_in import IfcOptions

ROOT = Path(__file__).resolve().parents[2]


def plan_storey(path: Path, storey: str, out: Path, tag: str, registration: str | None = None) -> str:
    site = planner.load_site(path, ifc=IfcOptions(storey=storey))
    t0 = time.perf_counter()
    plan = planner.plan_site(site, planner.PlanOptions(method="milp", registration=registration))
    dt = time.perf_counter() - t0
    r = plan.result
    per_room = Counter(s.zone for s in plan.stations)
    rooms = ", ".join(f"{z.id} {per_room.get(z.id, 0)}" for z in site.zones)
    png = out / f"ifc_{tag}.png"
    png.write_bytes(
        png_bytes(
            storey_figure(
                site, plan.stations, site.zones[0].frame, f"{path.name}, storey {storey}: {len(plan.stations)} stations"
            )
        )
    )
    scope = r.info.get("bound_scope", "pool")
    mode = registration or default_registration(site).mode
    return (
        f"| {path.name} | {storey} | {mode} | {len(site.zones)} | {len(plan.stations)} | {r.bound} ({scope}) | "
        f"{dt:.1f} | {plan.verification.percent:.3f} % | {rooms} | {png.relative_to(ROOT) if png.is_relative_to(ROOT) else png} |"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fzk", default=str(ROOT / "instances/external/AC20-FZK-Haus.ifc"))
    ap.add_argument("--out", default=str(ROOT / "docs/figures"))
    ap.add_argument(
        "--registration",
        choices=("zone", "site"),
        default=None,
        help="registration bundles (default: the planner's, site for a model with doors)",
    )
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print(
        "| model | storey | registration | rooms | stations | bound (scope) | time s | verified | stations per room | figure |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    house = ROOT / "instances/house2.ifc"
    for storey in ("Ground floor", "Upper floor"):
        print(plan_storey(house, storey, out, "house2_" + storey.split()[0].lower(), args.registration))
    fzk = Path(args.fzk)
    if fzk.is_file():
        print(plan_storey(fzk, "Erdgeschoss", out, "fzk_erdgeschoss", args.registration))
    else:
        print(f"(skipped {fzk}: not present)")


if __name__ == "__main__":
    main()
