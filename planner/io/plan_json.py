"""plan.json: writing a plan, and reading the stations of any plan (also one made elsewhere) for verify."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from planner.core.checks import SAMPLING_M
from planner.core.errors import InputError
from planner.core.fileio import read_json, to_float
from planner.core.text import dumps
from planner.plan import Plan
from planner.plan.tripod import TripodDisc
from planner.site.candidate import Candidate, CandidateKind, check_unique_ids
from planner.site.model import ScanSide, Site


def plan_to_dict(plan: Plan) -> dict[str, Any]:
    """The plan as plain JSON-ready data (coordinates in each zone's frame)."""
    site, o, r = plan.site, plan.options, plan.result
    p = site.parameters
    sides = plan.count_by_side()
    return {
        "instance": site.name,
        "source": site.source,
        "source_resolved": str(Path(site.source).resolve()) if site.source else None,
        "method": r.method,
        "status": r.status.value,
        "objective": r.objective,
        "bound": r.bound,
        "gap": r.gap,
        "bound_scope": r.info.get("bound_scope", "pool" if r.bound is not None else None),
        "plane_bound": r.info.get("plane_bound"),
        # every plan connected under the overlap rule, stations anywhere (zone registration; None: not formed)
        "connected_plane_bound": r.info.get("connected_plane_bound"),
        "connected_plane": r.info.get("connected_plane"),  # its parts per zone-side, patch side and time
        # the MILP's own bound, over the candidate pool; and what a plane bound assumes (None without pricing)
        "pool_bound": r.info.get("pool_bound", r.bound if r.method == "milp" else None),
        "certificate": r.info.get("certificate"),
        "time_s": r.time_s,
        "time_covers": plan.time_label,
        # the steps the user's wall-clock cap cut (empty: only counted work stopped the run: the same plan under
        # any load)
        "wall_cap_hit": wall_cap_hit(r.info),
        "backend": r.backend,
        "counts": {"inside": sides.get("inside", 0), "outside": sides.get("outside", 0), "total": len(plan.stations)},
        "parameters": {
            "instrument": plan.validation.scanner.name,
            "max_slant_range_m": plan.validation.range_limit.max_slant_range_m,
            "max_slant_range_source": plan.validation.range_limit.source,
            "theta_max_deg": p.theta_max_deg,
            "overlap": p.overlap,
            "sigma_req_m": p.sigma_req_m,
            "instrument_height_m": p.instrument_height_m,
            "target_spacing_m": o.target_spacing_m,
            "grid_spacing_m": o.pool.grid_spacing_m,
            "field_samples": o.pool.field_samples,
            "seed": o.pool.seed,
            "incidence": "3d" if o.incidence_3d else "horizontal",
            "precision": o.precision,
            "precision_mode": "combined" if o.combined else "single",
            "incidence_model": p.incidence_model,
            "min_standoff_m": p.min_standoff_m,
            "verify_spacing_m": o.verify_spacing_m,
            "milp": None
            if r.method != "milp"
            else {
                "backend": o.milp.backend,
                "time_limit_s": o.milp.time_limit_s,
                **{k: v for k, v in o.milp.limits.items() if k != "wall_cap_s"},
                "seed": o.milp.seed,
                "threads": o.milp.threads,
                "k": o.milp.k,
                "precision": o.milp.precision,
                "min_shared_m": o.milp.rule.min_shared_m if o.milp.rule else None,
                "max_link_m": o.milp.rule.max_link_m if o.milp.rule else None,
            },
        },
        "presolve": r.info.get("presolve"),
        "solver": {k: v for k, v in r.info.items() if k != "presolve"},
        "registration": {
            "connected": plan.connected,
            "components": plan.registration,
            # the share the registration was checked at (planned under, else the site's)
            "overlap": plan.problem.checked_rule.overlap,
        },
        "problem": plan.problem_size,
        "zones": [
            {
                "id": z.id,
                "side": z.scan_side.value,
                "frame": z.frame,
                "polygon": [list(v) for v in z.vertices],
                **({"holes": [[list(v) for v in r] for r in z.holes]} if z.holes else {}),
            }
            for z in site.zones
        ],
        "stations": [_station(s, plan.tripods[k] if plan.tripods else None) for k, s in enumerate(plan.stations)],
        "verification": plan.verification.to_dict(),
        "log": list(plan.log),
    }


def wall_cap_hit(info: dict[str, Any]) -> list[str]:
    """The steps of a run that the user's wall-clock cap cut, from its result's ``info``: the MILP (``milp``),
    pricing (``pricing``), or the tiles, bound and windows of a tiled run by name."""
    tiled = info.get("wall_cap_hit")
    steps = [str(s) for s in tiled] if isinstance(tiled, list) else []
    steps += ["milp"] if (info.get("work") or {}).get("wall_cap_hit") else []
    steps += ["pricing"] if (info.get("pricing") or {}).get("wall_cap_hit") else []
    return steps


def _station(s: Candidate, disc: TripodDisc | None) -> dict[str, Any]:
    out: dict[str, Any] = {"id": s.id, "zone": s.zone, "side": s.side.value, "x": s.x, "y": s.y, "kind": s.kind.value}
    if disc is not None:
        out["tripod_radius_m"] = disc.radius_m
        out["tripod_centre"] = list(disc.centre)
        out["height_tolerance_m"] = (
            None if disc.height_tolerance_m != disc.height_tolerance_m else disc.height_tolerance_m
        )
    return out


def write_plan(plan: Plan, out_dir: Path | str) -> Path:
    """Write ``out_dir/plan.json`` (the folder is created) and return its path."""
    folder = Path(out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "plan.json"
    path.write_text(dumps(plan_to_dict(plan)))
    return path


def read_plan_stations(path: Path | str, site: Site) -> list[Candidate]:
    """The stations of a plan file: a JSON object with ``stations`` [{id, zone, side, x, y, kind?}]."""
    name = str(path)
    data = read_json(path)
    rows = data.get("stations") if isinstance(data, dict) else None
    if not isinstance(rows, list):
        raise InputError("a plan needs a list 'stations'", file=name, field="stations")
    zones = {z.id: z for z in site.zones}
    out = []
    for k, row in enumerate(rows, 1):
        where: dict[str, Any] = dict(file=name, row=f"stations[{k}]")
        if not isinstance(row, dict):
            raise InputError("must be an object", **where)
        zone = row.get("zone")
        if zone not in zones:
            raise InputError("names no zone of the site", **where, field="zone", value=zone)
        try:
            side = ScanSide(row.get("side"))
        except ValueError:
            side = None
        if side not in zones[zone].scan_side.sides:
            raise InputError(
                f"zone {zone} is scanned {zones[zone].scan_side.value}", **where, field="side", value=row.get("side")
            )
        try:
            kind = CandidateKind(row.get("kind", "grid"))
        except ValueError:
            raise InputError("unknown station kind", **where, field="kind", value=row.get("kind")) from None
        x, y = (to_float(row.get(c), field=c, **where) for c in ("x", "y"))
        out.append(Candidate(str(row.get("id", f"S{k}")), zone, side, zones[zone].frame, x, y, kind))
    check_unique_ids(out, row="stations[{}]", file=name)
    return out


#: the site parameters a plan.json records (``report`` plans under them again), and the option setting each
RECORDED_PARAMETERS = {
    "theta_max_deg": "--theta-max",
    "overlap": "--overlap",
    "sigma_req_m": "--sigma-req",
    "instrument_height_m": "--instrument-height",
    "incidence_model": "--incidence-model",
    "min_standoff_m": "--standoff",
}


def recorded_differences(path: Path | str, site: Site) -> list[str]:
    """One line per site parameter that ``path`` (a plan.json) records with another value than ``site`` has:
    the plan was made under other limits than it is now checked against (``verify``, ``network``, ``chain``
    check it against the site as given, which is the point when the site is the stricter requirement)."""
    data = read_json(path)
    recorded = data.get("parameters") if isinstance(data, dict) else None
    if not isinstance(recorded, dict):
        return []
    now = {key: getattr(site.parameters, key) for key in RECORDED_PARAMETERS} | {"instrument": site.instrument}
    out = []
    for key, flag in (RECORDED_PARAMETERS | {"instrument": "--instrument"}).items():
        was = recorded.get(key)
        if key in recorded and was != now[key] and now[key] is not None:
            out.append(
                f"note: {path} was made with {key} = {was} (checked here: {now[key]}); "
                f"give {flag} {was} to check it under its own limits"
            )
    return out


#: plan.json fields ``planner report`` reads back: (key, check, what it must be)
_POSITIVE = (
    lambda v: isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0,
    "a number > 0",
)
_SAMPLING = (
    lambda v: _POSITIVE[0](v) and SAMPLING_M[0] <= v <= SAMPLING_M[1],
    f"a number of metres in [{SAMPLING_M[0]:g}, {SAMPLING_M[1]:g}], as the command line takes",
)
_PARAMETER_CHECKS: dict[str, tuple[Any, str]] = {
    "target_spacing_m": _POSITIVE,
    "verify_spacing_m": _SAMPLING,
    "grid_spacing_m": _POSITIVE,
    "seed": (lambda v: isinstance(v, int) and not isinstance(v, bool) and v >= 0, "an integer >= 0"),
    "instrument": (lambda v: isinstance(v, str), "an instrument name"),
    "incidence": (lambda v: v in ("horizontal", "3d"), "'horizontal' or '3d'"),
    "precision": (lambda v: isinstance(v, bool), "true or false"),
    "precision_mode": (lambda v: v in ("single", "combined"), "'single' or 'combined'"),
    "milp": (lambda v: isinstance(v, dict), "an object"),
}


def check_plan_meta(meta: Any, name: str) -> dict[str, Any]:
    """The plan.json object ``planner report`` reads, its fields checked: a clear one-line error naming the
    file and the field, instead of a crash deep in the report (the plan may have been edited by hand)."""
    if not isinstance(meta, dict):
        raise InputError("a plan must be a JSON object", file=name)
    for key in ("parameters", "counts", "registration"):
        if meta.get(key) is not None and not isinstance(meta[key], dict):
            raise InputError("must be an object", file=name, field=key, value=meta[key])
    for key in ("source", "source_resolved"):  # the site file's path
        if meta.get(key) is not None and not isinstance(meta[key], str):
            raise InputError("must be a file path (text) or null", file=name, field=key, value=meta[key])
    for key, value in (meta.get("parameters") or {}).items():
        ok, what = _PARAMETER_CHECKS.get(key, (None, ""))
        if ok is not None and value is not None and not ok(value):
            raise InputError(f"must be {what}", file=name, field=f"parameters.{key}", value=value)
    for key in ("bound", "gap", "time_s"):
        value = meta.get(key)
        if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float))):
            raise InputError("must be a number or null", file=name, field=key, value=value)
    return meta
