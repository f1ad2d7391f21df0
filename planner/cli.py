"""The ``planner`` command: one function per subcommand; parses, calls the library, prints.

Exit codes: 0 ok, 1 internal error, 2 usage, 3 invalid input, 4 infeasible
problem (see :mod:`planner.errors`). Errors print as one line on stderr; set
PLANNER_DEBUG=1 to see the traceback of an internal error.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import traceback
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from planner import __version__, progress
from planner.cli_choices import BACKENDS, CONNECTIVITY, FORMATS, INCIDENCE_MODELS, METHODS, PRECISION_MODES, SIDES
from planner.cli_report import add_report_parser, parse_exports, write_exports
from planner.cli_tiles import add_tile_options, plan_command
from planner.errors import ExitCode, InfeasibleError, PlannerError, UsageError

# Everything else loads inside the command that needs it, so that --help, --version and validate
# start without the solver, network, figure and report stacks (docs/startup.md).
if TYPE_CHECKING:
    from planner.exchange import DxfOptions
    from planner.network.check import NetworkReport
    from planner.plan import PlanOptions
    from planner.site import Site
    from planner.solve.result import SolveResult

#: seed 003: a Monte Carlo design study repeats the adjustment at least 100 times
MIN_MONTE_CARLO = 100

class _Parser(argparse.ArgumentParser):
    """argparse that exits with our usage code and a one-line message."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        print(f"{self.prog}: usage error: {message}", file=sys.stderr)
        raise SystemExit(ExitCode.USAGE)


def _add_site_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("site", help="site file: JSON instance or table CSV")
    p.add_argument("--instrument", help="instrument name from models/ (overrides the instance)")
    p.add_argument("--max-range", type=float, metavar="M", help="slant range S_max in m (overrides derivation)")
    p.add_argument("--theta-max", type=_theta, metavar="DEG|derive",
                   help="largest incidence angle in degrees, or 'derive' (from sigma_req and the incidence model)")
    p.add_argument("--incidence-model", choices=INCIDENCE_MODELS,
                   help="how a view's error grows with incidence: none (range only), table (2.3), soudarissanane")
    p.add_argument("--standoff", type=float, metavar="M", help="no station or control point closer to a wall/obstacle")
    p.add_argument("--overlap", type=float, metavar="FRACTION", help="registration overlap, e.g. 0.3")
    acc = p.add_mutually_exclusive_group()
    acc.add_argument("--sigma-req", type=float, metavar="M", help="required accuracy in m")
    acc.add_argument("--scale", metavar="1:N", help="drawing scale; accuracy from table 1.1")
    p.add_argument("--instrument-height", type=float, metavar="M", help="instrument height IH in m")
    p.add_argument("--angular-tolerance", type=float, metavar="DEG", help="closure tolerance of table CSV zones")
    p.add_argument("--min-relative-precision", type=float, metavar="N", help="closure 1:N of table CSV zones")
    p.add_argument("--crs", metavar="CRS", help="metric CRS (e.g. EPSG:32636) of a lon/lat GeoJSON site; exports go back to lon/lat")
    p.add_argument("--layer-height", action="append", default=[], metavar="LAYER=M",
                   help="DXF: wall height of polylines on LAYER that carry none (repeatable)")
    p.add_argument("--dxf-side", choices=SIDES, default="inside",
                   help="DXF: scan side of zones whose layer and XDATA do not say (default inside)")
    p.add_argument("--storey", metavar="NAME|INDEX|all",
                   help="IFC: the building storey to read (default: every storey that holds spaces)")
    p.add_argument("--exterior", action="store_true", help="IFC: also scan the storey's outer outline from outside")
    p.add_argument("--ifc-windows", action="store_true",
                   help="IFC: record windows as openings too (default: a window is wall surface)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")


def _add_network_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--control", metavar="FILE", help="control points (JSON list: name, x, y, sigma_x_mm, sigma_y_mm)")
    p.add_argument("--monte-carlo", type=int, default=0, metavar="N", help="also simulate N adjustments (seeded)")
    p.add_argument("--traverse", metavar="FILE", help="the planned control traverse (JSON: points, legs), the only "
                   "total-station observations; 'none' for no traverse (default: a proposed one, labelled so)")
    p.add_argument("--ts-everywhere", action="store_true",
                   help="the earlier design: a total station on every station sight line (no traverse)")


def _add_limit_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--incidence", choices=("horizontal", "3d"), default="horizontal",
                   help="incidence angle in plan (as the dissertation) or 3-D to the top of the wall")
    p.add_argument("--no-precision", action="store_true", help="do not require the predicted point error <= sigma_req")


def _add_memory_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--memory-limit", metavar="SIZE",
                   help="refuse a problem whose estimated memory passes SIZE, e.g. 4G (default: half the available memory)")


def load_with_overrides(args: argparse.Namespace) -> Site:
    """Load the site and apply the command-line parameter overrides."""
    from planner.params import ClosureTolerance
    from planner.site import load_site

    tol_kw = {}
    if args.angular_tolerance is not None:
        tol_kw["angular_deg"] = args.angular_tolerance
    if args.min_relative_precision is not None:
        tol_kw["min_relative_precision"] = args.min_relative_precision
    suffix = Path(args.site).suffix.lower()
    site = load_site(args.site, ClosureTolerance(**tol_kw) if tol_kw else None, crs=args.crs,
                     dxf=_dxf_options(args) if suffix == ".dxf" else None,
                     ifc=_ifc_options(args) if suffix == ".ifc" else None)
    p = site.parameters
    derive = args.theta_max == "derive"
    changes = {k: v for k, v in {
        "max_slant_range_m": args.max_range, "theta_max_deg": None if derive else args.theta_max, "overlap": args.overlap,
        "sigma_req_m": args.sigma_req, "instrument_height_m": args.instrument_height,
        "incidence_model": args.incidence_model, "min_standoff_m": args.standoff, "derive_theta_max": derive or None,
    }.items() if v is not None}
    if args.sigma_req is not None:
        changes["drawing_scale"] = None
    p = replace(p, **changes)
    if args.scale is not None:
        p = p.with_scale(args.scale)
    return replace(site, parameters=p, instrument=args.instrument or site.instrument)


def _ifc_options(args: argparse.Namespace) -> Any:
    from planner.exchange.ifc_in import IfcOptions

    return IfcOptions(storey=args.storey, windows=args.ifc_windows, exterior=args.exterior)


def _theta(text: str) -> float | str:
    """--theta-max: degrees, or 'derive'."""
    if text.strip().lower() == "derive":
        return "derive"
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected degrees or 'derive', got {text!r}") from None


def _dxf_options(args: argparse.Namespace) -> DxfOptions:
    from planner.exchange.dxf_in import DxfOptions
    from planner.site import ScanSide

    heights = {}
    for item in args.layer_height:
        layer, _, value = item.partition("=")
        try:
            heights[layer] = float(value)
        except ValueError:
            raise UsageError("expected LAYER=HEIGHT_M", field="--layer-height", value=item) from None
        if not (math.isfinite(heights[layer]) and heights[layer] > 0):
            raise UsageError("height must be a finite number > 0", field="--layer-height", value=item)
    return DxfOptions(layer_heights_m=heights, default_side=ScanSide(args.dxf_side))


def cmd_validate(args: argparse.Namespace) -> int:
    from planner.validate import validate_site

    report = validate_site(load_with_overrides(args))
    print(json.dumps(report.to_dict(), indent=2) if args.json else report.summary())
    return ExitCode.OK


def _plan_options(args: argparse.Namespace, overlap: float) -> PlanOptions:
    from planner.candidates.pool import PoolOptions
    from planner.coverage.overlap import OverlapRule
    from planner.plan import PlanOptions
    from planner.solve.milp import MilpOptions

    pool = PoolOptions(grid_spacing_m=args.grid_spacing, seed=args.seed)
    rule = None if args.no_overlap or overlap == 0 else OverlapRule(overlap, args.min_shared, args.max_link)
    milp = MilpOptions(backend=args.backend, time_limit_s=args.time_limit, seed=args.seed, threads=args.threads,
                       k=args.k, overlap=rule, precision=args.precision, connectivity=args.connectivity,
                       layer_cuts=args.layer_cuts, tree_bound=args.tree_bound, work_limit=args.work_limit,
                       local_search_moves=args.local_search_moves, ring_bound=not args.no_ring_bound,
                       ring_lagrange_steps=args.ring_lagrange_steps)
    return PlanOptions(method=args.method, target_spacing_m=args.target_spacing, pool=pool,
                       incidence_3d=args.incidence == "3d", precision=not args.no_precision,
                       verify_spacing_m=args.verify_spacing, milp=milp,
                       tripod=args.method == "milp" or args.tripod, recentre=args.recentre,
                       registration=args.registration,
                       regions=not args.no_regions, pricing=not args.no_pricing,
                       pricing_time_limit_s=args.pricing_time_limit, memory_limit_bytes=_memory_limit(args))


def _guard_memory(site: Site, args: argparse.Namespace) -> None:
    """The memory check of build_problem, run before the solver stacks load so that a refusal is quick."""
    from planner.memory_guard import check_memory
    from planner.validate import validate_site

    s_max = validate_site(site).range_limit.max_slant_range_m
    check_memory(site, args.target_spacing, args.grid_spacing, s_max, _memory_limit(args))


def _memory_limit(args: argparse.Namespace) -> int | None:
    from planner.memory_guard import parse_memory

    return parse_memory(args.memory_limit) if args.memory_limit else None


def cmd_plan(args: argparse.Namespace) -> int:
    formats = parse_exports(args.export)
    if formats and not args.out:
        raise UsageError("--export writes into the --out folder; give --out DIR", field="--export", value=args.export)
    site = load_with_overrides(args)
    _guard_memory(site, args)
    from planner.outcome import outcome_from_plan
    from planner.plan_io import write_plan
    from planner.report import compare_methods, write_report

    options = _plan_options(args, site.parameters.overlap)
    plan = plan_command(site, options, args)
    if not plan.stations and plan.result.status.value in ("infeasible", "no_solution"):
        print(plan.summary().splitlines()[0])
        raise InfeasibleError(f"{plan.result.method} found no plan: {_no_plan_reason(plan.result, options)}")
    print(plan.summary())
    if args.out:
        print(f"wrote {write_plan(plan, args.out)}")
    network = None
    if args.network or args.report:
        network = _network(site, list(plan.stations), args, show=args.network)
    if formats or args.report:
        outcome = outcome_from_plan(plan, network, compare_methods(site, options, plan) if args.report else ())
        write_exports(outcome, formats, args.out, args.crs)
        if args.report:
            print(f"wrote {write_report(outcome, args.report)}")
    return ExitCode.OK


def _no_plan_reason(result: SolveResult, options: PlanOptions) -> str:
    """Why a solver stopped without stations, in words."""
    info = result.info
    if "targets_seen_by_fewer_than_k" in info:
        return f"{info['count']} target(s) seen by fewer than k = {options.milp.k} candidates"
    if result.status.value == "no_solution":
        return f"no cover found within the time limit of {options.milp.time_limit_s:g} s (raise --time-limit)"
    rules = ["every piece covered"] + (["k = %d" % options.milp.k] if options.milp.k > 1 else [])
    rules += ["registration overlap connected"] if options.milp.overlap is not None else []
    rules += ["combined precision"] if options.combined else []
    return f"the solver proved that no set of candidates meets {', '.join(rules)}"


def _network(site: Site, stations: list[Any], args: argparse.Namespace, show: bool = True) -> NetworkReport:
    from planner.network.check import run_network
    from planner.network.io import adjust_observations, read_control

    if args.monte_carlo and args.monte_carlo < MIN_MONTE_CARLO:
        raise UsageError(f"Monte Carlo needs at least {MIN_MONTE_CARLO} runs (seed 003)", field="--monte-carlo",
                         value=args.monte_carlo)
    from planner.network.traverse import read_traverse

    control = read_control(args.control) if getattr(args, "control", None) else None
    if getattr(args, "traverse", None) and args.ts_everywhere:
        raise UsageError("--traverse and --ts-everywhere exclude each other", field="--traverse", value=args.traverse)
    traverse = read_traverse(args.traverse) if getattr(args, "traverse", None) else None
    report = run_network(site, stations, control=control, monte_carlo_runs=args.monte_carlo, seed=args.seed,
                         registration=getattr(args, "registration", None),
                         precision=getattr(args, "precision", "single"), traverse=traverse,
                         ts_everywhere=getattr(args, "ts_everywhere", False))
    if not show:
        return report
    print(report.summary())
    if getattr(args, "observations", None):
        print(adjust_observations(report, args.observations))
    if args.out:
        Path(args.out).mkdir(parents=True, exist_ok=True)
        path = Path(args.out) / "network.json"
        path.write_text(json.dumps(report.to_dict(), indent=2, default=_jsonable) + "\n")
        print(f"wrote {path}")
    return report


def _jsonable(o: object) -> object:
    import numpy as np

    if isinstance(o, (set, frozenset)):
        return sorted(o)
    if isinstance(o, (np.integer, np.floating)):
        return o.item()
    raise TypeError(type(o).__name__)


def cmd_network(args: argparse.Namespace) -> int:
    from planner.plan_io import read_plan_stations

    site = load_with_overrides(args)
    stations = read_plan_stations(args.plan, site)
    _network(site, stations, args)
    return ExitCode.OK


def cmd_verify(args: argparse.Namespace) -> int:
    from planner.plan import sight_limits
    from planner.plan_io import read_plan_stations
    from planner.validate import validate_site
    from planner.verify import verify_stations

    site = load_with_overrides(args)
    validation = validate_site(site)
    stations = read_plan_stations(args.plan, site)
    limits = sight_limits(validation, args.incidence == "3d", not args.no_precision, args.precision == "combined")
    report = verify_stations(site, stations, limits, args.spacing)
    print(f"plan {args.plan}: {len(stations)} stations")
    print(report.summary())
    return ExitCode.OK if report.complete else ExitCode.INFEASIBLE


def cmd_export(args: argparse.Namespace) -> int:
    site = load_with_overrides(args)
    _guard_memory(site, args)
    from planner.candidates.pool import PoolOptions
    from planner.coverage.overlap import OverlapRule
    from planner.export import export_problem
    from planner.plan import PlanOptions, build_problem

    options = PlanOptions(
        target_spacing_m=args.target_spacing, pool=PoolOptions(grid_spacing_m=args.grid_spacing, seed=args.seed),
        incidence_3d=args.incidence == "3d", precision=not args.no_precision, memory_limit_bytes=_memory_limit(args))
    problem = build_problem(site, options)
    text = export_problem(problem, args.format, OverlapRule(site.parameters.overlap))
    if args.out:
        Path(args.out).write_text(text)
        print(f"wrote {args.out}: {problem.shape[0]} candidates, {problem.shape[1]} targets, {problem.by_candidate.nnz:,} pairs")
    else:
        sys.stdout.write(text)
    return ExitCode.OK


def cmd_instruments(args: argparse.Namespace) -> int:
    from planner.instruments import list_instruments, load_instrument

    for name in list_instruments():
        inst = load_instrument(name)
        print(f"{name:<22}{type(inst).__name__:<14}{inst.description}")
    return ExitCode.OK


def cmd_assemble(args: argparse.Namespace) -> int:
    """Place the table zones of an instance from their shared walls; print matches, residuals, unplaced zones."""
    from planner.site import load_site
    from planner.site.assemble import assemble
    from planner.site.assembly_io import assembled_instance
    from planner.site.fileio import read_json

    path = Path(args.site)
    site = load_site(path)
    report = assemble(site, tolerance_m=args.tolerance, wall_thickness_m=args.wall_thickness, anchor=args.anchor)
    print("\n".join(report.lines()))
    if args.out:
        out = Path(args.out)
        source = read_json(path) if path.suffix.lower() == ".json" else {
            "format": "tls-planner/1", "name": path.stem, "zones": [{"table_csv": path.name}]}
        data = assembled_instance(source, str(path.parent), str(out.parent), report)
        out.write_text(json.dumps(data, indent=2) + "\n")
        print(f"wrote {out}: {len(report.placements)} zones placed, {len(report.unplaced)} left in their own frames")
    return ExitCode.OK


def cmd_chain(args: argparse.Namespace) -> int:
    """The plan's network as a scanner survey: registration links, ties to control, chain accuracy."""
    from planner.network.survey import survey_network
    from planner.plan_io import read_plan_stations

    site = load_with_overrides(args)
    stations = read_plan_stations(args.plan, site)
    print("\n".join(survey_network(site, stations, args.registration).lines()))
    return ExitCode.OK


def _add_assemble_parser(sub: argparse._SubParsersAction) -> None:
    c = sub.add_parser("chain", help="registration-chain accuracy of a plan (links, ties to control; seed 003)")
    _add_site_options(c)
    c.add_argument("plan", help="plan.json with stations [{id, zone, side, x, y}]")
    c.add_argument("--registration", choices=("zone", "site"), default=None,
                   help="registration groups (default: site where zones are placed or openings given)")
    c.set_defaults(func=cmd_chain)
    a = sub.add_parser("assemble", help="place table zones in one site frame from their shared walls")
    a.add_argument("site", help="JSON instance or table CSV")
    a.add_argument("--tolerance", type=float, default=0.005, metavar="M", help="equal side lengths within M m (default 0.005)")
    a.add_argument("--wall-thickness", type=float, default=0.0, metavar="M", help="offset between the two faces (default 0)")
    a.add_argument("--anchor", metavar="ZONE", help="zone whose frame becomes the site frame (default: the outline)")
    a.add_argument("--out", metavar="FILE", help="write the instance with its placements to FILE")
    a.set_defaults(func=cmd_assemble)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="planner", description="Plan terrestrial laser scanner stations.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    v = sub.add_parser("validate", help="read a site and report zones, closures, corrections and limits")
    _add_site_options(v)
    v.add_argument("--json", action="store_true", help="print the report as JSON")
    v.set_defaults(func=cmd_validate)
    pl = sub.add_parser("plan", help="plan the stations of a site and verify the plan")
    _add_site_options(pl)
    pl.add_argument("--method", choices=METHODS, default="milp",
                    help="closed-form (the dissertation), greedy (Chvatal) or milp (optimal; default)")
    pl.add_argument("--backend", choices=BACKENDS, default="cpsat", help="MILP backend (default cpsat)")
    pl.add_argument("--time-limit", type=float, default=60.0, metavar="S", help="MILP time limit in s (default 60)")
    pl.add_argument("--work-limit", type=float, default=None, metavar="S",
                    help="cpsat, 1 thread: stop on S deterministic seconds of CP-SAT work (same plan under any load); "
                         "--time-limit stays a wall-clock cap")
    pl.add_argument("--local-search-moves", type=int, default=500, metavar="N",
                    help="milp: swaps of the local search for a connected plan one station smaller, tried once per "
                         "incumbent size down to the bound (default 500; 0: off)")
    pl.add_argument("--threads", type=int, default=1, help="solver threads (default 1: deterministic)")
    pl.add_argument("--k", type=int, default=1, help="each wall piece seen by at least k stations (default 1)")
    pl.add_argument("--precision", choices=PRECISION_MODES, default="single",
                    help="single: each view must meet sigma_req; combined: views add information (every method)")
    pl.add_argument("--no-overlap", action="store_true", help="MILP and greedy without the registration-overlap constraint")
    pl.add_argument("--connectivity", choices=CONNECTIVITY, default="auto",
                    help="milp: registration connectivity by branch-and-cut (bc, pyscipopt backend), a flow model or "
                         "the cut loop (auto: bc on pyscipopt, loop elsewhere)")
    pl.add_argument("--layer-cuts", action="store_true", help="milp: add distance-layer cuts before the first solve")
    pl.add_argument("--tree-bound", action="store_true", help="milp: add the tree (Hunter) covering bound rows")
    pl.add_argument("--no-ring-bound", action="store_true",
                    help="milp: no ring bound (the cheapest walk over the arcs a zone-side's stations see, exact when "
                         "each sees one run of its wall)")
    pl.add_argument("--ring-lagrange-steps", type=int, default=500, metavar="N",
                    help="milp: steps of the Lagrangian ascent that adds the cover rows to the ring bound (default 500; "
                         "0: the ring bound alone)")
    pl.add_argument("--min-shared", type=float, default=0.0, metavar="M", help="registration: shared wall at least M m")
    pl.add_argument("--max-link", type=float, default=None, metavar="M", help="registration: stations at most M m apart")
    pl.add_argument("--registration", choices=("zone", "site"), default=None,
                    help="one registration bundle per zone-side, or per accessible area of the site (default: site "
                         "where zones are placed or openings given)")
    pl.add_argument("--tripod", action="store_true", help="compute tripod discs (always on for milp)")
    pl.add_argument("--recentre", action="store_true", help="move each station to the centre of its tripod disc")
    pl.add_argument("--no-regions", action="store_true",
                    help="no whole-zone-side candidates from the coverage regions (the pool as before issue 12)")
    pl.add_argument("--no-pricing", action="store_true",
                    help="milp: no geometric pricing, so the bound holds over the candidate pool only")
    pl.add_argument("--pricing-time-limit", type=float, default=120.0, metavar="S",
                    help="milp: time for geometric pricing (default 120 s); past it the bound scope stays 'pool'")
    _add_memory_option(pl)
    pl.add_argument("--network", action="store_true", help="then build the station network and check its accuracy")
    _add_network_options(pl)
    pl.add_argument("--out", metavar="DIR", help="write DIR/plan.json")
    pl.add_argument("--export", metavar="LIST", help="also write into --out: dxf (plan.dxf), geojson (plan.geojson), "
                    "csv (stations.csv), comma-separated")
    pl.add_argument("--report", metavar="DIR", help="write DIR/report.html (figures embedded; runs the network check)")
    pl.add_argument("--seed", type=int, default=0, help="seed of the movement-field sampling (default 0)")
    pl.add_argument("--target-spacing", type=float, default=1.0, metavar="M", help="wall piece length (default 1 m)")
    pl.add_argument("--grid-spacing", type=float, default=10.0, metavar="M", help="candidate grid spacing (default 10 m)")
    pl.add_argument("--verify-spacing", type=float, default=0.1, metavar="M", help="verification sampling (default 0.1 m)")
    _add_limit_options(pl)
    add_tile_options(pl)
    pl.set_defaults(func=cmd_plan)
    ve = sub.add_parser("verify", help="re-verify any plan's coverage on a fine sampling of every wall")
    _add_site_options(ve)
    ve.add_argument("plan", help="plan.json with stations [{id, zone, side, x, y}] in the zones' frames")
    ve.add_argument("--spacing", type=float, default=0.1, metavar="M", help="sampling along the walls (default 0.1 m)")
    ve.add_argument("--precision", choices=PRECISION_MODES, default="single",
                    help="single: each point needs one view within sigma_req; combined: its views add information")
    _add_limit_options(ve)
    ve.set_defaults(func=cmd_verify)
    ex = sub.add_parser("export", help="write the coverage problem for third-party solvers")
    _add_site_options(ex)
    ex.add_argument("--format", choices=FORMATS, default="json")
    ex.add_argument("--out", metavar="FILE", help="write to FILE (default: standard output)")
    ex.add_argument("--seed", type=int, default=0)
    ex.add_argument("--target-spacing", type=float, default=1.0, metavar="M")
    ex.add_argument("--grid-spacing", type=float, default=10.0, metavar="M")
    _add_memory_option(ex)
    _add_limit_options(ex)
    ex.set_defaults(func=cmd_export)
    nw = sub.add_parser("network", help="station network, least-squares accuracy and the accuracy check of a plan")
    _add_site_options(nw)
    nw.add_argument("plan", help="plan.json with stations [{id, zone, side, x, y}]")
    nw.add_argument("--out", metavar="DIR", help="write DIR/network.json")
    nw.add_argument("--seed", type=int, default=0)
    nw.add_argument("--precision", choices=PRECISION_MODES, default="single",
                    help="accuracy check by the best view (single) or all views combined")
    _add_network_options(nw)
    nw.add_argument("--observations", metavar="FILE", help="adjust real observations (JSON) instead of only the design")
    nw.add_argument("--registration", choices=("zone", "site"), default=None,
                    help="registration links per zone-side or across the site (default: site where zones are placed "
                         "or openings given)")
    nw.set_defaults(func=cmd_network)
    add_report_parser(sub)
    _add_assemble_parser(sub)
    i = sub.add_parser("instruments", help="list the instrument models in models/")
    i.set_defaults(func=cmd_instruments)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    args = build_parser().parse_args(argv)
    show = not getattr(args, "quiet", True) and sys.stderr.isatty()
    previous = progress.set_sink(progress.Bar(sys.stderr) if show else None)
    try:
        return int(args.func(args))
    except PlannerError as exc:
        print(f"planner: error: {exc.one_line()}", file=sys.stderr)
        return int(exc.exit_code)
    except KeyboardInterrupt:
        print("planner: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # a bug: one line, the traceback only on request
        if os.environ.get("PLANNER_DEBUG"):
            traceback.print_exc()
        first = str(exc).splitlines()[0] if str(exc) else ""
        print(f"planner: internal error: {type(exc).__name__}: {first} (set PLANNER_DEBUG=1 for the traceback)", file=sys.stderr)
        return int(ExitCode.INTERNAL)
    finally:
        progress.set_sink(previous)
