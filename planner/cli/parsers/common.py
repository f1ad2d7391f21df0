"""What the subcommands' parsers share: the parser class (one-line usage errors) and the option groups."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Mapping

from planner.cli.choices import INCIDENCE_MODELS, SIDES
from planner.cli.option_types import NON_NEGATIVE_INT, POSITIVE, OncePerKey
from planner.errors import ExitCode

#: each subcommand's function, by name
Handlers = Mapping[str, Callable[[argparse.Namespace], int]]


class Parser(argparse.ArgumentParser):
    """argparse that exits with our usage code and a one-line message."""

    def error(self, message: str) -> None:  # type: ignore[override]
        print(f"{self.prog}: usage error: {message} (see {self.prog} --help)", file=sys.stderr)
        raise SystemExit(ExitCode.USAGE)


def add_site_options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "site",
        help="site file: JSON instance (.json), table CSV (.csv), DXF (.dxf), GeoJSON (.geojson), "
        "AGPLIB polygon (.pol) or IFC model (.ifc)",
    )
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


def add_network_options(p: argparse.ArgumentParser) -> None:
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


def add_limit_options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--incidence",
        choices=("horizontal", "3d"),
        default="horizontal",
        help="incidence angle in plan (as the dissertation) or 3-D to the top of the wall (default horizontal)",
    )
    p.add_argument("--no-precision", action="store_true", help="do not require the predicted point error <= sigma_req")


def add_pool_options(p: argparse.ArgumentParser) -> None:
    """The options that fix the coverage problem: pieces, candidate grid, sampling seed (plan and export)."""
    p.add_argument("--seed", type=NON_NEGATIVE_INT, default=0, help="seed of the movement-field sampling (default 0)")
    p.add_argument("--target-spacing", type=POSITIVE, default=1.0, metavar="M", help="wall piece length (default 1 m)")
    p.add_argument(
        "--grid-spacing", type=POSITIVE, default=10.0, metavar="M", help="candidate grid spacing (default 10 m)"
    )


def add_memory_option(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--memory-limit",
        metavar="SIZE",
        help="refuse a problem whose estimated memory passes SIZE, e.g. 4G (default: half the available memory)",
    )


def theta(text: str) -> float | str:
    """--theta-max: degrees, or 'derive'."""
    if text.strip().lower() == "derive":
        return "derive"
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected degrees or 'derive', got {text!r}") from None
