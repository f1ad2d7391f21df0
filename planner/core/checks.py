"""Checks of option values for the frozen option dataclasses (``__post_init__``): a wrong type or an out-of-range
value is a :class:`~planner.core.errors.UsageError` naming the field and the value, before any work starts; and the
one check of names that must be unique (station ids, control point names), an :class:`~planner.core.errors.InputError`."""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Iterable
from typing import Any, TypeGuard

from planner.core.errors import ArgumentTypeError, InputError, UsageError

#: verification sampling along the walls (m): finer than 1 mm is no survey resolution (and 10^9 samples per km
#: of wall), coarser than 10 m checks little more than the corners
SAMPLING_M = (0.001, 10.0)


def no_repeats(names: Iterable[str], *, what: str, field: str, row: str, file: str | None = None) -> None:
    """Refuse the first name given twice (the network, the report and the exports key points by name, so two
    would merge into one); ``row`` formats a 1-based position, e.g. ``"control[{}]"``."""
    first: dict[str, int] = {}
    for k, name in enumerate(names, 1):
        if name in first:
            raise InputError(
                f"{what} used twice (also {row.format(first[name])})",
                file=file,
                row=row.format(k),
                field=field,
                value=name,
            )
        first[name] = k


#: how to get an object of the kind a public function takes, for the message when it was given another
MAKE = {
    "Site": "planner.load_site(path) reads one",
    "Plan": "planner.plan_site(site, options) makes one",
    "Outcome": "planner.outcome_from_plan(plan) makes one",
    "PlanOptions": "e.g. planner.PlanOptions(method='milp')",
    "CoverageProblem": "planner.build_problem(site, options) makes one",
    "NetworkReport": "planner.run_network(site, plan.stations) makes one",
    "CoverInstance": "planner.cover_instance(problem) makes one",
    "OverlapRule": "e.g. planner.OverlapRule(0.3)",
    "Problem": "planner.resolve(site, options) makes one",
    "Sight": "planner.resolve(site, options).sight, or planner.Sight.of_site(site)",
}


def argument(value: Any, kind: type | tuple[type, ...], name: str) -> None:
    """Refuse an argument that is not a ``kind`` (an :class:`ArgumentTypeError` naming the argument, what it
    got and how to get the right one), before a deep AttributeError could name neither."""
    if isinstance(value, kind):
        return
    kinds = kind if isinstance(kind, tuple) else (kind,)
    want = " or ".join("None" if k is type(None) else article(k.__name__) for k in kinds)
    how = "; ".join(MAKE[k.__name__] for k in kinds if k.__name__ in MAKE)
    raise ArgumentTypeError(
        f"must be {want}, not {article(type(value).__name__)}" + (f" ({how})" if how else ""),
        field=name,
        value=shown(value),
    )


def path_argument(value: Any, name: str) -> None:
    """Refuse a file path that is no ``str`` or path-like (a Site, None, a number: pathlib's bare TypeError
    before), naming the argument and, for a number, its value."""
    if not isinstance(value, (str, os.PathLike)):
        raise ArgumentTypeError(
            f"must be a file path (str or pathlib.Path), not {type(value).__name__}", field=name, value=shown(value)
        )


def article(noun: str) -> str:
    return ("an " if noun[:1].lower() in "aeiou" else "a ") + noun


def shown(value: Any) -> Any:
    """A short text or number as found; None (left out of the message) for other objects."""
    if isinstance(value, str):
        return value if len(value) <= 60 else value[:57] + "..."
    return value if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def finite_number(value: Any) -> TypeGuard[float]:
    """True for a finite int or float (a bool is no number here)."""
    return not isinstance(value, bool) and isinstance(value, (int, float)) and math.isfinite(value)


def count(value: Any, field: str, least: int = 0) -> None:
    """An integer (not a bool, not a float) >= ``least``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < least:
        raise UsageError(f"must be an integer >= {least}", field=field, value=value)


def real(
    value: Any, field: str, *, above: float | None = None, at_least: float | None = None, infinite_ok: bool = False
) -> None:
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
