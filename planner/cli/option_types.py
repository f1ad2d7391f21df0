"""Checked number types of the command line's options: a bad value is a one-line usage error (exit 2)
that names the option and the value, before any work starts."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable


def number(
    kind: type = float, *, above: float | None = None, at_least: float | None = None, at_most: float | None = None
) -> Callable[[str], float]:
    """An argparse ``type``: ``kind`` (float or int) parsed from the text, finite, within the bounds given
    (``above`` < x, ``at_least`` <= x, x <= ``at_most``)."""
    rules = [
        (above, lambda x, b: x > b, ">"),
        (at_least, lambda x, b: x >= b, ">="),
        (at_most, lambda x, b: x <= b, "<="),
    ]
    wanted = " and ".join(f"{op} {b:g}" for b, _, op in rules if b is not None)

    def parse(text: str) -> float:
        try:
            value: float = kind(text.strip())
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"expected {'an integer' if kind is int else 'a number'}, got {text!r}"
            ) from None
        if not math.isfinite(value) or not all(ok(value, b) for b, ok, _ in rules if b is not None):
            raise argparse.ArgumentTypeError(f"must be {'finite' if not wanted else wanted}, got {text!r}")
        return value

    parse.__name__ = kind.__name__
    return parse


#: the option types used by the parser
POSITIVE = number(float, above=0)
NON_NEGATIVE = number(float, at_least=0)
POSITIVE_INT = number(int, at_least=1)
NON_NEGATIVE_INT = number(int, at_least=0)


class OncePerKey(argparse.Action):
    """A repeatable ``KEY=VALUE`` option (``--layer-height WALLS=3``) that refuses a key given twice (keys
    compared case-insensitively, as DXF layer names are), since only one of the two values could be used."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: object,
        option_string: str | None = None,
    ) -> None:
        try:
            items = once_per_key(list(getattr(namespace, self.dest, None) or []), str(values))
        except ValueError as exc:
            raise argparse.ArgumentError(self, str(exc)) from None
        setattr(namespace, self.dest, items)


def once_per_key(items: list[str], item: str) -> list[str]:
    """``items`` with the ``KEY=VALUE`` ``item`` added (a new list); ValueError where its key, compared
    case-insensitively, is already there."""
    key = item.partition("=")[0].strip().upper()
    twice = next((old for old in items if old.partition("=")[0].strip().upper() == key), None)
    if twice is not None:
        raise ValueError(f"layer {key!r} given twice ({twice!r} and {item!r}): give each layer once")
    return [*items, item]


def name_list(choices: tuple[str, ...], need: str = "", what: str = "name") -> Callable[[str], str]:
    """An argparse ``type``: a comma-separated list of distinct names of ``choices`` that holds ``need`` (a name,
    or none), returned without blanks (``walls,floors``); the empty text: no names."""

    def parse(text: str) -> str:
        names = [n.strip().lower() for n in text.split(",") if n.strip()]
        unknown = [n for n in names if n not in choices]
        if unknown:
            raise argparse.ArgumentTypeError(
                f"unknown {what} {unknown[0]!r} (known: {', '.join(choices)}), got {text!r}"
            )
        if need and need not in names:
            raise argparse.ArgumentTypeError(f"must include {need} (e.g. {need},{choices[-1]}), got {text!r}")
        if len(set(names)) != len(names):
            raise argparse.ArgumentTypeError(f"names a {what} twice, got {text!r}")
        return ",".join(names)

    parse.__name__ = "list"
    return parse


def memory_size(text: str) -> int:
    """An argparse ``type``: a memory size (``1.5GiB``, ``4G``, ``512M``, ``800k`` or bytes; binary multiples) in
    bytes, the one unit inside."""
    units = {"k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}
    t = text.strip().lower().removesuffix("b").removesuffix("i")
    try:
        value = float(t[:-1] if t[-1:] in units else t) * units.get(t[-1:], 1)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a memory size such as 1.5GiB, 4G or bytes, got {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be > 0 (a memory size), got {text!r}")
    return int(value)


def tiles(text: str) -> float | str:
    """``--tiles``: a core side in m, ``auto`` or ``off``."""
    word = text.strip().lower()
    return word if word in ("auto", "off") else POSITIVE(text)
