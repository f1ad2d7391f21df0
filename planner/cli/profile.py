"""Tuning profiles of the command line: the knobs ``--help`` leaves out, their defaults, and ``--config FILE``.

``planner plan --help`` lists what a surveyor sets (the site, the instrument's limits, the method and its
time, the outputs). The solver and tile knobs, the rarer input-format options and the field-sheet details are
*tuning*: hidden from ``--help``, listed by ``--help-all``, and settable from a TOML profile::

    # my.toml
    [plan]
    tile-window-radius = 80
    backend = "scip"

    planner plan site.json --config my.toml      # the command line still wins over the file

The package ships the profile of the defaults (``planner/cli/profiles/default.toml``, :data:`DEFAULT_PROFILE`):
every tuning knob with a default, its value and what it does; a test checks it against the parser, so the file
cannot drift from the defaults the command uses. A key the command does not know, or a value its
option refuses, is a one-line usage error (exit 2) naming the file, the table and the key.
"""

from __future__ import annotations

import argparse
import sys
import tomllib
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from planner.errors import UsageError

#: the profile shipped with the package: the defaults of every tuning knob that has one
DEFAULT_PROFILE = Path(__file__).with_name("profiles") / "default.toml"

#: per subcommand, the options ``--help`` leaves out (``--help-all`` lists them); all are settable by ``--config``
TUNING: dict[str, tuple[str, ...]] = {
    "plan": (
        # the solver
        "--backend",
        "--work-limit",
        "--local-search-moves",
        "--connectivity",
        "--layer-cuts",
        "--tree-bound",
        "--no-ring-bound",
        "--ring-lagrange-steps",
        "--no-regions",
        "--no-pricing",
        "--pricing-time-limit",
        "--plane-refine-steps",
        "--seed",
        # the registration rule's extra limits, the accuracy model's switches, verification
        "--min-shared",
        "--max-link",
        "--incidence",
        "--no-precision",
        "--verify-spacing",
        "--tripod",
        # the network check and the field sheet
        "--monte-carlo",
        "--traverse",
        "--ts-everywhere",
        "--field-mode",
        "--field-start",
        "--field-session",
        # the tiles
        "--tile-time-limit",
        "--bound-time-limit",
        "--lagrange-work",
        "--lagrange-group",
        "--tile-search-moves",
        "--tile-search-seeds",
        "--tile-window-passes",
        "--tile-window-radius",
        "--tile-window-work",
        "--tile-window-batch",
        "--tile-wall-clock",
        "--worker-memory",
        "--tile-budget",
        # input formats (table CSV closures, DXF, IFC)
        "--angular-tolerance",
        "--min-relative-precision",
        "--layer-height",
        "--dxf-side",
        "--exterior",
        "--ifc-windows",
    ),
}


class _HelpAll(argparse.Action):
    """``--help-all``: the help with the tuning options shown too, then exit 0."""

    def __init__(self, option_strings: Sequence[str], dest: str, **kwargs: Any) -> None:
        super().__init__(
            option_strings,
            dest=argparse.SUPPRESS,
            default=argparse.SUPPRESS,
            nargs=0,
            help="show every option, the tuning ones too (also settable by --config), and exit",
        )

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: object,
        option_string: str | None = None,
    ) -> None:
        for action in parser._actions:
            if hasattr(action, "tuning_help"):
                action.help = f"[tuning] {action.tuning_help}"
        parser.print_help()
        parser.exit()


def add_profile_options(p: argparse.ArgumentParser) -> None:
    """``--config FILE`` and ``--help-all`` (the file itself is read by :func:`apply_config` before parsing)."""
    p.add_argument(
        "--config",
        metavar="FILE",
        help="a TOML profile of tuning options, [plan] table (see --help-all; "
        "defaults in planner/cli/profiles/default.toml); the command line wins",
    )
    p.add_argument("--help-all", action=_HelpAll)


def hide_tuning(p: argparse.ArgumentParser, command: str) -> None:
    """Hide ``command``'s tuning options from ``--help`` (``--help-all`` shows them, marked ``[tuning]``)."""
    names = set(TUNING.get(command, ()))
    for action in p._actions:
        if names.intersection(action.option_strings):
            action.tuning_help = action.help  # type: ignore[attr-defined]
            action.help = argparse.SUPPRESS


def read_profile(path: str | Path) -> dict[str, Any]:
    """The TOML file as a dict; a missing or malformed file is a usage error naming it."""
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except OSError as exc:
        raise UsageError(f"cannot read the profile: {exc.strerror or exc}", field="--config", value=str(path)) from None
    except tomllib.TOMLDecodeError as exc:
        raise UsageError(f"not a TOML file: {exc}", field="--config", value=str(path)) from None


def apply_profile(p: argparse.ArgumentParser, command: str, profile: Mapping[str, Any], source: str | Path) -> None:
    """Set the defaults of ``p`` (the ``command`` subparser) from the profile's ``[command]`` table.

    Each value goes through its option's own check (type, choices), so a profile value is refused exactly as
    the same value on the command line would be."""
    table = profile.get(command, {})
    if not isinstance(table, dict):
        raise UsageError(f"[{command}] must be a table", field=str(source), value=type(table).__name__)
    by_name = {s.lstrip("-"): a for a in p._actions for s in a.option_strings if s.startswith("--")}
    for key, value in table.items():
        action = by_name.get(str(key).replace("_", "-"))
        where = f"{source}: [{command}] {key}"
        if action is None or action.dest in ("help", "config", argparse.SUPPRESS):
            raise UsageError(
                f"{where}: no such option of 'planner {command}' (see planner {command} --help-all)",
                field="--config",
                value=str(key),
            )
        action.default = _checked(action, value, where)


def _checked(action: argparse.Action, value: Any, where: str) -> Any:
    """``value`` as the option would parse it on the command line."""
    if isinstance(action, (argparse._StoreTrueAction, argparse._StoreFalseAction)):
        if not isinstance(value, bool):
            raise UsageError(f"{where}: expected true or false", field="--config", value=repr(value))
        return value
    if action.nargs == 0 or isinstance(value, (dict, bool)):
        raise UsageError(f"{where}: not a value this option takes", field="--config", value=repr(value))
    items = value if isinstance(value, list) else [value]
    out = []
    for item in items:
        try:
            v = action.type(str(item)) if callable(action.type) else item
        except (argparse.ArgumentTypeError, ValueError, TypeError) as exc:
            raise UsageError(f"{where}: {exc}", field="--config", value=repr(item)) from None
        if action.choices is not None and v not in action.choices:
            raise UsageError(
                f"{where}: must be one of {', '.join(map(str, action.choices))}", field="--config", value=repr(item)
            )
        out.append(v)
    return out if isinstance(value, list) else out[0]


def config_argument(argv: Sequence[str]) -> str | None:
    """The FILE of ``--config FILE`` / ``--config=FILE`` in ``argv`` (read before the full parse)."""
    for k, arg in enumerate(argv):
        if arg == "--config" and k + 1 < len(argv):
            return argv[k + 1]
        if arg.startswith("--config="):
            return arg.partition("=")[2]
    return None


def apply_config(parser: argparse.ArgumentParser, argv: Sequence[str] | None) -> None:
    """Apply ``--config FILE`` (if given) to the subcommand named in ``argv``."""
    argv = list(sys.argv[1:] if argv is None else argv)
    path = config_argument(argv)
    if path is None:
        return
    subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    command = next((a for a in argv if a in subs.choices), None)
    if command is None:
        return
    profile = read_profile(path)
    unknown = [k for k in profile if k not in subs.choices]
    if unknown:
        raise UsageError(
            f"{path}: [{unknown[0]}] is no command (tables: {', '.join(TUNING)})", field="--config", value=unknown[0]
        )
    apply_profile(subs.choices[command], command, profile, path)
