"""``planner chain``: the registration-chain accuracy of a plan (links, ties to control; seed 003)."""

from __future__ import annotations

import argparse

from planner.cli.parsers.common import (
    Handlers,
    add_site_options,
)


def add_parser(sub: argparse._SubParsersAction, handlers: Handlers) -> None:
    """Add ``chain`` to the subcommands ``sub``."""
    c = sub.add_parser("chain", help="registration-chain accuracy of a plan (links, ties to control; seed 003)")
    add_site_options(c)
    c.add_argument("plan", help="plan.json with stations [{id, zone, side, x, y}]")
    c.add_argument(
        "--registration",
        choices=("zone", "site"),
        default=None,
        help="registration groups (default: site where the zones share one frame or openings are given; zone for "
        "one zone or zones in their own frames)",
    )
    c.set_defaults(func=handlers["chain"])
