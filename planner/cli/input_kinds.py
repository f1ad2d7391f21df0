"""The files a command line names, checked before any reader runs: each exists, is a file, can be read and is the
kind the command reads there (:func:`planner.io.file_kind.file_kind`), else one line and exit 2 (3 for a file
that is missing or cannot be read).

A plan given where a site belongs (or the other way round) used to reach the reader, which said what it did not
understand ("backend: unknown key in instance"); this says which kind of file was given and which was expected.
Light on purpose: the check runs before numpy, shapely or the planning stack load (docs/startup.md).
"""

from __future__ import annotations

import argparse

from planner.cli.tuning import option_name
from planner.core.errors import UsageError

#: the options that name an input file, and the kind each reads; a command checks those it has
FILE_OPTIONS = (("site", "site"), ("plan", "plan"), ("control", "control"), ("observations", "observations"))

#: the commands whose ``site`` is the ``--site`` option (their positional is the plan)
_SITE_OPTION = ("report", "field", "replan")

#: the commands that take SITE PLAN, in this order
_SITE_THEN_PLAN = ("verify", "network", "chain")


def check_input_files(args: argparse.Namespace) -> None:
    """Check every input file ``args`` names (site, plan, control points, observations, traverse).

    Raises
    ------
    UsageError
        An empty path, a folder, or a file of another kind than the command reads there (exit 2).
    InputError
        A file that does not exist or cannot be read, or a small JSON file that is invalid (exit 3).
    """
    command = str(getattr(args, "command", ""))
    named = [(dest, kind) for dest, kind in FILE_OPTIONS if getattr(args, dest, None) is not None]
    traverse = getattr(args, "traverse", None)
    if isinstance(traverse, str) and traverse != "none":
        named.append(("traverse", "traverse"))
    for dest, kind in named:
        _check(command, _label(command, dest), str(getattr(args, dest)), kind, args)


def _label(command: str, dest: str) -> str:
    """How the command line names the file: a positional by its name (``site``), an option by its flag."""
    if dest in ("site", "plan") and not (dest == "site" and command in _SITE_OPTION):
        return dest
    return option_name(command, dest) if dest == "traverse" else f"--{dest}"


def _check(command: str, label: str, path: str, expected: str, args: argparse.Namespace) -> None:
    from planner.io.file_kind import EXPECTED, KINDS, file_kind

    what = f"planner {command}" if not label.startswith("-") else f"planner {command} {label}"
    if not path.strip():
        raise UsageError(f"the {label} path is empty: {what} expects {EXPECTED[expected]}")
    given = file_kind(path)
    if given in (expected, "unknown"):
        return
    raise UsageError(f"{path} is {KINDS[given]}; {what} expects {EXPECTED[expected]}{_hint(command, given, args)}")


def _hint(command: str, given: str, args: argparse.Namespace) -> str:
    """What to do instead, where the mix-up is a common one."""
    if given == "site" and command in ("report", "field"):
        return f" (plan it first: planner plan {args.plan} --out DIR --{command} DIR)"
    if given == "plan" and command in _SITE_THEN_PLAN:
        return f" (the site comes first: planner {command} SITE PLAN)"
    if given == "plan":
        return "; planner verify, network, chain, report and field read a plan"
    return ""
