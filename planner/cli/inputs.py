"""What the command line names, read and checked: the site with its parameter overrides, output folders,
plan files and the memory limit (shared by the commands)."""

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


def load_with_overrides(args: argparse.Namespace) -> Site:
    """Load the site and apply the command-line parameter overrides."""
    from planner.io import load_site
    from planner.site.params import ClosureTolerance

    tol_kw = {}
    if args.angular_tolerance is not None:
        tol_kw["angular_deg"] = args.angular_tolerance
    if args.min_relative_precision is not None:
        tol_kw["min_relative_precision"] = args.min_relative_precision
    suffix = Path(args.site).suffix.lower()
    site = load_site(
        args.site,
        ClosureTolerance(**tol_kw) if tol_kw else None,
        crs=args.crs,
        dxf=_dxf_options(args) if suffix == ".dxf" else None,
        ifc=_ifc_options(args) if suffix == ".ifc" else None,
    )
    p = site.parameters
    derive = args.theta_max == "derive"
    changes = {
        k: v
        for k, v in {
            "max_slant_range_m": args.max_range,
            "theta_max_deg": None if derive else args.theta_max,
            "overlap": args.overlap,
            "sigma_req_m": args.sigma_req,
            "instrument_height_m": args.instrument_height,
            "incidence_model": args.incidence_model,
            "min_standoff_m": args.standoff,
            "derive_theta_max": derive or None,
        }.items()
        if v is not None
    }
    if args.sigma_req is not None:
        changes["drawing_scale"] = None
    p = replace(p, **changes)
    if args.scale is not None:
        p = p.with_scale(args.scale)
    return replace(site, parameters=p, instrument=args.instrument or site.instrument)


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
    check_memory(problem.site, o.target_spacing_m, o.pool.grid_spacing_m, max_slant_range_m, o.memory_limit_bytes)


def memory_limit(args: argparse.Namespace) -> int | None:
    from planner.plan.memory_guard import parse_memory

    return parse_memory(args.memory_limit) if args.memory_limit else None


def usable_folder(flag: str, folder: str | None) -> None:
    """An output folder given on the command line: it is (or can be made) a folder, else a usage error."""
    if folder is None:
        return
    if not folder.strip():
        raise UsageError("is empty: name a folder", field=flag, value=folder)
    try:
        Path(folder).mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UsageError(
            f"cannot be used as an output folder ({exc.strerror or exc})", field=flag, value=folder
        ) from None


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
