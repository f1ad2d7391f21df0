"""The ``planner field`` command (the field sheet of a plan) and the ``--field DIR`` step of
``planner plan``."""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from planner.cli.option_types import POSITIVE
from planner.cli.tuning import add_setting, option_name
from planner.core.errors import ExitCode, UsageError

if TYPE_CHECKING:  # loaded when the command runs (a fast --help: docs/startup.md)
    from planner.field.run import FieldOptions, FieldPlan
    from planner.plan.problem import Problem
    from planner.site import Site
    from planner.site.candidate import Candidate


def add_field_options(p: argparse.ArgumentParser) -> None:
    """Options of the sheet: ``--mode``, ``--start``, ``--session``, ``--strict-walls`` (on ``planner plan``
    the tuning keys ``field-mode``, ``field-start``, ``field-session``, ``field-strict-walls``: one help text
    for both, :mod:`planner.cli.tuning`)."""
    for key in ("field-mode", "field-start", "field-session", "field-strict-walls"):
        add_setting(p, key, name=key.removeprefix("field-"))


def add_field_parser(sub: Any) -> None:
    """Register ``planner field``."""
    f = sub.add_parser("field", help="the field sheet of a plan: visiting order, walking route, field time, targets")
    f.add_argument("plan", help="plan.json written by planner plan --out")
    f.add_argument("--site", help="the site file (default: the one recorded in the plan)")
    f.add_argument(
        "--out", metavar="DIR", help="folder for field.html/.csv/.geojson/.json (default: the plan's folder)"
    )
    add_field_options(f)
    f.add_argument("--tour", action="store_true", help="return to the start (default: an open path)")
    f.add_argument("--setting", metavar="NAME", help="scan setting of the instrument model (default: its default)")
    add_setting(f, "strong-overlap")
    add_setting(f, "solution-limit")
    f.add_argument(
        "--time-limit",
        type=POSITIVE,
        default=None,
        metavar="S",
        help="routing and branch-and-cut: a wall-clock cap in s (default none: they stop on counted work, the "
        "same sheet under any load; a capped sheet says so)",
    )
    f.add_argument("--quiet", action="store_true", help="no progress bars")
    f.set_defaults(func=cmd_field)


def field_options(args: argparse.Namespace, prefix: str = "") -> FieldOptions:
    """The sheet's options from ``args`` (``prefix`` ``field-``: the keys of ``planner plan``); a bad value is a
    usage error naming the option or key that gave it."""
    from planner.field.run import FieldOptions
    from planner.field.timing import parse_duration

    key = prefix.replace("-", "_")  # argparse: --field-mode is args.field_mode
    session = getattr(args, f"{key}session")
    try:
        return FieldOptions(
            mode=getattr(args, f"{key}mode"),
            start=getattr(args, f"{key}start"),
            closed=getattr(args, "tour", False),
            session_s=parse_duration(session) if session else None,
            setting=getattr(args, "setting", None),
            strong_overlap=args.strong_overlap,
            solution_limit=args.solution_limit,
            time_cap_s=getattr(args, "time_limit", None) if prefix == "" else None,
            strict_walls=bool(getattr(args, f"{key}strict_walls", False)),
        )
    except UsageError as err:
        if not prefix or err.field not in ("--mode", "--start", "--session"):
            raise
        name = option_name(getattr(args, "command", None), f"{prefix}{err.field[2:]}")
        raise UsageError(err.message, field=name, value=err.value) from None


def write_field(
    site: Site | Problem,
    stations: Sequence[Candidate],
    options: FieldOptions,
    folder: str,
    plan_file: str | None = None,
    settings: Sequence[str] | None = None,
) -> FieldPlan:
    """Make the sheet, print its summary and write its files into ``folder``; ``settings``: each station's scan
    setting where the plan chose them)."""
    from planner.field.run import field_plan
    from planner.field.sheet import write_sheet

    fp = field_plan(site, stations, options, plan_file=plan_file, settings=settings)
    print(summary(fp))
    for path in write_sheet(fp, folder):
        print(f"wrote {path}")
    return fp


def summary(fp: FieldPlan) -> str:
    """The sheet's summary as printed: route, bound, time, targets, order, and the rooms without openings."""
    from planner.field.crossing import advice
    from planner.field.storeys import stairs_line

    t = fp.time
    weak = sum(1 for lk in fp.links if lk.weak)
    walls = advice(fp.crossings)
    return "\n".join(
        [
            f"field sheet {fp.site.name}: {len(fp.order)} setups, {fp.options.mode} order from {fp.start_label}",
            f"route {fp.route_length_m:.1f} m, lower bound {fp.lower_bound_m:.1f} m ({fp.bound_method}), gap "
            f"{100 * fp.gap:.2f} %; nearest-neighbour order {fp.nearest_neighbour_m:.1f} m"
            + ("" if fp.registration_ok else "; registration order NOT honoured (shortest mode)")
            + (
                f"; stopped by the wall-clock cap of {fp.options.time_cap_s:g} s (may depend on the load)"
                if fp.capped and fp.options.time_cap_s is not None
                else ""
            ),
            (
                f"field time {t.total_s / 3600:.2f} h ({t.walking_s / 60:.0f} min walking, {t.station_s / 60:.0f} min at "
                f"stations, setting {t.setting}) in {len(t.sessions)} session(s)"
            ),
            f"targets: {len(fp.targets)}; chain links {len(fp.links)}, weak left {weak}",
            "order: " + " ".join(fp.stations[k].id for k in fp.order),
            *([stairs_line(fp)] if fp.spaces else []),
            *([walls] if walls else []),
        ]
    )


#: the suffixes of site files that are never a plan.json
SITE_SUFFIXES = (".csv", ".dxf", ".pol", ".ifc")


def _not_a_site(path: str, data: Any = None) -> None:
    """A site file given where a plan.json belongs is a usage error (exit 2), said as such: a table, drawing or
    building model by its suffix, a JSON instance by its ``zones`` without ``stations``."""
    site = Path(path).suffix.lower() in SITE_SUFFIXES or (
        isinstance(data, dict) and "zones" in data and "stations" not in data
    )
    if site:
        raise UsageError(
            f"{path} is a site file; planner field expects a plan.json written by `planner plan --out DIR` "
            f"(plan it first: planner plan {path} --out DIR --field DIR)"
        )


def cmd_field(args: argparse.Namespace) -> int:
    from planner.core.fileio import read_json
    from planner.io.plan_file import site_for_plan
    from planner.io.plan_json import check_plan_meta, read_plan_stations
    from planner.plan.problem import recorded_problem

    options = field_options(args)  # option values checked before any work
    folder = args.out or str(Path(args.plan).parent)
    if not folder.strip():
        raise UsageError("is empty: name a folder", field="--out", value=args.out)
    _not_a_site(args.plan)
    raw = read_json(args.plan)
    _not_a_site(args.plan, raw)
    meta = check_plan_meta(raw, args.plan)
    site = site_for_plan(meta, args.site, args.plan)
    stations = read_plan_stations(args.plan, site)
    settings = _plan_settings(raw, len(stations), args)
    problem = recorded_problem(site, meta)  # the plan's sight and registration: the sheet relates its own pairs
    fp = write_field(problem, stations, options, folder, plan_file=args.plan, settings=settings)
    note = numbering_note(meta, fp, args.plan, folder)
    if note:
        print(note)
    return ExitCode.OK


def numbering_note(meta: dict[str, Any], fp: FieldPlan, plan_file: str, folder: str) -> str:
    """A note where the sheet numbers the stations otherwise than ``plan_file`` records (a plan made without a
    sheet, or a sheet made again with other options): the report of the plan follows the sheet it links."""
    from planner.plan.plan_dict import StationNumbering

    recorded = StationNumbering.recorded(meta, fp.stations)
    if recorded == fp.numbering:
        return ""
    return (
        f"note: this sheet numbers the stations in its walking order, {plan_file} in {recorded.basis}; "
        f"`planner report {plan_file} --out {folder}` numbers them as this sheet does"
    )


def _plan_settings(raw: object, n: int, args: argparse.Namespace) -> list[str] | None:
    """The scan setting of each station where plan.json records them (a plan with --objective field-time or
    --max-point-spacing), unless ``--setting`` asks for one setting for all."""
    if getattr(args, "setting", None) is not None or not isinstance(raw, dict):
        return None
    rows = raw.get("stations")
    if not isinstance(rows, list) or len(rows) != n:
        return None
    settings = [row.get("setting") if isinstance(row, dict) else None for row in rows]
    return [str(s) for s in settings] if all(isinstance(s, str) for s in settings) else None
