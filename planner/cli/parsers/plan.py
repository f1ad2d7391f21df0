"""``planner plan``: plan the stations of a site and verify the plan (its tuning keys, set by ``--set`` and
``--config``: :mod:`planner.cli.tuning`)."""

from __future__ import annotations

import argparse

from planner.cli.choices import METHODS, OBJECTIVES, PRECISION_MODES
from planner.cli.option_types import POSITIVE, POSITIVE_INT
from planner.cli.parsers.common import (
    Handlers,
    add_limit_options,
    add_memory_option,
    add_network_options,
    add_pool_options,
    add_site_options,
    add_surfaces_option,
)
from planner.cli.profile import add_profile_options
from planner.cli.tiles import add_tile_options
from planner.cli.tuning import TUNING


def add_parser(sub: argparse._SubParsersAction, handlers: Handlers) -> None:
    """Add ``plan`` to the subcommands ``sub``."""
    pl = sub.add_parser("plan", help="plan the stations of a site and verify the plan")
    tuning = TUNING["plan"]  # set by --set KEY=VALUE and --config FILE, not flags
    add_site_options(pl, tuning)
    pl.add_argument(
        "--method",
        choices=METHODS,
        default="milp",
        help="closed-form (the dissertation), greedy (Chvatal) or milp (optimal; default)",
    )
    pl.add_argument(
        "--time-limit",
        type=POSITIVE,
        default=None,
        metavar="S",
        help="a wall-clock cap on the MILP in s (default none: it stops on its work-limit, the same plan under any "
        "load; a capped plan says so)",
    )
    pl.add_argument("--k", type=POSITIVE_INT, default=1, help="each wall piece seen by at least k stations (default 1)")
    pl.add_argument(
        "--precision",
        choices=PRECISION_MODES,
        default="single",
        help="single: each view must meet sigma_req; combined: views add information (every method; default single)",
    )
    add_surfaces_option(pl)
    pl.add_argument(
        "--max-point-spacing",
        type=POSITIVE,
        default=None,
        metavar="M",
        help="the largest point spacing on the walls in m, e.g. 0.006: a view covers a piece only at a scan "
        "setting that gives it that (default none; docs/field-time.md)",
    )
    pl.add_argument(
        "--objective",
        choices=OBJECTIVES,
        default="stations",
        help="stations: the fewest stations (default); field-time: the least set-up + scan time, a scan setting "
        "chosen per station, compared with the plans at one setting",
    )
    pl.add_argument(
        "--no-overlap", action="store_true", help="MILP and greedy without the registration-overlap constraint"
    )
    pl.add_argument(
        "--registration",
        choices=("zone", "site"),
        default=None,
        help="one registration bundle per zone-side, or per accessible area of the site (default: site "
        "where the zones share one frame or openings are given; zone for one zone or zones in their own frames)",
    )
    pl.add_argument("--recentre", action="store_true", help="move each station to the centre of its tripod disc")
    add_memory_option(pl)
    pl.add_argument("--network", action="store_true", help="then build the station network and check its accuracy")
    add_network_options(pl, tuning)
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
    add_pool_options(pl, tuning)
    add_limit_options(pl, tuning)
    add_tile_options(pl)
    add_profile_options(pl, "plan")
    pl.set_defaults(func=handlers["plan"])
