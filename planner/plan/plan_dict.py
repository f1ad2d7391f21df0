"""A plan as the dictionary plan.json holds (:func:`plan_to_dict`): what the outcome, the report and the file writer
(:mod:`planner.io.plan_json`) all take, so the file and the figures never disagree; and each station's one number and
label (:class:`StationNumbering`), which plan.json records and every figure, map, table and export shows."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

from planner.plan.networks import storey_networks
from planner.plan.result import Plan
from planner.plan.tripod import TripodDisc
from planner.site.candidate import Candidate
from planner.site.model import Zone

#: the two ways stations are numbered: in the field sheet's walking order where one is made, else in the plan's order
WALKING_ORDER = "walking order"
PLAN_ORDER = "plan order"
_LEGENDS = {
    WALKING_ORDER: "stations numbered in walking order (the field sheet's visiting order)",
    PLAN_ORDER: "stations numbered in plan order (no field sheet was made)",
}
_S = TypeVar("_S")


@dataclass(frozen=True, kw_only=True)
class StationNumbering:
    """Each station's one number (1..N) and one label (its id), decided once and shown alike by every figure, map,
    table and export of a plan: ``ids`` are the station ids by number (``ids[0]`` is number 1); ``basis`` says how
    they were numbered (:data:`WALKING_ORDER` where a field sheet was made, else :data:`PLAN_ORDER`), and
    :attr:`legend` says it in words for each figure's or table's legend. plan.json records it (each station's
    ``number`` and ``label``, and ``numbering``), so that a report or a sheet made from the file numbers alike."""

    ids: tuple[str, ...]
    basis: str = PLAN_ORDER

    def __post_init__(self) -> None:
        if self.basis not in _LEGENDS:
            raise ValueError(f"unknown numbering basis {self.basis!r} (known: {', '.join(_LEGENDS)})")
        if len(set(self.ids)) != len(self.ids):
            raise ValueError("a station numbering names a station more than once")

    @classmethod
    def plan_order(cls, stations: Sequence[Any]) -> StationNumbering:
        """Stations numbered in the plan's order (no field sheet)."""
        return cls(ids=tuple(str(s.id) for s in stations), basis=PLAN_ORDER)

    @classmethod
    def walking(cls, stations: Sequence[Any], order: Sequence[str]) -> StationNumbering:
        """Stations numbered in the walking ``order`` (station ids), any station it leaves out after them in plan
        order; an id of ``order`` that is no station is an error."""
        ids = [str(s.id) for s in stations]
        unknown = sorted(set(order) - set(ids))
        if unknown:
            raise ValueError(f"the walking order names stations the plan does not have: {', '.join(unknown)}")
        given = set(order)
        return cls(ids=(*map(str, order), *(i for i in ids if i not in given)), basis=WALKING_ORDER)

    @classmethod
    def recorded(cls, data: Mapping[str, Any], stations: Sequence[Any]) -> StationNumbering:
        """The numbering a plan.json dictionary records for ``stations`` (its rows, in order): each row's ``number``
        and the ``numbering`` basis; plan order where the file records none (a plan written before numbers were
        recorded, or made elsewhere). :func:`planner.io.plan_json.check_plan_meta` has checked the numbers."""
        rows = data.get("stations")
        basis = (data.get("numbering") or {}).get("basis") if isinstance(data.get("numbering"), dict) else None
        if not isinstance(rows, list) or len(rows) != len(stations) or basis not in _LEGENDS:
            return cls.plan_order(stations)
        numbers = [row.get("number") if isinstance(row, dict) else None for row in rows]
        if sorted(n for n in numbers if isinstance(n, int)) != list(range(1, len(stations) + 1)):
            return cls.plan_order(stations)
        by_number = sorted(zip(numbers, (str(s.id) for s in stations)))
        return cls(ids=tuple(sid for _n, sid in by_number), basis=str(basis))

    @classmethod
    def decide(
        cls, data: Mapping[str, Any], stations: Sequence[Any], field_order: Sequence[str] | None = None
    ) -> StationNumbering:
        """The one rule: walking order where a field sheet of these stations is made (``field_order``: its station
        ids in visiting order), else the numbering the plan dictionary ``data`` records (plan order where none)."""
        ids = {str(s.id) for s in stations}
        if field_order and set(map(str, field_order)) <= ids:
            return cls.walking(stations, [str(i) for i in field_order])
        return cls.recorded(data, stations)

    def record(self, data: Mapping[str, Any]) -> dict[str, Any]:
        """A copy of the plan dictionary ``data`` with this numbering: its ``numbering`` and each station row's
        ``number`` and ``label`` (what :func:`plan_to_dict` writes)."""
        rows = [
            {**row, "number": self.number(str(row.get("id"))), "label": self.label(str(row.get("id")))}
            if isinstance(row, dict)
            else row
            for row in data.get("stations") or []
        ]
        return {**data, "numbering": self.to_dict(), "stations": rows}

    @property
    def numbers(self) -> dict[str, int]:
        """Station id to its number."""
        return {sid: k for k, sid in enumerate(self.ids, 1)}

    def number(self, station_id: str) -> int:
        """The number of a station (0 for an id the numbering does not hold)."""
        return self.numbers.get(station_id, 0)

    @staticmethod
    def label(station_id: str) -> str:
        """The label of a station: its id, the same text in every file and figure."""
        return str(station_id)

    @property
    def legend(self) -> str:
        """How the stations are numbered, in words (e.g. "stations numbered in walking order (...)")."""
        return _LEGENDS[self.basis]

    def ordered(self, stations: Sequence[_S]) -> list[_S]:
        """``stations`` (anything with an ``id``) by number; those the numbering lacks last, as given."""
        n = self.numbers
        return sorted(stations, key=lambda s: n.get(str(s.id), len(n) + 1))  # type: ignore[attr-defined]

    def to_dict(self) -> dict[str, Any]:
        """plan.json's ``numbering``: the basis, its legend and the labels by number."""
        return {"basis": self.basis, "legend": self.legend, "labels": list(self.ids)}


def plan_to_dict(plan: Plan, numbering: StationNumbering | None = None) -> dict[str, Any]:
    """The plan as plain JSON-ready data (coordinates in each zone's frame); each station with its number and label
    in ``numbering`` (None: plan order, no field sheet)."""
    numbering = numbering or StationNumbering.plan_order(plan.stations)
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
        "numbering": numbering.to_dict(),
        "stations": [
            {
                **_station(
                    s, plan.tripods[k] if plan.tripods else None, plan.hours.settings[k] if plan.hours else None
                ),
                "number": numbering.number(s.id),
                "label": numbering.label(s.id),
            }
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
    out["links"] = [list(p) for p in plan.links]  # the pairs the field sheet, network check and report relate
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
