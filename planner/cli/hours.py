"""The command line's side of the hours on site: the field session the trade-off counts in, and
``planner verify --max-point-spacing``."""

from __future__ import annotations

import argparse
from typing import Any

from planner.cli.tuning import option_name
from planner.core.errors import UsageError


def session_of(args: argparse.Namespace) -> float | None:
    """The field session (``--set field-session=4h``) in seconds, which the field-time trade-off counts in."""
    from planner.field.timing import parse_duration

    text = getattr(args, "field_session", None)
    if not text:
        return None
    try:
        return parse_duration(text)
    except UsageError as err:
        raise UsageError(err.message, field=option_name("plan", "field-session"), value=err.value) from None


def verify_spacing_of(args: argparse.Namespace, problem: Any, stations: Any) -> Any:
    """The spacing check of ``planner verify --max-point-spacing``: each station at the setting plan.json
    records for it, else at the instrument's default setting."""
    from planner.core.fileio import read_json
    from planner.plan.hours.field_time import field_properties
    from planner.plan.hours.verify import verify_spacing

    props = field_properties(problem.site)
    rows = read_json(args.plan).get("stations", [])
    recorded = [r.get("setting") if isinstance(r, dict) else None for r in rows]
    settings: list[str] = [str(s) for s in recorded]
    if len(recorded) != len(stations) or not all(isinstance(s, str) for s in recorded):
        settings = [props.default_setting] * len(stations)
    for s in settings:
        if s not in props.settings:
            raise UsageError(
                f"is not a setting of the instrument {problem.site.instrument} (known: {', '.join(props.settings)})",
                file=args.plan,
                field="setting",
                value=s,
            )
    return verify_spacing(problem.sight, stations, settings, props, args.max_point_spacing, args.spacing)
