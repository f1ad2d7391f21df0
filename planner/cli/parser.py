"""The ``planner`` command line's parser: the subcommands in the order ``--help`` lists them.

The settings they share come from :mod:`planner.core.settings` through :mod:`planner.cli.tuning` (one
definition each: type, default, help); the site and its parameter overrides, and the plan file, through
:func:`add_site`. The commands themselves are in :mod:`planner.cli.commands`, which hands them in as
``handlers``; bad options exit with the usage code (2) and a one-line message.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Mapping

from planner import __version__
from planner.cli.field import add_field_parser
from planner.cli.profile import add_profile_options
from planner.cli.replan_command import add_replan_parser
from planner.cli.report import add_report_parser
from planner.cli.tuning import TUNING, add_plan_settings, add_setting, add_settings
from planner.core.errors import ExitCode
from planner.core.settings import FORMATS, INCIDENCE_MODELS, SETTINGS

__all__ = ["Handlers", "build_parser"]

#: each subcommand's function, by name
Handlers = Mapping[str, Callable[[argparse.Namespace], int]]

_PLAN_FILE = "plan.json with stations [{id, zone, side, x, y}] in the zones' frames"
_INPUT_KEYS = ("angular-tolerance", "min-relative-precision", "layer-height", "dxf-side", "exterior", "ifc-windows")


class Parser(argparse.ArgumentParser):
    """argparse that exits with our usage code and a one-line message."""

    def error(self, message: str) -> None:  # type: ignore[override]
        print(f"{self.prog}: usage error: {message} (see {self.prog} --help)", file=sys.stderr)
        raise SystemExit(ExitCode.USAGE)


#: the registration flag of the commands that read a plan: its default is the plan's own
PLAN_REGISTRATION = (
    "one registration bundle per zone-side, or per accessible area of the site (default: the plan's, as plan.json "
    "records it)"
)


def theta(text: str) -> float | str:
    """--theta-max: degrees, or 'derive'."""
    if text.strip().lower() == "derive":
        return "derive"
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected degrees or 'derive', got {text!r}") from None


def add_site(sub: argparse._SubParsersAction, name: str, help: str, *, plan_file: bool = False) -> Parser:
    """The subcommand ``name`` with the site, its parameter overrides and input formats (the command's tuning
    keys among them as keys), the plan file where it reads one, and every setting at its default."""
    p: Parser = sub.add_parser(name, help=help)
    p.set_defaults(**{s.dest: s.initial for s in SETTINGS.values()})
    tuning = TUNING.get(name, ())
    p.add_argument(
        "site",
        help="site file: JSON instance (.json), table CSV (.csv), DXF (.dxf), GeoJSON (.geojson), "
        "AGPLIB polygon (.pol) or IFC model (.ifc)",
    )
    if plan_file:
        p.add_argument("plan", help=_PLAN_FILE)
    p.add_argument("--instrument", help="instrument name from models/ (overrides the instance)")
    p.add_argument("--max-range", type=float, metavar="M", help="slant range S_max in m (overrides derivation)")
    p.add_argument(
        "--theta-max",
        type=theta,
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
    p.add_argument(
        "--crs",
        metavar="CRS",
        help="metric CRS (e.g. EPSG:32636) of a lon/lat GeoJSON site; exports go back to lon/lat",
    )
    p.add_argument(
        "--storey",
        metavar="NAME|INDEX|all",
        help="IFC: the building storey to read (default: every storey that holds spaces)",
    )
    add_settings(p, *(k for k in _INPUT_KEYS if name != "plan" or SETTINGS[k].plan), tuning=tuning)
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    return p


def _add_plan(sub: argparse._SubParsersAction) -> Parser:
    pl = add_site(sub, "plan", "plan the stations of a site and verify the plan")
    add_plan_settings(pl)
    pl.add_argument("--network", action="store_true", help="then build the station network and check its accuracy")
    pl.add_argument("--control", metavar="FILE", help="control points (JSON list: name, x, y, sigma_x_mm, sigma_y_mm)")
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
        help="write the field sheet into DIR (field.html/.csv/.geojson/.json: visiting order, walking route, "
        "field time, targets; see planner field)",
    )
    add_profile_options(pl, "plan")
    return pl


def build_parser(handlers: Handlers) -> argparse.ArgumentParser:
    """The ``planner`` parser; ``handlers`` maps each subcommand (but ``report`` and ``field``) to its function."""
    parser = Parser(prog="planner", description="Plan terrestrial laser scanner stations.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    add_site(sub, "validate", "read a site and report zones, closures, corrections and limits").add_argument(
        "--json", action="store_true", help="print the report as JSON"
    )
    _add_plan(sub)
    ve = add_site(sub, "verify", "re-verify any plan's coverage on a fine sampling of every wall", plan_file=True)
    add_setting(ve, "verify-spacing", name="spacing")
    add_settings(ve, "precision", "surfaces")
    add_setting(
        ve,
        "max-point-spacing",
        help="also check that every wall point gets at most M m point spacing from a station that sees it, at "
        "the station's setting in the plan (else the instrument's default) (docs/field-time.md)",
    )
    add_settings(ve, "theta-max-floor", "incidence", "no-precision")
    ex = add_site(sub, "export", "write the coverage problem for third-party solvers")
    ex.add_argument(
        "--format",
        choices=FORMATS,
        default="json",
        help="json (both sparse views), orlib (OR-Library set cover) or mps (the MILP) (default json)",
    )
    ex.add_argument("--out", metavar="FILE", help="write to FILE (default: standard output)")
    add_settings(ex, "seed", "target-spacing", "grid-spacing", "memory-limit", "incidence", "no-precision")
    nw = add_site(
        sub, "network", "station network, least-squares accuracy and the accuracy check of a plan", plan_file=True
    )
    nw.add_argument("--out", metavar="DIR", help="write DIR/network.json")
    add_settings(nw, "seed", "precision")
    nw.add_argument("--control", metavar="FILE", help="control points (JSON list: name, x, y, sigma_x_mm, sigma_y_mm)")
    add_settings(nw, "monte-carlo", "traverse", "ts-everywhere")
    nw.add_argument("--observations", metavar="FILE", help="adjust real observations (JSON) instead of only the design")
    add_setting(nw, "registration", help=PLAN_REGISTRATION)
    add_report_parser(sub)
    add_field_parser(sub)
    add_replan_parser(sub)
    ch = add_site(sub, "chain", "registration-chain accuracy of a plan (links, ties to control)", plan_file=True)
    add_setting(ch, "registration", help=PLAN_REGISTRATION)
    a = sub.add_parser("assemble", help="place table zones in one site frame from their shared walls")
    a.add_argument("site", help="JSON instance (.json) or table CSV (.csv)")
    add_settings(a, "tolerance", "wall-thickness")
    a.add_argument("--anchor", metavar="ZONE", help="zone whose frame becomes the site frame (default: the outline)")
    a.add_argument("--out", metavar="FILE", help="write the instance with its placements to FILE")
    sub.add_parser("instruments", help="list the instrument models in models/")
    for name, p in sub.choices.items():
        if name in handlers:
            p.set_defaults(func=handlers[name])
    return parser
