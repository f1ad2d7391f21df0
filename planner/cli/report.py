"""The ``planner report`` command and the exports shared with ``planner plan`` (DXF, GeoJSON, CSV)."""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from planner.core.errors import ExitCode, UsageError
from planner.core.settings import DEFAULTS, EXPORTS

if TYPE_CHECKING:  # the rest loads when a command runs (a fast --help: docs/startup.md)
    from planner.plan.outcome import Outcome


def parse_exports(text: str | None) -> list[str]:
    if not text:
        return []
    items = [x.strip().lower() for x in text.split(",") if x.strip()]
    bad = [x for x in items if x not in EXPORTS]
    if bad:
        raise UsageError(f"unknown export format (known: {', '.join(EXPORTS)})", field="--export", value=bad[0])
    return items


def write_exports(outcome: Outcome, formats: list[str], folder: str, crs: str | None) -> None:
    from planner.io import write_dxf, write_geojson, write_stations_csv

    writers = {
        "dxf": lambda: write_dxf(outcome, Path(folder) / "plan.dxf"),
        "geojson": lambda: write_geojson(outcome, Path(folder) / "plan.geojson", crs),
        "csv": lambda: write_stations_csv(outcome, Path(folder) / "stations.csv", crs),
    }
    for f in formats:
        print(f"wrote {writers[f]()}")


def cmd_report(args: argparse.Namespace) -> int:
    from planner.io.plan_file import outcome_from_file
    from planner.network.check import run_network
    from planner.report import write_report
    from planner.report.html import linked_field_sheet
    from planner.report.site_map import numbered_outcome, report_numbering

    formats = parse_exports(args.export)
    ifc = None
    if args.storey or args.exterior or args.ifc_windows:
        from planner.io.ifc_in import IfcOptions

        ifc = IfcOptions(storey=args.storey, windows=args.ifc_windows, exterior=args.exterior)
    outcome = outcome_from_file(args.plan, args.site, ifc=ifc)
    folder = args.out or str(Path(args.plan).parent)
    # judged under the limits the plan was made under
    network = (
        None
        if args.no_network
        else run_network(outcome.sight, list(outcome.stations), seed=0, registration=outcome.registration)
    )
    comparison = _file_comparison(outcome)
    outcome = replace(outcome, network=network, comparison=tuple(comparison))
    # one numbering for the report and the exports: the linked field sheet's walking order, else the plan's own
    outcome = numbered_outcome(outcome, report_numbering(outcome, linked_field_sheet(folder)[1]))
    write_exports(outcome, formats, folder, args.crs)
    print(outcome.summary())
    print(f"wrote {write_report(outcome, folder)}")
    return ExitCode.OK


def _file_comparison(outcome: Outcome) -> list[dict[str, Any]]:
    """Closed form and greedy recomputed with the plan's settings, beside the plan's own figures."""
    from planner.candidates.pool import GRID_SPACING_M, PoolOptions
    from planner.plan import PlanOptions, resolve
    from planner.report import compare_methods
    from planner.report.compare import meta_row
    from planner.solve.milp import MilpOptions

    m, p = outcome.meta, outcome.meta.get("parameters", {})
    options = PlanOptions(
        target_spacing_m=float(p.get("target_spacing_m", DEFAULTS["plan.target_spacing_m"])),
        pool=PoolOptions(grid_spacing_m=float(p.get("grid_spacing_m", GRID_SPACING_M)), seed=int(p.get("seed", 0))),
        incidence_3d=p.get("incidence") == "3d",
        precision=bool(p.get("precision", True)),
        milp=MilpOptions(precision=p.get("precision_mode", "single")),
    )
    problem = resolve(outcome.site, options, validation=outcome.validation)
    rows = [r for r in compare_methods(problem) if r["method"] != m.get("method")]
    return rows + [{**meta_row(m, outcome.verification.percent), "stations": len(outcome.stations)}]


def add_report_parser(sub: Any) -> None:
    rp = sub.add_parser("report", help="write the HTML report (and exports) of a plan.json")
    rp.add_argument("plan", help="plan.json written by planner plan --out")
    rp.add_argument("--site", help="the site file (default: the one recorded in the plan)")
    rp.add_argument("--out", metavar="DIR", help="folder for report.html and exports (default: the plan's folder)")
    rp.add_argument("--export", metavar="LIST", help="also write dxf, geojson, csv (comma-separated)")
    rp.add_argument("--crs", metavar="CRS", help="write GeoJSON in lon/lat from this metric CRS")
    rp.add_argument("--no-network", action="store_true", help="leave out the network and accuracy check")
    rp.add_argument("--storey", metavar="NAME|INDEX|all", help="IFC site: the storey the plan was made for")
    rp.add_argument("--exterior", action="store_true", help="IFC site: planned with --exterior (plan: --set exterior)")
    rp.add_argument(
        "--ifc-windows", action="store_true", help="IFC site: planned with --ifc-windows (plan: --set ifc-windows)"
    )
    rp.add_argument("--quiet", action="store_true", help="no progress bars")
    rp.set_defaults(func=cmd_report)
