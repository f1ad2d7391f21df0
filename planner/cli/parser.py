"""The ``planner`` command line's parser: the subcommands in the order ``--help`` lists them, each from its own
module (:mod:`planner.cli.parsers`).

The commands themselves are in :mod:`planner.cli.commands`, which hands them in as ``handlers``; bad options
exit with the usage code (2) and a one-line message.
"""

from __future__ import annotations

import argparse

from planner import __version__
from planner.cli.field import add_field_parser
from planner.cli.parsers import assemble, chain, export, instruments, network, plan, validate, verify
from planner.cli.parsers.common import Handlers, Parser
from planner.cli.report import add_report_parser

__all__ = ["Handlers", "build_parser"]


def build_parser(handlers: Handlers) -> argparse.ArgumentParser:
    """The ``planner`` parser; ``handlers`` maps each subcommand (but ``report`` and ``field``) to its function."""
    parser = Parser(prog="planner", description="Plan terrestrial laser scanner stations.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    for module in (validate, plan, verify, export, network):
        module.add_parser(sub, handlers)
    add_report_parser(sub)
    add_field_parser(sub)
    for module in (chain, assemble, instruments):
        module.add_parser(sub, handlers)
    return parser
