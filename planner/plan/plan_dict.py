"""A plan as the dictionary plan.json holds (:func:`plan_to_dict`): what the outcome, the report and the file writer
(:mod:`planner.io.plan_json`) all take, so the file and the figures never disagree."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from planner.plan.networks import storey_networks
from planner.plan.result import Plan
from planner.plan.tripod import TripodDisc
from planner.site.candidate import Candidate
from planner.site.model import Zone


def plan_to_dict(plan: Plan) -> dict[str, Any]:
    """The plan as plain JSON-ready data (coordinates in each zone's frame)."""
    site, r = plan.site, plan.result
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
        # the steps the user's wall-clock cap cut (empty: only counted work stopped it, the same plan under any load)
        "wall_cap_hit": wall_cap_hit(r.info),
        "backend": r.backend,
        "counts": {"inside": sides.get("inside", 0), "outside": sides.get("outside", 0), "total": len(plan.stations)},
        "parameters": _parameters(plan),
        "presolve": r.info.get("presolve"),
        "solver": {k: v for k, v in r.info.items() if k != "presolve"},
        "registration": _registration(plan),
        "problem": plan.problem_size,
        # the pool the plan was chosen from and its fingerprint: the best plans known are compared only on the same
        # pool (None: not recorded)
        "pool": plan.pool.to_dict() if plan.pool is not None else None,
        # what every number above was computed under: the limits, the registration rule and scope, the strategy
        "resolved": plan.problem.to_dict(),
        "zones": [_zone(z) for z in site.zones],
        "stations": [
            _station(s, plan.tripods[k] if plan.tripods else None, plan.hours.settings[k] if plan.hours else None)
            for k, s in enumerate(plan.stations)
        ],
        "verification": plan.verification.to_dict(),
        "log": list(plan.log),
        # floors and ceilings, only where the plan has them
        **({"surfaces": plan.surfaces.to_dict()} if plan.surfaces is not None else {}),
        # scan settings, set-up + scan time, point spacing, only where asked
        **({"hours": plan.hours.to_dict()} if plan.hours is not None else {}),
    }


def _parameters(plan: Plan) -> dict[str, Any]:
    """The parameters and options the plan was made under (the MILP's only for a MILP plan)."""
    o, r, p = plan.options, plan.result, plan.site.parameters
    return {
        "instrument": plan.validation.scanner.name,
        "max_slant_range_m": plan.validation.range_limit.max_slant_range_m,
        "max_slant_range_source": plan.validation.range_limit.source,
        "theta_max_deg": p.theta_max_deg,
        "overlap": p.overlap,
        "sigma_req_m": p.sigma_req_m,
        "instrument_height_m": p.instrument_height_m,
        "target_spacing_m": o.target_spacing_m,
        "grid_spacing_m": o.pool.grid_m,
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
    }


def _registration(plan: Plan) -> dict[str, Any]:
    """The registration check: connected or not, the components of each group, the share it was checked at (planned
    under, else the site's) and, only where the site has stairs, the storeys joined into one network."""
    out = {"connected": plan.connected, "components": plan.registration, "overlap": plan.problem.checked_rule.overlap}
    if plan.site.stairs:
        out["networks"] = [n.to_dict() for n in storey_networks(plan.site, plan.registration)]
    return out


def _zone(z: Zone) -> dict[str, Any]:
    return {
        "id": z.id,
        "side": z.scan_side.value,
        "frame": z.frame,
        "polygon": [list(v) for v in z.vertices],
        **({"holes": [[list(v) for v in r] for r in z.holes]} if z.holes else {}),
    }


def wall_cap_hit(info: dict[str, Any]) -> list[str]:
    """The steps of a run that the user's wall-clock cap cut, from its result's ``info``: the MILP (``milp``), pricing
    (``pricing``), or the tiles, bound and windows of a tiled run by name."""
    tiled = info.get("wall_cap_hit")
    steps = [str(s) for s in tiled] if isinstance(tiled, list) else []
    steps += ["milp"] if (info.get("work") or {}).get("wall_cap_hit") else []
    steps += ["pricing"] if (info.get("pricing") or {}).get("wall_cap_hit") else []
    return steps


def _station(s: Candidate, disc: TripodDisc | None, setting: str | None = None) -> dict[str, Any]:
    out: dict[str, Any] = {"id": s.id, "zone": s.zone, "side": s.side.value, "x": s.x, "y": s.y, "kind": s.kind.value}
    if setting is not None:
        out["setting"] = setting
    if disc is not None:
        out["tripod_radius_m"] = disc.radius_m
        out["tripod_centre"] = list(disc.centre)
        out["height_tolerance_m"] = (
            None if disc.height_tolerance_m != disc.height_tolerance_m else disc.height_tolerance_m
        )
    return out
