"""``field.json``: the field sheet as one dictionary (:func:`to_dict`), which the sheet writes, the report reads back
(:func:`planner.report.site_map.read_field_sheet`) and the site maps of both pages draw their route and targets from
(:func:`planner.figures.webmap.field_layers`); and the setup table, shared by field.html, field.csv, field.json and
field.pdf: one row per setup in visiting order (:data:`HEADER`, :func:`rows`) and the totals line (:func:`totals`)."""

from __future__ import annotations

from dataclasses import asdict
from typing import Any

from planner import __version__
from planner.field.crossing import advice, closed_parts
from planner.field.run import FieldPlan
from planner.field.spread import MIN_ANGLE_DEG, MIN_SPREAD_M
from planner.field.storeys import climbs

HEADER = (
    "no.",
    "station",
    "x m",
    "y m",
    "zone",
    "side",
    "instrument height m",
    "scan setting",
    "walk m",
    "minutes",
    "targets seen",
    "session",
)


def rows(fp: FieldPlan) -> list[list[Any]]:
    """One row per setup in visiting order (the columns of :data:`HEADER`): "no." is the station's number and
    "station" its label (:attr:`FieldPlan.numbering <planner.field.run.FieldPlan.numbering>`)."""
    out = []
    numbering = fp.numbering
    for setup, k in zip(fp.time.setups, fp.order):
        s = fp.stations[k]
        where = [
            numbering.number(s.id),
            numbering.label(s.id),
            round(s.x, 3),
            round(s.y, 3),
            s.zone,
            s.side.value,
            fp.instrument_height_m,
        ]
        time = [setup.setting or fp.time.setting, round(setup.walk_m, 1), round(setup.total_s / 60.0, 1)]
        out.append(where + time + [" ".join(fp.targets_of(s.id)), setup.session])
    return out


def totals(fp: FieldPlan) -> list[Any]:
    """The totals under the table, in the columns of :data:`HEADER` (blank where nothing adds up)."""
    t = fp.time
    sums = [round(fp.route_length_m, 1), round(t.total_s / 60.0, 1), f"{len(fp.targets)} targets", len(t.sessions)]
    return [f"total: {len(fp.order)} setups", *[""] * 7, *sums]


#: field.json's names of the fields of a :class:`~planner.field.targets.Link`
_LINK_KEYS = {
    "places": "target_places",
    "reason": "weak_reason",
    "spread_m": "target_spread_m",
    "min_angle_deg": "target_min_angle_deg",
    "spread_note": "target_geometry_note",
}


def _record(obj: Any, **names: str) -> dict[str, Any]:
    """A dataclass as a record of field.json: its fields in order (tuples as lists), ``names`` renaming some."""
    return {names.get(k, k): list(v) if isinstance(v, tuple) else v for k, v in asdict(obj).items()}


def to_dict(fp: FieldPlan) -> dict[str, Any]:
    """field.json: the order, route, bound, field time, setups, targets, links and legs through walls of ``fp``
    (plain numbers, text and lists: :func:`planner.core.text.dumps` writes it)."""
    o = fp.options
    return {
        "instance": fp.site.name,
        "mode": o.mode,
        "closed": o.closed,
        "start": fp.start_label,
        "start_xy": list(fp.start_xy),
        "order": [fp.stations[k].id for k in fp.order],
        "numbering": fp.numbering.to_dict(),
        "route_length_m": fp.route_length_m,
        "lower_bound_m": fp.lower_bound_m,
        "bound_method": fp.bound_method,
        "bound_scope": fp.certified.scope if fp.certified else "shortest route",
        "bounds": {m: b for m, b in fp.certified.bounds} if fp.certified else {},
        "gap": fp.gap,
        "nearest_neighbour_m": fp.nearest_neighbour_m,
        "registration_order_honoured": fp.registration_ok,
        "search_capped": fp.capped,
        "legs": [[list(p) for p in leg] for leg in fp.legs],
        "field_time_s": fp.time.total_s,
        "time": fp.time.to_dict(),
        "sessions": fp.time.to_dict()["sessions"],
        "setups": [dict(zip(HEADER, r)) for r in rows(fp)],
        "targets": [_record(t) for t in fp.targets],
        "links": [_record(lk, **_LINK_KEYS) for lk in fp.links],
        "target_geometry": {"min_spread_m": MIN_SPREAD_M, "min_angle_deg": MIN_ANGLE_DEG},
        "legs_crossing_walls": [_record(c, start="from", end="to") for c in fp.crossings],
        "wall_crossing": "straight line from setup to setup, through the walls it meets",
        "no_opening_between": list(closed_parts(fp.crossings)),
        "walls_advice": advice(fp.crossings),
        "instrument_height_m": fp.instrument_height_m,
        "solve_s": fp.solve_s,
        "version": __version__,
    } | (_storeys(fp) if fp.spaces else {})


def _storeys(fp: FieldPlan) -> dict[str, Any]:
    """Across storeys (:mod:`planner.field.storeys`): the frames walked through, each leg's points' frames, the
    stair legs."""
    return {
        "frames": [sp.frame for sp in fp.spaces],
        "start_frame": fp.space.frame,
        "station_frames": {s.id: s.frame for s in fp.stations},
        "leg_frames": [list(f) for f in fp.leg_frames],
        "stair_legs": [
            {"leg": k, "stair": f.stair, "way": climbs(f, fp.leg_frames[k])}
            | _record(f, lower="lower_frame", upper="upper_frame")
            | {"length_m": f.length_m}
            for k, f in fp.stair_legs
        ],
        "stair_leg_length": "run in plan (foot to head) plus rise (z_max - z_min), timed at the walking speed",
    }
