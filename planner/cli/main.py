"""The ``planner`` command: one function per subcommand; parses, calls the library, prints.

Exit codes: 0 ok, 1 internal error, 2 usage, 3 invalid input, 4 infeasible problem, 5 unreachable
scheduler, 141 standard output closed by its reader (see :mod:`planner.core.errors`). Errors print as one
line on stderr; set PLANNER_DEBUG=1 to see the traceback of an internal error.
"""

from __future__ import annotations

import argparse
import os
import sys
import traceback
from collections.abc import Callable, Sequence

from planner.cli.commands import cmd_assemble, cmd_export, cmd_instruments, cmd_plan, cmd_validate, cmd_verify
from planner.cli.input_kinds import check_input_files
from planner.cli.network_command import cmd_chain, cmd_network
from planner.cli.outputs import staged_outputs
from planner.cli.parser import build_parser as _build_parser
from planner.cli.profile import apply_config
from planner.core import progress
from planner.core.errors import ExitCode, PlannerError, UsageError


def build_parser() -> argparse.ArgumentParser:
    """The ``planner`` parser with this module's commands (:func:`planner.cli.parser.build_parser`)."""
    return _build_parser(
        {
            "validate": cmd_validate,
            "plan": cmd_plan,
            "verify": cmd_verify,
            "export": cmd_export,
            "network": cmd_network,
            "chain": cmd_chain,
            "assemble": cmd_assemble,
            "instruments": cmd_instruments,
        }
    )


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    try:
        parser = build_parser()
        apply_config(parser, argv)  # --config FILE: the profile's values become the defaults, the command line wins
        args = parser.parse_args(argv)
    except UsageError as exc:
        print(f"planner: usage error: {exc.one_line()}", file=sys.stderr)
        return int(exc.exit_code)
    except SystemExit as done:  # --help, --version, or a usage error already printed in one line
        return int(done.code or 0) if not isinstance(done.code, str) else int(ExitCode.USAGE)
    # a bar on a terminal, a line now and then in a log (a long run never looks hung), nothing with --quiet
    previous = progress.set_sink(progress.sink_for(sys.stderr, quiet=getattr(args, "quiet", True)))
    try:
        return _guarded(lambda: _run(args))
    finally:
        progress.set_sink(previous)


def _run(args: argparse.Namespace) -> int:
    """The command of ``args``: its input files checked for their kind first, its outputs staged and moved into
    place only when it succeeds (:mod:`planner.cli.outputs`); an error inside prints with the paths as given."""
    check_input_files(args)
    with staged_outputs(args) as stage:
        return _guarded(lambda: stage.commit(int(args.func(args))))


def _guarded(run: Callable[[], int]) -> int:
    """``run()``'s exit code, or the one-line message and exit code of what it raised."""
    try:
        return run()
    except PlannerError as exc:  # a usage error says so, as argparse's own do
        kind = "usage error" if isinstance(exc, UsageError) else "error"
        print(f"planner: {kind}: {exc.one_line()}", file=sys.stderr)
        return int(exc.exit_code)
    except KeyboardInterrupt:
        print("planner: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader of standard output stopped reading (| head): stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # so that the interpreter's final flush does not fail again
        return int(ExitCode.BROKEN_PIPE)
    except OSError as exc:  # a path given on the command line that cannot be written (or read)
        where = f"{exc.filename}: " if exc.filename else ""
        print(
            f"planner: error: {where}{exc.strerror or exc} (an output path given on the command line?)", file=sys.stderr
        )
        return int(ExitCode.USAGE)
    except Exception as exc:  # a bug: one line, the traceback only on request
        if os.environ.get("PLANNER_DEBUG"):
            traceback.print_exc()
        first = str(exc).splitlines()[0] if str(exc) else ""
        print(
            f"planner: internal error: {type(exc).__name__}: {first} (set PLANNER_DEBUG=1 for the traceback)",
            file=sys.stderr,
        )
        return int(ExitCode.INTERNAL)
