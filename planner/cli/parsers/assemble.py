"""``planner assemble``: place table zones in one site frame from their shared walls."""

from __future__ import annotations

import argparse

from planner.cli.option_types import NON_NEGATIVE, POSITIVE
from planner.cli.parsers.common import (
    Handlers,
)


def add_parser(sub: argparse._SubParsersAction, handlers: Handlers) -> None:
    """Add ``assemble`` to the subcommands ``sub``."""
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
