"""Checks of option values for the frozen option dataclasses (``__post_init__``): a wrong type or an out-of-range
value is a :class:`~planner.errors.UsageError` naming the field and the value, before any work starts."""

from __future__ import annotations

import math
import numbers
from typing import Any

from planner.errors import UsageError


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
