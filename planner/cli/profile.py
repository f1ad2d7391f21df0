"""How the tuning keys (:mod:`planner.cli.tuning`) are set and listed: ``--set KEY=VALUE``, ``--config FILE``
(a TOML profile: ``[plan]`` then ``key = value`` lines) and ``--help-all``. Each value goes through its key's own
check and lands in the parsed namespace under the setting's attribute (``args.tile_budget``); ``--set`` and the
flags win over the file. A key the command does not know, or a value the key refuses, is a one-line usage error
(exit 2) naming the key (and for a profile the file and the table).
"""

from __future__ import annotations

import argparse
import difflib
import shutil
import sys
import tomllib
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from planner.cli.tuning import TUNING, from_profile, from_text, keys_help
from planner.core.errors import UsageError
from planner.core.settings import SETTINGS, Setting

__all__ = ["DEFAULT_PROFILE", "TUNING", "add_profile_options", "apply_config", "apply_profile", "read_profile"]

#: the profile shipped with the package: the defaults of every tuning knob that has one
DEFAULT_PROFILE = Path(__file__).with_name("profiles") / "default.toml"


class _CommandAction(argparse.Action):
    """An option of ``command``'s tuning (``--help-all``, ``--set``) that stores nothing by itself."""

    def __init__(self, option_strings: Sequence[str], dest: str, *, command: str, **kwargs: Any) -> None:
        super().__init__(option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, **kwargs)
        self.command = command


class _HelpAll(_CommandAction):
    """``--help-all``: the help, then every tuning key with its values and help; exit 0."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: Any, values: Any, option: Any = None) -> None:
        epilog, parser.epilog = parser.epilog, None  # the epilog points here: the keys follow instead
        try:
            text = parser.format_help()
        finally:
            parser.epilog = epilog
        print(text + "\n" + keys_help(self.command, shutil.get_terminal_size().columns - 2))
        parser.exit()


class _SetKey(_CommandAction):
    """``--set KEY=VALUE`` (repeatable): one tuning key's value, checked by the key, into the namespace; a later
    ``--set`` of the same key wins (a repeatable key collects its items)."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: Any, values: Any, option: Any = None) -> None:
        key, eq, text = str(values).partition("=")
        flag = f"--{key.strip().replace('_', '-')}"
        if flag in parser._option_string_actions:
            raise UsageError(
                f"{flag} is an option of 'planner {self.command}', not a tuning key: give {flag}",
                field=f"--set {values}",
            )
        s = tuning_key(self.command, key.strip(), f"--set {values}")
        try:
            value = from_text(s, text if eq else None, getattr(namespace, s.dest, None))
        except ValueError as exc:
            raise UsageError(str(exc), field=f"--set {s.key}") from None
        setattr(namespace, s.dest, value)


def tuning_key(command: str, key: str, where: str) -> Setting:
    """The tuning key ``key`` of ``command`` (``_`` taken for ``-``); else a usage error naming ``where``, with
    the keys of that name nearest to it."""
    name = key.replace("_", "-")
    keys = TUNING.get(command, ())
    if name in keys:
        return SETTINGS[name]
    near = difflib.get_close_matches(name, keys, n=3)
    hint = f"; did you mean {' or '.join(near)}?" if near else ""
    raise UsageError(
        f"no tuning key {name!r} of 'planner {command}' (see planner {command} --help-all){hint}", field=where
    )


def add_profile_options(p: argparse.ArgumentParser, command: str) -> None:
    """``--set KEY=VALUE``, ``--config FILE`` (read by :func:`apply_config` before parsing) and ``--help-all``
    for ``command``, whose tuning keys start at their defaults in the parsed namespace."""
    keys = TUNING.get(command, ())
    p.add_argument(
        "--set",
        action=_SetKey,
        command=command,
        metavar="KEY=VALUE",
        help="set a tuning key, e.g. --set tile-budget=600 (repeatable; the keys: --help-all); wins over --config",
    )
    p.add_argument(
        "--config",
        metavar="FILE",
        help=f"a TOML profile of tuning keys, [{command}] table (see --help-all; "
        "defaults in planner/cli/profiles/default.toml); the command line wins",
    )
    p.add_argument(
        "--help-all", action=_HelpAll, command=command, nargs=0, help="show this help and every tuning key, and exit"
    )
    p.set_defaults(**{SETTINGS[key].dest: SETTINGS[key].initial for key in keys})
    p.epilog = (
        f"{len(keys)} tuning keys (solver, tiles and Dask, field sheet, input formats) are set by --set KEY=VALUE "
        f"or --config FILE; planner {command} --help-all lists them."
    )


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
    """Set the defaults of ``p`` (the ``command`` subparser) from the profile's ``[command]`` table: its tuning
    keys, and any of its options (``method = "greedy"``), which the command line then overrides.

    Each value goes through its key's or option's own check (type, choices), so a profile value is refused
    exactly as the same value on the command line would be."""
    table = profile.get(command, {})
    if not isinstance(table, dict):
        raise UsageError(f"[{command}] must be a table", field=str(source), value=type(table).__name__)
    by_name = {s.lstrip("-"): a for a in p._actions for s in a.option_strings if s.startswith("--")}
    for key, value in table.items():
        name = str(key).replace("_", "-")
        where = f"[{command}] {key}"
        action = by_name.get(name)
        try:
            if name in TUNING.get(command, ()):
                p.set_defaults(**{SETTINGS[name].dest: from_profile(SETTINGS[name], value)})
            elif action is not None and action.dest not in ("help", "config", argparse.SUPPRESS):
                action.default = _checked(action, value)
            else:
                tuning_key(command, name, where)  # the error, with the nearest keys
        except ValueError as exc:  # UsageError is one: it keeps its words, with the file in front
            message = exc.one_line() if isinstance(exc, UsageError) else f"{where}: {exc}"
            raise UsageError(message, file=str(source)) from None


def _checked(action: argparse.Action, value: Any) -> Any:
    """``value`` as the option would parse it on the command line; ValueError says why not."""
    if isinstance(action, (argparse._StoreTrueAction, argparse._StoreFalseAction)):
        if not isinstance(value, bool):
            raise ValueError("expected true or false")
        return value
    if action.nargs == 0 or isinstance(value, (dict, bool)):
        raise ValueError("not a value this option takes")
    items = value if isinstance(value, list) else [value]
    out = []
    for item in items:
        try:
            v = action.type(str(item)) if callable(action.type) else item
        except (argparse.ArgumentTypeError, ValueError, TypeError) as exc:
            raise ValueError(str(exc)) from None
        if action.choices is not None and v not in action.choices:
            raise ValueError(f"must be one of {', '.join(map(str, action.choices))}, got {item!r}")
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
        raise UsageError(f"[{unknown[0]}] is no command (tables: {', '.join(TUNING)})", file=path)
    apply_profile(subs.choices[command], command, profile, path)
