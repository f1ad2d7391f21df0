"""``planner verify``: re-verify any plan's coverage on a fine sampling of every wall."""

from __future__ import annotations

import argparse

from planner.cli.choices import PRECISION_MODES
from planner.cli.option_types import POSITIVE, SAMPLING_M
from planner.cli.parsers.common import (
    Handlers,
    add_limit_options,
    add_site_options,
    add_surfaces_option,
)
from planner.cli.tuning import add_option


def add_parser(sub: argparse._SubParsersAction, handlers: Handlers) -> None:
    """Add ``verify`` to the subcommands ``sub``."""
    ve = sub.add_parser("verify", help="re-verify any plan's coverage on a fine sampling of every wall")
    add_site_options(ve)
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
    add_surfaces_option(ve, "verified")
    ve.add_argument(
        "--max-point-spacing",
        type=POSITIVE,
        default=None,
        metavar="M",
        help="also check that every wall point gets at most M m point spacing from a station that sees it, at "
        "the station's setting in the plan (its 'setting'; else the instrument's default) (docs/field-time.md)",
    )
    add_option(ve, "theta-max-floor")
    add_limit_options(ve)
    ve.set_defaults(func=handlers["verify"])
