"""``planner instruments``: list the instrument models."""

from __future__ import annotations

import argparse

from planner.cli.parsers.common import (
    Handlers,
)


def add_parser(sub: argparse._SubParsersAction, handlers: Handlers) -> None:
    """Add ``instruments`` to the subcommands ``sub``."""
    i = sub.add_parser("instruments", help="list the instrument models in models/")
    i.set_defaults(func=handlers["instruments"])
