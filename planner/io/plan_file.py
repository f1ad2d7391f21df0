"""Plans read back from plan.json: the site a plan was made for (:func:`site_for_plan`) and its outcome with
coverage and verification recomputed (:func:`outcome_from_file`)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

from planner.core.checks import path_argument
from planner.core.errors import InputError, located_in
from planner.core.fileio import read_json
from planner.coverage.stations import station_coverage
from planner.instrument.models import load_instrument
from planner.io.load import load_site
from planner.io.plan_json import RECORDED_PARAMETERS, check_plan_meta, read_plan_stations
from planner.network.check import NetworkReport
from planner.plan.options import PlanOptions
from planner.plan.outcome import Outcome
from planner.plan.problem import Problem, recorded_problem
from planner.plan.surfaces import SurfaceSetup, surface_setup
from planner.plan.verify import verify_stations
from planner.site.model import Site
from planner.site.validate import ValidationReport


def site_for_plan(meta: dict[str, Any], site_path: str | Path | None, plan_path: str, ifc: Any = None) -> Site:
    """The site a plan.json was made for, with the parameters recorded in it (``ifc``: the storeys of an IFC
    model, :class:`~planner.io.ifc_in.IfcOptions`)."""
    src = site_path or meta.get("source")
    if not src:
        raise InputError("the plan names no site file; give one with --site", file=plan_path, field="source")
    tried = (
        [Path(src)]
        if site_path
        else [Path(src), Path(plan_path).parent / src, Path(meta.get("source_resolved") or src)]
    )
    path = next((p for p in tried if p.exists()), Path(src))
    site = load_site(path, ifc=ifc)
    p = meta.get("parameters") or {}
    changes = {k: p[k] for k in RECORDED_PARAMETERS if k in p}
    if "given" in str(p.get("max_slant_range_source", "")):
        if "max_slant_range_m" not in p:
            raise InputError(
                "the plan says its slant range was given but records none",
                file=plan_path,
                field="parameters.max_slant_range_m",
            )
        changes["max_slant_range_m"] = p["max_slant_range_m"]
    with located_in(plan_path):  # the values come from the plan, not from the site file
        params = replace(site.parameters, **changes)
        if "instrument" in p:
            load_instrument(p["instrument"])
    return replace(site, parameters=params, instrument=p.get("instrument", site.instrument))


def outcome_from_file(
    plan_path: str | Path, site_path: str | Path | None = None, network: NetworkReport | None = None, ifc: Any = None
) -> Outcome:
    """The outcome of a plan.json (stations re-read, coverage and verification recomputed); ``ifc`` selects
    the storeys when the site is an IFC model."""
    path_argument(plan_path, "plan_path")
    if site_path is not None:
        path_argument(site_path, "site_path")
    name = str(plan_path)
    meta = check_plan_meta(read_json(plan_path), name)
    site = site_for_plan(meta, site_path, name, ifc)
    p = meta.get("parameters") or {}
    problem = recorded_problem(site, meta)  # the limits and registration the plan was made under, resolved once
    validation, sight, limits = problem.validation, problem.sight, problem.limits
    stations = tuple(read_plan_stations(plan_path, site))
    spacing = float(p.get("target_spacing_m", 1.0))
    _fits_in_memory(site, validation, spacing, float(p.get("grid_spacing_m", 1.0)), name)
    cov = station_coverage(sight, stations, spacing)
    verification = verify_stations(sight, stations, float(p.get("verify_spacing_m", 0.1)))
    radii = {
        s["id"]: s["tripod_radius_m"]
        for s in meta.get("stations", [])
        if isinstance(s, dict) and isinstance(s.get("tripod_radius_m"), (int, float))
    }
    return Outcome(
        site=site,
        validation=validation,
        limits=limits,
        stations=stations,
        coverage=cov,
        verification=verification,
        tripod_radius_m=radii,
        meta=meta,
        registration=problem.registration,
        network=network,
        surfaces=_surfaces(meta, problem, spacing),
    )


def _surfaces(meta: dict[str, Any], problem: Problem, spacing_m: float) -> SurfaceSetup | None:
    """The floor and ceiling patches of a plan that recorded surfaces beyond walls, made again under the recorded
    instrument height, incidence limit and target spacing (None: a walls-only plan). The report draws them on its
    map; their verification is plan.json's."""
    s = meta.get("surfaces")
    kinds = tuple(str(t) for t in (s.get("types") or ()) if t != "walls") if isinstance(s, dict) else ()
    if not kinds:
        return None
    assert isinstance(s, dict)
    theta = s.get("theta_max_floor_deg")
    options = PlanOptions(
        surfaces=("walls", *kinds),
        theta_max_floor_deg=float(theta) if isinstance(theta, (int, float)) else None,
        target_spacing_m=spacing_m,
    )
    return surface_setup(problem.site, problem.validation, options, problem.limits)


def _fits_in_memory(site: Site, validation: ValidationReport, spacing_m: float, grid_m: float, name: str) -> None:
    """The memory guard of ``planner plan`` for the spacings a plan.json records (an edited file may ask
    for pieces of a micrometre): refused naming the plan file and the field, before any coverage is built."""
    from planner.plan.memory_guard import DEFAULT_SHARE, available_memory_bytes, estimate_work

    est = estimate_work(site, spacing_m, grid_m, validation.range_limit.max_slant_range_m)
    if est.bytes > int(DEFAULT_SHARE * available_memory_bytes()):
        raise InputError(
            f"the report's coverage would not fit in memory (the coverage problem needs about {est.describe()})",
            file=name,
            field="parameters.target_spacing_m",
            value=spacing_m,
        )
