"""``planner export``: write the coverage problem for third-party solvers."""

from __future__ import annotations

import argparse

from planner.cli.choices import FORMATS
from planner.cli.parsers.common import (
    Handlers,
    add_limit_options,
    add_memory_option,
    add_pool_options,
    add_site_options,
)


def add_parser(sub: argparse._SubParsersAction, handlers: Handlers) -> None:
    """Add ``export`` to the subcommands ``sub``."""
    ex = sub.add_parser("export", help="write the coverage problem for third-party solvers")
    add_site_options(ex)
    ex.add_argument(
        "--format",
        choices=FORMATS,
        default="json",
        help="json (both sparse views), orlib (OR-Library set cover) or mps (the MILP) (default json)",
    )
    ex.add_argument("--out", metavar="FILE", help="write to FILE (default: standard output)")
    add_pool_options(ex)
    add_memory_option(ex)
    add_limit_options(ex)
    ex.set_defaults(func=handlers["export"])
