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
from planner.plan.plan_dict import PLAN_ORDER, WALKING_ORDER, StationNumbering, plan_to_dict
from planner.site.candidate import Candidate, CandidateKind, check_unique_ids
from planner.site.model import ScanSide, Site


def write_plan(plan: Plan, out_dir: Path | str, numbering: StationNumbering | None = None) -> Path:
    """Write ``out_dir/plan.json`` (the folder is created) and return its path; each station with its number and label
    in ``numbering`` (None: plan order, no field sheet)."""
    folder = Path(out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "plan.json"
    path.write_text(dumps(plan_to_dict(plan, numbering)))
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
    """One line per site parameter that ``path`` (a plan.json) records with another value than ``site`` has: the plan
    was made under other limits than it is now checked against (``verify``, ``network``, ``chain`` check it against the
    site as given, which is the point when the site is the stricter requirement)."""
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
    """The plan.json object ``planner report`` reads, its fields checked: a clear one-line error naming the file and the
    field, instead of a crash deep in the report (the plan may have been edited by hand)."""
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
    _check_numbering(meta, name)
    return meta


def _check_numbering(meta: dict[str, Any], name: str) -> None:
    """The stations' recorded numbers (:class:`~planner.plan.plan_dict.StationNumbering`): where the plan records
    them, each station has a number, together 1..N once each, and the basis is known; a plan without them is
    numbered in plan order. A station's label is its id (the ``label`` written beside it is not read back)."""
    rows = meta.get("stations")
    numbering = meta.get("numbering")
    if numbering is None or not isinstance(rows, list):
        return
    basis = numbering.get("basis") if isinstance(numbering, dict) else numbering
    if basis not in (WALKING_ORDER, PLAN_ORDER):
        raise InputError(
            f"must be '{WALKING_ORDER}' or '{PLAN_ORDER}'", file=name, field="numbering.basis", value=basis
        )
    seen: set[int] = set()
    for k, row in enumerate(rows, 1):
        if not isinstance(row, dict):
            continue
        n = row.get("number")
        if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= len(rows) or n in seen:
            what = f"an integer in 1..{len(rows)}, each number once (remove 'numbering' to number in plan order)"
            raise InputError(f"must be {what}", file=name, row=f"stations[{k}]", field="number", value=n)
        seen.add(n)
