"""Checks of option values for the frozen option dataclasses (``__post_init__``): a wrong type or an out-of-range
value is a :class:`~planner.errors.UsageError` naming the field and the value, before any work starts; and the
one check of names that must be unique (station ids, control point names), an :class:`~planner.errors.InputError`."""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable
from typing import Any

from planner.errors import InputError, UsageError


#: verification sampling along the walls (m): finer than 1 mm is no survey resolution (and 10^9 samples per km
#: of wall), coarser than 10 m checks little more than the corners
SAMPLING_M = (0.001, 10.0)


def no_repeats(names: Iterable[str], *, what: str, field: str, row: str, file: str | None = None) -> None:
    """Refuse the first name given twice (the network, the report and the exports key points by name, so two
    would merge into one); ``row`` formats a 1-based position, e.g. ``"control[{}]"``."""
    first: dict[str, int] = {}
    for k, name in enumerate(names, 1):
        if name in first:
            raise InputError(f"{what} used twice (also {row.format(first[name])})", file=file, row=row.format(k),
                             field=field, value=name)
        first[name] = k


def count(value: Any, field: str, least: int = 0) -> None:
    """An integer (not a bool, not a float) >= ``least``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < least:
        raise UsageError(f"must be an integer >= {least}", field=field, value=value)


def real(value: Any, field: str, *, above: float | None = None, at_least: float | None = None,
         infinite_ok: bool = False) -> None:
    """A number (not a bool), finite unless ``infinite_ok``, > ``above`` or >= ``at_least``."""
    ok = not isinstance(value, bool) and isinstance(value, numbers.Real) and not math.isnan(value)
    ok = ok and (infinite_ok or math.isfinite(value))
    ok = ok and (above is None or value > above) and (at_least is None or value >= at_least)
    if not ok:
        bound = f" > {above:g}" if above is not None else f" >= {at_least:g}" if at_least is not None else ""
        raise UsageError(f"must be a {'' if infinite_ok else 'finite '}number{bound}", field=field, value=value)


def flag(value: Any, field: str) -> None:
    """True or False (a string such as 'no' is truthy, so it is refused)."""
    if not isinstance(value, bool):
        raise UsageError("must be True or False", field=field, value=value)
