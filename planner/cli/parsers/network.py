"""``planner network``: the station network, its least-squares accuracy and the accuracy check of a plan."""

from __future__ import annotations

import argparse

from planner.cli.choices import PRECISION_MODES
from planner.cli.option_types import NON_NEGATIVE_INT
from planner.cli.parsers.common import (
    Handlers,
    add_network_options,
    add_site_options,
)


def add_parser(sub: argparse._SubParsersAction, handlers: Handlers) -> None:
    """Add ``network`` to the subcommands ``sub``."""
    nw = sub.add_parser("network", help="station network, least-squares accuracy and the accuracy check of a plan")
    add_site_options(nw)
    nw.add_argument("plan", help="plan.json with stations [{id, zone, side, x, y}]")
    nw.add_argument("--out", metavar="DIR", help="write DIR/network.json")
    nw.add_argument("--seed", type=NON_NEGATIVE_INT, default=0, help="seed of the Monte Carlo runs (default 0)")
    nw.add_argument(
        "--precision",
        choices=PRECISION_MODES,
        default="single",
        help="accuracy check by the best view (single) or all views combined (default single)",
    )
    add_network_options(nw)
    nw.add_argument("--observations", metavar="FILE", help="adjust real observations (JSON) instead of only the design")
    nw.add_argument(
        "--registration",
        choices=("zone", "site"),
        default=None,
        help="registration links per zone-side or across the site (default: site where the zones share one "
        "frame or openings are given; zone for one zone or zones in their own frames)",
    )
    nw.set_defaults(func=handlers["network"])
