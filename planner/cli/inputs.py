"""What the command line names, read and checked: the site with its parameter overrides, plan files and the
memory limit (shared by the commands; the output folders: :mod:`planner.cli.outputs`)."""

from __future__ import annotations

import argparse
import math
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from planner.cli.tuning import option_name
from planner.core.errors import InputError, UsageError

# Everything else loads inside the command that needs it, so that --help, --version and validate
# start without the solver, network, figure and report stacks (docs/startup.md).
if TYPE_CHECKING:
    from planner.io.dxf_in import DxfOptions
    from planner.plan.problem import Problem
    from planner.site import Site


#: each site parameter a flag overrides: the parameter, its flag, the attribute of the parsed options, and what
#: the value is (for the error that names the flag, not the parameter, when the value is refused)
SITE_FLAGS: tuple[tuple[str, str, str, str], ...] = (
    ("max_slant_range_m", "--max-range", "max_range", "a slant range S_max in metres"),
    ("theta_max_deg", "--theta-max", "theta_max", "an incidence angle limit in degrees"),
    ("overlap", "--overlap", "overlap", "a registration overlap"),
    ("sigma_req_m", "--sigma-req", "sigma_req", "a required accuracy in metres"),
    ("instrument_height_m", "--instrument-height", "instrument_height", "an instrument height in metres"),
    ("incidence_model", "--incidence-model", "incidence_model", "an incidence model"),
    ("min_standoff_m", "--standoff", "standoff", "a stand-off in metres"),
)


def refused_flag(flag: str, what: str, value: Any, message: str) -> UsageError:
    """The usage error of a flag's value that the library refused with ``message``: names the flag and the
    value as typed, then what was expected (``--max-range: -5 is not a slant range S_max in metres (expected
    > 0 and <= 10000 m)``)."""
    shown = f"{value:g}" if isinstance(value, float) else str(value)
    if message.startswith("must be "):
        rule = message.removeprefix("must be ")
        rule = f"a value {rule}" if rule.startswith("in ") else rule
        return UsageError(f"{shown} is not {what} (expected {rule})", field=flag)
    if message.startswith("not "):
        return UsageError(f"{shown} is {message}", field=flag)
    return UsageError(f"{shown} is not {what}: {message}", field=flag)


def load_with_overrides(args: argparse.Namespace) -> Site:
    """Load the site and apply the command-line parameter overrides.

    Raises
    ------
    UsageError
        An override the site's checks refuse, or an unknown ``--instrument``: named by its flag (exit 2).
    """
    from planner.io import load_site
    from planner.site.params import ClosureTolerance

    command = getattr(args, "command", None)
    tol_kw = {}
    if args.angular_tolerance is not None:
        tol_kw["angular_deg"] = args.angular_tolerance
    if args.min_relative_precision is not None:
        tol_kw["min_relative_precision"] = args.min_relative_precision
    try:
        tolerance = ClosureTolerance(**tol_kw) if tol_kw else None
    except InputError as err:
        key = "angular-tolerance" if err.field == "angular_tolerance_deg" else "min-relative-precision"
        raise refused_flag(option_name(command, key), "a closure tolerance", err.value, err.message) from None
    suffix = Path(args.site).suffix.lower()
    site = load_site(
        args.site,
        tolerance,
        crs=args.crs,
        dxf=_dxf_options(args) if suffix == ".dxf" else None,
        ifc=_ifc_options(args) if suffix == ".ifc" else None,
    )
    derive = args.theta_max == "derive"
    given = {name: getattr(args, dest) for name, _, dest, _ in SITE_FLAGS}
    given["theta_max_deg"] = None if derive else args.theta_max
    changes = {k: v for k, v in given.items() if v is not None}
    if derive:
        changes["derive_theta_max"] = True
    if args.sigma_req is not None:
        changes["drawing_scale"] = None
    try:
        p = replace(site.parameters, **changes)
        if args.scale is not None:
            p = p.with_scale(args.scale)
    except InputError as err:  # the flag the user typed, not the parameter it sets
        flags = {name: (flag, what) for name, flag, _, what in SITE_FLAGS if name in changes}
        flags["drawing_scale"] = ("--scale", "a drawing scale 1:N")
        if err.field not in flags:
            raise
        flag, what = flags[err.field]
        raise refused_flag(flag, what, args.scale if flag == "--scale" else err.value, err.message) from None
    if args.instrument:
        _check_instrument(args.instrument)
    return replace(site, parameters=p, instrument=args.instrument or site.instrument)


def _check_instrument(name: str) -> None:
    """``--instrument``: a model of ``models/`` (else a usage error naming the flag) or a TOML file (whose own
    errors name the file)."""
    from planner.instrument.models import list_instruments, load_instrument

    try:
        load_instrument(name)
    except InputError as err:
        if err.file is None and err.field == "instrument":
            known = ", ".join(list_instruments()) or "none"
            raise UsageError(f"{name} is no instrument model (known: {known})", field="--instrument") from None
        raise


def _ifc_options(args: argparse.Namespace) -> Any:
    from planner.io.ifc_in import IfcOptions

    return IfcOptions(storey=args.storey, windows=args.ifc_windows, exterior=args.exterior)


def _dxf_options(args: argparse.Namespace) -> DxfOptions:
    from planner.io.dxf_in import DxfOptions
    from planner.site import ScanSide

    flag = option_name(getattr(args, "command", None), "layer-height")
    heights = {}
    for item in args.layer_height:
        layer, _, value = item.partition("=")
        try:
            heights[layer] = float(value)
        except ValueError:
            raise UsageError("expected LAYER=HEIGHT_M", field=flag, value=item) from None
        if not (math.isfinite(heights[layer]) and heights[layer] > 0):
            raise UsageError("height must be a finite number > 0", field=flag, value=item)
    return DxfOptions(layer_heights_m=heights, default_side=ScanSide(args.dxf_side))


def guard_memory(problem: Problem) -> None:
    """The memory check of build_problem, run before the solver stacks load so that a refusal is quick."""
    from planner.plan.memory_guard import check_memory

    o = problem.options
    max_slant_range_m = problem.validation.range_limit.max_slant_range_m
    check_memory(problem.site, o.target_spacing_m, o.pool.grid_m, max_slant_range_m, o.memory_limit_bytes)


def recorded_notes(path: str, site: Any) -> None:
    """Say which limits the plan was made under that differ from the site's (the check uses the site's)."""
    from planner.io.plan_json import recorded_differences

    for line in recorded_differences(path, site):
        print(line)


def some_stations(path: str, stations: list[Any]) -> list[Any]:
    """A network needs a station (verify, by contrast, reports an empty plan as 0 % covered)."""
    if not stations:
        raise InputError("the plan has no stations: there is no network to check", file=path, field="stations", value=0)
    return stations
