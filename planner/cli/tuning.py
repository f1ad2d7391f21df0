"""The settings of :mod:`planner.core.settings` on the command line: as flags (``--KEY``), as tuning keys
(``--set KEY=VALUE``, a ``[plan]`` table of ``--config FILE``), in ``--help-all`` and in the shipped profile
``planner/cli/profiles/default.toml`` (:func:`profile_text` writes it; a test checks the file).

``planner plan`` takes as flags what a surveyor sets; the solver, tile and Dask settings, the registration rule's
extra limits, the field-sheet details and the rarer input formats are its tuning keys. The other subcommands that
share a setting take it as the flag ``--KEY`` (:func:`add_setting`), with the same type, choices, default and
help, so a value means the same wherever it is given. Text is parsed here, at the edge: a memory size becomes
bytes, a list stays its checked text.
"""

from __future__ import annotations

import argparse
import json
import textwrap
from collections.abc import Callable, Collection
from typing import Any

from planner.cli.option_types import OncePerKey, memory_size, name_list, number, once_per_key, tiles
from planner.core.settings import PLAN_FLAGS, PLAN_KEYS, SETTINGS, Setting, setting_of

#: per subcommand, its tuning keys: not flags, but ``--set KEY=VALUE`` and ``--config FILE`` keys
TUNING: dict[str, tuple[str, ...]] = {"plan": PLAN_KEYS}

_TRUE = ("true", "yes", "on", "1")
_FALSE = ("false", "no", "off", "0")


def parser_of(s: Setting) -> Callable[[str], Any]:
    """The argparse ``type`` of a setting (``str``: the text itself)."""
    if s.kind in ("float", "int"):
        return number(float if s.kind == "float" else int, above=s.above, at_least=s.at_least, at_most=s.at_most)
    listed = name_list(s.choices or (), s.default or "", s.key.removesuffix("s")) if s.kind == "list" else None
    return {"memory": memory_size, "tiles": tiles, "list": listed}.get(s.kind) or str


def usage(s: Setting) -> str:
    """``KEY=VALUE`` as ``--help-all`` shows it."""
    if s.kind == "switch":
        return f"{s.key}[=true|false]"
    if s.choices is not None and s.kind != "list":
        return f"{s.key}={{{','.join(s.choices)}}}"
    return f"{s.key}={s.metavar or 'VALUE'}"


def from_text(s: Setting, text: str | None, items: list[str] | None = None) -> Any:
    """The value of ``KEY=text`` (``text`` None: ``KEY`` alone, a switch set), checked as the flag would be;
    ``items``: a repeatable key's values so far. ValueError says why not."""
    if s.kind == "switch":
        word = "true" if text is None else text.strip().lower()
        if word not in _TRUE + _FALSE:
            raise ValueError(f"expected true or false, got {text!r}")
        return word in _TRUE
    if text is None:
        raise ValueError(f"expected {s.key}={s.metavar or 'VALUE'}")
    if s.kind == "items":
        return once_per_key(list(items or []), text)
    parse = parser_of(s)
    try:
        value = parse(text)
    except argparse.ArgumentTypeError as exc:
        raise ValueError(str(exc)) from None
    if s.choices is not None and s.kind != "list" and value not in s.choices:
        raise ValueError(f"must be one of {', '.join(s.choices)}, got {text!r}")
    return value


def from_profile(s: Setting, value: object) -> Any:
    """The value of ``key = value`` in a TOML profile: a boolean for a switch, strings for a repeatable key,
    else a number or string checked as its text would be."""
    if s.kind == "switch":
        if not isinstance(value, bool):
            raise ValueError("expected true or false")
        return value
    if s.kind == "items":
        items: list[str] = []
        for item in value if isinstance(value, list) else [value]:
            if not isinstance(item, str):
                raise ValueError(f"expected {s.metavar} strings")
            items = once_per_key(items, item)
        return items
    if s.kind == "memory" and isinstance(value, int) and not isinstance(value, bool):
        value = str(value)
    if isinstance(value, (bool, list, dict)):
        raise ValueError("not a value this key takes")
    return from_text(s, str(value))


def add_setting(
    p: argparse.ArgumentParser, key: str, tuning: Collection[str] = (), *, name: str | None = None, help: str = ""
) -> None:
    """The setting ``key`` as the flag ``--KEY`` (``--NAME``) of ``p``, unless it is one of ``tuning``, the
    tuning keys of ``p``'s command; ``help`` replaces the setting's own."""
    if key in tuning:
        return
    s = SETTINGS[key]
    flag, text = f"--{name or key}", help or s.help
    if s.kind == "switch":
        p.add_argument(flag, action="store_true", help=text)
    elif s.kind == "items":
        p.add_argument(flag, action=OncePerKey, default=[], metavar=s.metavar, help=text)
    else:
        choices = s.choices if s.kind != "list" else None
        p.add_argument(flag, type=parser_of(s), choices=choices, default=s.default, metavar=s.metavar, help=text)


def add_settings(p: argparse.ArgumentParser, *keys: str, tuning: Collection[str] = ()) -> None:
    """Each of ``keys`` as :func:`add_setting` adds it."""
    for key in keys:
        add_setting(p, key, tuning)


def add_plan_settings(p: argparse.ArgumentParser) -> None:
    """The surveyor's settings as flags; every other setting at its default in the parsed namespace (the
    plan's tuning keys set by ``--set``/``--config``)."""
    add_settings(p, *PLAN_FLAGS)
    p.set_defaults(**{s.dest: s.initial for k, s in SETTINGS.items() if k not in PLAN_FLAGS})


def option_name(command: str | None, key: str) -> str:
    """How ``command`` takes the setting ``key``, for an error message: ``--set KEY`` or ``--KEY``."""
    return f"--set {key}" if key in TUNING.get(command or "", ()) else f"--{key}"


def field_flag(command: str | None, field: str | None) -> str | None:
    """How ``command`` takes the setting that gives an options field (the field itself where none does)."""
    s = setting_of(field) if field and not field.startswith("-") else None
    return field if s is None else option_name(command, s.key)


def keys_help(command: str, width: int = 80) -> str:
    """The tuning keys of ``command`` by section, each with its values and help (the end of ``--help-all``)."""
    lines = textwrap.wrap(
        f"tuning keys (--set KEY=VALUE, repeatable, or a [{command}] table in --config FILE; the defaults, "
        f"commented: planner/cli/profiles/default.toml):",
        width,
        break_on_hyphens=False,
    )
    indent, section = 24, None
    for key in TUNING.get(command, ()):
        s = SETTINGS[key]
        if s.section != section:
            section = s.section
            lines += ["", f" {section}:"]
        head = f"  {usage(s)}"
        body = textwrap.wrap(s.help, max(width - indent, 20), break_on_hyphens=False)
        if len(head) + 2 <= indent:
            lines.append(head.ljust(indent) + body[0])
            body = body[1:]
        else:
            lines.append(head)
        lines += [" " * indent + line for line in body]
    return "\n".join(lines)


def profile_text(command: str) -> str:
    """The shipped profile of ``command`` (``planner/cli/profiles/default.toml``): every tuning key with its help
    as a comment and its default (keys without one commented out)."""
    out = [
        f"# The tuning keys of `planner {command}` and their defaults (`planner {command} --help-all` lists them).",
        "# Copy the lines you change into a file of your own and give it with",
        f"# `planner {command} SITE --config FILE`, or set one key on the command line with `--set KEY=VALUE`",
        "# (`--set` wins over the file). Written from the settings (planner/core/settings/); a test checks",
        "# it, so it is what the command does when nothing is said.",
        "",
        f"[{command}]",
    ]
    section = None
    for key in TUNING[command]:
        s = SETTINGS[key]
        if s.section != section:
            section = s.section
            out += ["", f"# --- {section} ---"]
        out += [""] + ["# " + line for line in textwrap.wrap(s.help, 108, break_on_hyphens=False)]
        value = s.initial
        out.append(f"# {key} = (no default: unset)" if value is None or value == [] else f"{key} = {_toml(value)}")
    return "\n".join(out) + "\n"


def _toml(value: object) -> str:
    """``value`` as a TOML value (booleans, numbers and strings are all the defaults hold)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value) if isinstance(value, (int, float)) else json.dumps(value)
