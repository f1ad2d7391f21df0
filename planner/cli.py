"""The ``planner`` command: one function per subcommand; parses, calls the library, prints.

Exit codes: 0 ok, 1 internal error, 2 usage, 3 invalid input, 4 infeasible
problem (see :mod:`planner.errors`). Errors print as one line on stderr; set
PLANNER_DEBUG=1 to see the traceback of an internal error.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import traceback
from collections.abc import Sequence
from dataclasses import replace

from planner.errors import ExitCode, PlannerError
from planner.instruments import list_instruments, load_instrument
from planner.params import ClosureTolerance
from planner.site import Site, load_site
from planner.validate import validate_site


class _Parser(argparse.ArgumentParser):
    """argparse that exits with our usage code and a one-line message."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        print(f"{self.prog}: usage error: {message}", file=sys.stderr)
        raise SystemExit(ExitCode.USAGE)


def _add_site_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("site", help="site file: JSON instance or table CSV")
    p.add_argument("--instrument", help="instrument name from models/ (overrides the instance)")
    p.add_argument("--max-range", type=float, metavar="M", help="slant range S_max in m (overrides derivation)")
    p.add_argument("--theta-max", type=float, metavar="DEG", help="largest incidence angle, degrees")
    p.add_argument("--overlap", type=float, metavar="FRACTION", help="registration overlap, e.g. 0.3")
    acc = p.add_mutually_exclusive_group()
    acc.add_argument("--sigma-req", type=float, metavar="M", help="required accuracy in m")
    acc.add_argument("--scale", metavar="1:N", help="drawing scale; accuracy from table 1.1")
    p.add_argument("--instrument-height", type=float, metavar="M", help="instrument height IH in m")
    p.add_argument("--angular-tolerance", type=float, metavar="DEG", help="closure tolerance of table CSV zones")
    p.add_argument("--min-relative-precision", type=float, metavar="N", help="closure 1:N of table CSV zones")


def load_with_overrides(args: argparse.Namespace) -> Site:
    """Load the site and apply the command-line parameter overrides."""
    tol_kw = {}
    if args.angular_tolerance is not None:
        tol_kw["angular_deg"] = args.angular_tolerance
    if args.min_relative_precision is not None:
        tol_kw["min_relative_precision"] = args.min_relative_precision
    site = load_site(args.site, ClosureTolerance(**tol_kw) if tol_kw else None)
    p = site.parameters
    changes = {k: v for k, v in {
        "max_slant_range_m": args.max_range, "theta_max_deg": args.theta_max, "overlap": args.overlap,
        "sigma_req_m": args.sigma_req, "instrument_height_m": args.instrument_height,
    }.items() if v is not None}
    if args.sigma_req is not None:
        changes["drawing_scale"] = None
    p = replace(p, **changes)
    if args.scale is not None:
        p = p.with_scale(args.scale)
    return replace(site, parameters=p, instrument=args.instrument or site.instrument)


def cmd_validate(args: argparse.Namespace) -> int:
    report = validate_site(load_with_overrides(args))
    print(json.dumps(report.to_dict(), indent=2) if args.json else report.summary())
    return ExitCode.OK


def cmd_instruments(args: argparse.Namespace) -> int:
    for name in list_instruments():
        inst = load_instrument(name)
        print(f"{name:<22}{type(inst).__name__:<14}{inst.description}")
    return ExitCode.OK


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="planner", description="Plan terrestrial laser scanner stations.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    v = sub.add_parser("validate", help="read a site and report zones, closures, corrections and limits")
    _add_site_options(v)
    v.add_argument("--json", action="store_true", help="print the report as JSON")
    v.set_defaults(func=cmd_validate)
    i = sub.add_parser("instruments", help="list the instrument models in models/")
    i.set_defaults(func=cmd_instruments)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    args = build_parser().parse_args(argv)
    try:
        return int(args.func(args))
    except PlannerError as exc:
        print(f"planner: error: {exc.one_line()}", file=sys.stderr)
        return int(exc.exit_code)
    except KeyboardInterrupt:
        print("planner: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # a bug: one line, the traceback only on request
        if os.environ.get("PLANNER_DEBUG"):
            traceback.print_exc()
        first = str(exc).splitlines()[0] if str(exc) else ""
        print(f"planner: internal error: {type(exc).__name__}: {first} (set PLANNER_DEBUG=1 for the traceback)", file=sys.stderr)
        return int(ExitCode.INTERNAL)
