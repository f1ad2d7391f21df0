"""``planner validate``: read a site and report zones, closures, corrections and limits."""

from __future__ import annotations

import argparse

from planner.cli.parsers.common import (
    Handlers,
    add_site_options,
)


def add_parser(sub: argparse._SubParsersAction, handlers: Handlers) -> None:
    """Add ``validate`` to the subcommands ``sub``."""
    v = sub.add_parser("validate", help="read a site and report zones, closures, corrections and limits")
    add_site_options(v)
    v.add_argument("--json", action="store_true", help="print the report as JSON")
    v.set_defaults(func=handlers["validate"])
