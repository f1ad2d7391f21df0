"""The ``planner`` command line's parser: subcommands, options, defaults and help texts.

The commands themselves are in :mod:`planner.cli`, which hands them in as ``handlers``; bad options
exit with the usage code (2) and a one-line message.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Mapping

from planner import __version__
from planner.cli.choices import BACKENDS, CONNECTIVITY, FORMATS, INCIDENCE_MODELS, METHODS, PRECISION_MODES, SIDES
from planner.cli.field import add_field_options, add_field_parser
from planner.cli.option_types import NON_NEGATIVE, NON_NEGATIVE_INT, POSITIVE, POSITIVE_INT, SAMPLING_M, OncePerKey
from planner.cli.profile import add_profile_options, hide_tuning
from planner.cli.report import add_report_parser
from planner.cli.tiles import add_tile_options
from planner.errors import ExitCode

Handlers = Mapping[str, Callable[[argparse.Namespace], int]]


class _Parser(argparse.ArgumentParser):
    """argparse that exits with our usage code and a one-line message."""

    def error(self, message: str) -> None:  # type: ignore[override]
        print(f"{self.prog}: usage error: {message} (see {self.prog} --help)", file=sys.stderr)
        raise SystemExit(ExitCode.USAGE)


def _add_site_options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "site",
        help="site file: JSON instance (.json), table CSV (.csv), DXF (.dxf), GeoJSON (.geojson), "
        "AGPLIB polygon (.pol) or IFC model (.ifc)",
    )
    p.add_argument("--instrument", help="instrument name from models/ (overrides the instance)")
    p.add_argument("--max-range", type=float, metavar="M", help="slant range S_max in m (overrides derivation)")
    p.add_argument(
        "--theta-max",
        type=_theta,
        metavar="DEG|derive",
        help="largest incidence angle in degrees, or 'derive' (from sigma_req and the incidence model)",
    )
    p.add_argument(
        "--incidence-model",
        choices=INCIDENCE_MODELS,
        help="how a view's error grows with incidence: none (range only), table (2.3), soudarissanane",
    )
    p.add_argument(
        "--standoff",
        type=float,
        metavar="M",
        help="no station or control point closer to a wall/obstacle (default: the site's, else 0.4 m)",
    )
    p.add_argument("--overlap", type=float, metavar="FRACTION", help="registration overlap, e.g. 0.3")
    acc = p.add_mutually_exclusive_group()
    acc.add_argument("--sigma-req", type=float, metavar="M", help="required accuracy in m")
    acc.add_argument("--scale", metavar="1:N", help="drawing scale; accuracy from table 1.1")
    p.add_argument("--instrument-height", type=float, metavar="M", help="instrument height IH in m")
    p.add_argument("--angular-tolerance", type=float, metavar="DEG", help="closure tolerance of table CSV zones")
    p.add_argument("--min-relative-precision", type=float, metavar="N", help="closure 1:N of table CSV zones")
    p.add_argument(
        "--crs",
        metavar="CRS",
        help="metric CRS (e.g. EPSG:32636) of a lon/lat GeoJSON site; exports go back to lon/lat",
    )
    p.add_argument(
        "--layer-height",
        action=OncePerKey,
        default=[],
        metavar="LAYER=M",
        help="DXF: wall height of polylines on LAYER that carry none (repeatable, once per layer)",
    )
    p.add_argument(
        "--dxf-side",
        choices=SIDES,
        default="inside",
        help="DXF: scan side of zones whose layer and XDATA do not say (default inside)",
    )
    p.add_argument(
        "--storey",
        metavar="NAME|INDEX|all",
        help="IFC: the building storey to read (default: every storey that holds spaces)",
    )
    p.add_argument("--exterior", action="store_true", help="IFC: also scan the storey's outer outline from outside")
    p.add_argument(
        "--ifc-windows",
        action="store_true",
        help="IFC: record windows as openings too (default: a window is wall surface)",
    )
    p.add_argument("--quiet", action="store_true", help="no progress bars")


def _add_network_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--control", metavar="FILE", help="control points (JSON list: name, x, y, sigma_x_mm, sigma_y_mm)")
    p.add_argument(
        "--monte-carlo",
        type=NON_NEGATIVE_INT,
        default=0,
        metavar="N",
        help="also simulate N adjustments (seeded; N >= 100)",
    )
    p.add_argument(
        "--traverse",
        metavar="FILE",
        help="the planned control traverse (JSON: points, legs), the only "
        "total-station observations; 'none' for no traverse (default: a proposed one, labelled so)",
    )
    p.add_argument(
        "--ts-everywhere",
        action="store_true",
        help="the earlier design: a total station on every station sight line (no traverse)",
    )


def _add_limit_options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--incidence",
        choices=("horizontal", "3d"),
        default="horizontal",
        help="incidence angle in plan (as the dissertation) or 3-D to the top of the wall (default horizontal)",
    )
    p.add_argument("--no-precision", action="store_true", help="do not require the predicted point error <= sigma_req")


def _add_pool_options(p: argparse.ArgumentParser) -> None:
    """The options that fix the coverage problem: pieces, candidate grid, sampling seed (plan and export)."""
    p.add_argument("--seed", type=NON_NEGATIVE_INT, default=0, help="seed of the movement-field sampling (default 0)")
    p.add_argument("--target-spacing", type=POSITIVE, default=1.0, metavar="M", help="wall piece length (default 1 m)")
    p.add_argument(
        "--grid-spacing", type=POSITIVE, default=10.0, metavar="M", help="candidate grid spacing (default 10 m)"
    )


def _add_memory_option(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--memory-limit",
        metavar="SIZE",
        help="refuse a problem whose estimated memory passes SIZE, e.g. 4G (default: half the available memory)",
    )


def _theta(text: str) -> float | str:
    """--theta-max: degrees, or 'derive'."""
    if text.strip().lower() == "derive":
        return "derive"
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected degrees or 'derive', got {text!r}") from None


def _add_assemble_parser(sub: argparse._SubParsersAction, handlers: Handlers) -> None:
    c = sub.add_parser("chain", help="registration-chain accuracy of a plan (links, ties to control; seed 003)")
    _add_site_options(c)
    c.add_argument("plan", help="plan.json with stations [{id, zone, side, x, y}]")
    c.add_argument(
        "--registration",
        choices=("zone", "site"),
        default=None,
        help="registration groups (default: site where zones are placed or openings given)",
    )
    c.set_defaults(func=handlers["chain"])
    a = sub.add_parser("assemble", help="place table zones in one site frame from their shared walls")
    a.add_argument("site", help="JSON instance (.json) or table CSV (.csv)")
    a.add_argument(
        "--tolerance", type=POSITIVE, default=0.005, metavar="M", help="equal side lengths within M m (default 0.005)"
    )
    a.add_argument(
        "--wall-thickness", type=NON_NEGATIVE, default=0.0, metavar="M", help="offset between the two faces (default 0)"
    )
    a.add_argument("--anchor", metavar="ZONE", help="zone whose frame becomes the site frame (default: the outline)")
    a.add_argument("--out", metavar="FILE", help="write the instance with its placements to FILE")
    a.set_defaults(func=handlers["assemble"])


def build_parser(handlers: Handlers) -> argparse.ArgumentParser:
    """The ``planner`` parser; ``handlers`` maps each subcommand (but ``report``) to its function."""
    parser = _Parser(prog="planner", description="Plan terrestrial laser scanner stations.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    v = sub.add_parser("validate", help="read a site and report zones, closures, corrections and limits")
    _add_site_options(v)
    v.add_argument("--json", action="store_true", help="print the report as JSON")
    v.set_defaults(func=handlers["validate"])
    pl = sub.add_parser("plan", help="plan the stations of a site and verify the plan")
    _add_site_options(pl)
    pl.add_argument(
        "--method",
        choices=METHODS,
        default="milp",
        help="closed-form (the dissertation), greedy (Chvatal) or milp (optimal; default)",
    )
    pl.add_argument("--backend", choices=BACKENDS, default="cpsat", help="MILP backend (default cpsat)")
    pl.add_argument("--time-limit", type=POSITIVE, default=60.0, metavar="S", help="MILP time limit in s (default 60)")
    pl.add_argument(
        "--work-limit",
        type=POSITIVE,
        default=None,
        metavar="S",
        help="cpsat, 1 thread: stop on S deterministic seconds of CP-SAT work (same plan under any load); "
        "--time-limit stays a wall-clock cap",
    )
    pl.add_argument(
        "--local-search-moves",
        type=NON_NEGATIVE_INT,
        default=500,
        metavar="N",
        help="milp: swaps of the local search for a connected plan one station smaller, tried once per "
        "incumbent size down to the bound (default 500; 0: off)",
    )
    pl.add_argument("--threads", type=POSITIVE_INT, default=1, help="solver threads (default 1: deterministic)")
    pl.add_argument("--k", type=POSITIVE_INT, default=1, help="each wall piece seen by at least k stations (default 1)")
    pl.add_argument(
        "--precision",
        choices=PRECISION_MODES,
        default="single",
        help="single: each view must meet sigma_req; combined: views add information (every method; default single)",
    )
    pl.add_argument(
        "--no-overlap", action="store_true", help="MILP and greedy without the registration-overlap constraint"
    )
    pl.add_argument(
        "--connectivity",
        choices=CONNECTIVITY,
        default="auto",
        help="milp: registration connectivity by branch-and-cut (bc, pyscipopt backend), a flow model or "
        "the cut loop (auto: bc on pyscipopt, loop elsewhere)",
    )
    pl.add_argument("--layer-cuts", action="store_true", help="milp: add distance-layer cuts before the first solve")
    pl.add_argument("--tree-bound", action="store_true", help="milp: add the tree (Hunter) covering bound rows")
    pl.add_argument(
        "--no-ring-bound",
        action="store_true",
        help="milp: no ring bound (the cheapest walk over the arcs a zone-side's stations see, exact when "
        "each sees one run of its wall)",
    )
    pl.add_argument(
        "--ring-lagrange-steps",
        type=NON_NEGATIVE_INT,
        default=500,
        metavar="N",
        help="milp: steps of the Lagrangian ascent that adds the cover rows to the ring bound (default 500; "
        "0: the ring bound alone)",
    )
    pl.add_argument(
        "--min-shared", type=NON_NEGATIVE, default=0.0, metavar="M", help="registration: shared wall at least M m"
    )
    pl.add_argument(
        "--max-link", type=POSITIVE, default=None, metavar="M", help="registration: stations at most M m apart"
    )
    pl.add_argument(
        "--registration",
        choices=("zone", "site"),
        default=None,
        help="one registration bundle per zone-side, or per accessible area of the site (default: site "
        "where zones are placed or openings given)",
    )
    pl.add_argument("--tripod", action="store_true", help="compute tripod discs (always on for milp)")
    pl.add_argument("--recentre", action="store_true", help="move each station to the centre of its tripod disc")
    pl.add_argument(
        "--no-regions",
        action="store_true",
        help="no whole-zone-side candidates from the coverage regions (the pool as before issue 12)",
    )
    pl.add_argument(
        "--no-pricing",
        action="store_true",
        help="milp: no geometric pricing, so the bound holds over the candidate pool only",
    )
    pl.add_argument(
        "--pricing-time-limit",
        type=NON_NEGATIVE,
        default=120.0,
        metavar="S",
        help="milp: time for geometric pricing (default 120 s); past it the bound scope stays 'pool'",
    )
    _add_memory_option(pl)
    pl.add_argument("--network", action="store_true", help="then build the station network and check its accuracy")
    _add_network_options(pl)
    pl.add_argument("--out", metavar="DIR", help="write DIR/plan.json")
    pl.add_argument(
        "--export",
        metavar="LIST",
        help="also write into --out: dxf (plan.dxf), geojson (plan.geojson), csv (stations.csv), comma-separated",
    )
    pl.add_argument("--report", metavar="DIR", help="write DIR/report.html (figures embedded; runs the network check)")
    pl.add_argument(
        "--field",
        metavar="DIR",
        help="write the field sheet into DIR (field.html/.csv/.geojson/.json: "
        "visiting order, walking route, field time, targets; see planner field)",
    )
    add_field_options(pl, "field-")
    _add_pool_options(pl)
    pl.add_argument(
        "--verify-spacing", type=SAMPLING_M, default=0.1, metavar="M", help="verification sampling (default 0.1 m)"
    )
    _add_limit_options(pl)
    add_tile_options(pl)
    add_profile_options(pl)
    hide_tuning(pl, "plan")
    pl.set_defaults(func=handlers["plan"])
    ve = sub.add_parser("verify", help="re-verify any plan's coverage on a fine sampling of every wall")
    _add_site_options(ve)
    ve.add_argument("plan", help="plan.json with stations [{id, zone, side, x, y}] in the zones' frames")
    ve.add_argument(
        "--spacing", type=SAMPLING_M, default=0.1, metavar="M", help="sampling along the walls (default 0.1 m)"
    )
    ve.add_argument(
        "--precision",
        choices=PRECISION_MODES,
        default="single",
        help="single: each point needs one view within sigma_req; combined: its views add information (default single)",
    )
    _add_limit_options(ve)
    ve.set_defaults(func=handlers["verify"])
    ex = sub.add_parser("export", help="write the coverage problem for third-party solvers")
    _add_site_options(ex)
    ex.add_argument(
        "--format",
        choices=FORMATS,
        default="json",
        help="json (both sparse views), orlib (OR-Library set cover) or mps (the MILP) (default json)",
    )
    ex.add_argument("--out", metavar="FILE", help="write to FILE (default: standard output)")
    _add_pool_options(ex)
    _add_memory_option(ex)
    _add_limit_options(ex)
    ex.set_defaults(func=handlers["export"])
    nw = sub.add_parser("network", help="station network, least-squares accuracy and the accuracy check of a plan")
    _add_site_options(nw)
    nw.add_argument("plan", help="plan.json with stations [{id, zone, side, x, y}]")
    nw.add_argument("--out", metavar="DIR", help="write DIR/network.json")
    nw.add_argument("--seed", type=NON_NEGATIVE_INT, default=0, help="seed of the Monte Carlo runs (default 0)")
    nw.add_argument(
        "--precision",
        choices=PRECISION_MODES,
        default="single",
        help="accuracy check by the best view (single) or all views combined (default single)",
    )
    _add_network_options(nw)
    nw.add_argument("--observations", metavar="FILE", help="adjust real observations (JSON) instead of only the design")
    nw.add_argument(
        "--registration",
        choices=("zone", "site"),
        default=None,
        help="registration links per zone-side or across the site (default: site where zones are placed "
        "or openings given)",
    )
    nw.set_defaults(func=handlers["network"])
    add_report_parser(sub)
    add_field_parser(sub)
    _add_assemble_parser(sub, handlers)
    i = sub.add_parser("instruments", help="list the instrument models in models/")
    i.set_defaults(func=handlers["instruments"])
    return parser
