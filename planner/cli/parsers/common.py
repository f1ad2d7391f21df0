"""What the subcommands' parsers share: the parser class (one-line usage errors) and the option groups."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Collection, Mapping

from planner.cli.choices import INCIDENCE_MODELS
from planner.cli.option_types import POSITIVE, surface_list
from planner.cli.tuning import add_option
from planner.core.errors import ExitCode

#: each subcommand's function, by name
Handlers = Mapping[str, Callable[[argparse.Namespace], int]]


class Parser(argparse.ArgumentParser):
    """argparse that exits with our usage code and a one-line message."""

    def error(self, message: str) -> None:  # type: ignore[override]
        print(f"{self.prog}: usage error: {message} (see {self.prog} --help)", file=sys.stderr)
        raise SystemExit(ExitCode.USAGE)


def add_site_options(p: argparse.ArgumentParser, tuning: Collection[str] = ()) -> None:
    """The site and its parameter overrides; the input-format knobs among ``tuning`` (the command's tuning keys)
    are keys, not flags."""
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
    add_option(p, "angular-tolerance", tuning)
    add_option(p, "min-relative-precision", tuning)
    p.add_argument(
        "--crs",
        metavar="CRS",
        help="metric CRS (e.g. EPSG:32636) of a lon/lat GeoJSON site; exports go back to lon/lat",
    )
    add_option(p, "layer-height", tuning)
    add_option(p, "dxf-side", tuning)
    p.add_argument(
        "--storey",
        metavar="NAME|INDEX|all",
        help="IFC: the building storey to read (default: every storey that holds spaces)",
    )
    add_option(p, "exterior", tuning)
    add_option(p, "ifc-windows", tuning)
    p.add_argument("--quiet", action="store_true", help="no progress bars")


def add_network_options(p: argparse.ArgumentParser, tuning: Collection[str] = ()) -> None:
    """Control points and the network check's knobs (those among ``tuning`` as keys)."""
    p.add_argument("--control", metavar="FILE", help="control points (JSON list: name, x, y, sigma_x_mm, sigma_y_mm)")
    for key in ("monte-carlo", "traverse", "ts-everywhere"):
        add_option(p, key, tuning)


def add_limit_options(p: argparse.ArgumentParser, tuning: Collection[str] = ()) -> None:
    """The incidence angle and the precision requirement (those among ``tuning`` as keys)."""
    add_option(p, "incidence", tuning)
    add_option(p, "no-precision", tuning)


def add_pool_options(p: argparse.ArgumentParser, tuning: Collection[str] = ()) -> None:
    """The options that fix the coverage problem: pieces, candidate grid, sampling seed (plan and export; the
    seed among ``tuning`` as a key)."""
    add_option(p, "seed", tuning)
    p.add_argument("--target-spacing", type=POSITIVE, default=1.0, metavar="M", help="wall piece length (default 1 m)")
    p.add_argument(
        "--grid-spacing",
        type=POSITIVE,
        default=None,
        metavar="M",
        help="candidate grid spacing (default 10 m; 4 m where the automatic strategy (--tiles auto) plans "
        "the site by tiles and it has at most 10,000 wall pieces: docs/large-sites.md)",
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


def add_surfaces_option(p: argparse.ArgumentParser, what: str = "planned") -> None:
    """``--surfaces LIST``: walls and, besides them, floors and ceilings (issue 46)."""
    p.add_argument(
        "--surfaces",
        type=surface_list,
        default="walls",
        metavar="LIST",
        help=f"the surfaces {what}: walls and, besides them, floors and ceilings, e.g. walls,floors,ceilings "
        "(default walls; docs/surfaces.md)",
    )
