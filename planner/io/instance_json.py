"""Reader of the JSON instance format (documented in docs/instance-format.md).

Lengths carry their unit in the key (``sigma_req_mm`` or ``sigma_req_m``); unknown keys are refused so that a typo never
silently drops a setting. Only ``json`` is used to parse: nothing in a file is ever evaluated.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

from planner.core.errors import InputError
from planner.core.fileio import read_json, to_float
from planner.instrument.accuracy import ErrorBudget
from planner.io.json_reader import InstanceReader
from planner.io.table_csv import NUMBER_COLUMNS, read_table_csv
from planner.io.tables import SIDE_FIELDS, VERTEX_FIELDS, zone_from_table
from planner.site.geometry import as_vertices, signed_area
from planner.site.model import ControlPoint, Correction, NoGoArea, Obstacle, ScanSide, Site, Zone
from planner.site.params import DEFAULT_INSTRUMENT, MAX_HEIGHT_M, ClosureTolerance, Parameters
from planner.site.traverse import AcceptedMisclosure, TableRow, ZoneTable
from planner.site.zone_extras import place_and_open

TOP_KEYS = set(
    "format name description source instrument parameters closure_tolerance zones obstacles no_go boundary "
    "control_points corrections accepted_misclosures placements openings assembly".split()
)
FORMAT = "tls-planner/1"


def load_instance_json(path: Path | str) -> Site:
    """Read a JSON instance into a :class:`Site` (zones closed and adjusted)."""
    r = InstanceReader(Path(path))
    data = read_json(r.path)
    data = r.obj(data, "instance", TOP_KEYS)
    if "format" in data and data["format"] != FORMAT:
        raise r.fail(f"unsupported format (this reader knows {FORMAT})", field="format", value=data["format"])
    try:
        params = _parameters(r, data.get("parameters", {}))
        tol_data = r.obj(
            data.get("closure_tolerance", {}), "closure_tolerance", {"angular_deg", "min_relative_precision"}
        )
        tolerance = ClosureTolerance(**{k: to_float(v, field=k, file=r.file) for k, v in tol_data.items()})
        corrections = tuple(_correction(r, c, k) for k, c in enumerate(r.items(data, "corrections"), 1))
        accepted = tuple(_accepted(r, a, k) for k, a in enumerate(r.items(data, "accepted_misclosures"), 1))
        zones = _zones(r, r.items(data, "zones"), tolerance, corrections, accepted)
        _check_references(r, zones, corrections, accepted)
        zones = place_and_open(r, zones, data.get("placements", {}), r.items(data, "openings"))
        return Site(
            name=data.get("name", r.path.stem),
            zones=zones,
            parameters=params,
            instrument=r.text(data, "instrument", DEFAULT_INSTRUMENT),
            obstacles=tuple(_obstacle(r, o, k) for k, o in enumerate(r.items(data, "obstacles"), 1)),
            no_go_areas=tuple(_no_go(r, o, k) for k, o in enumerate(r.items(data, "no_go"), 1)),
            boundary=r.polygon(data["boundary"], "boundary", "boundary") if data.get("boundary") is not None else None,
            control_points=tuple(_control(r, c, k) for k, c in enumerate(r.items(data, "control_points"), 1)),
            corrections=corrections,
            accepted_misclosures=accepted,
            source=r.file,
        )
    except InputError as exc:
        raise exc.located(r.file) from None


PARAM_KEYS = set(
    "theta_max_deg overlap sigma_req_m sigma_req_mm drawing_scale sigma_0_m sigma_0_mm centring_m centring_mm "
    "graphical_m graphical_mm instrument_height_m max_slant_range_m incidence_model min_standoff_m instrument_height_span_m".split()
)


def _parameters(r: InstanceReader, raw: Any) -> Parameters:
    d = r.obj(raw, "parameters", PARAM_KEYS)
    base = Parameters()
    budget = ErrorBudget(
        sigma_0_m=r.length(d, "sigma_0", base.budget.sigma_0_m),
        centring_m=r.length(d, "centring", base.budget.centring_m),
        graphical_m=r.length(d, "graphical", base.budget.graphical_m),
    )
    sigma_req = r.length(d, "sigma_req", None)
    if sigma_req is not None and d.get("drawing_scale") is not None:
        raise r.fail("give sigma_req or drawing_scale, not both", field="drawing_scale", value=d["drawing_scale"])
    derive = d.get("theta_max_deg", 0) in (None, "derive")  # theta_max follows from sigma_req
    params = Parameters(
        theta_max_deg=r.num(d, "theta_max_deg") if "theta_max_deg" in d and not derive else base.theta_max_deg,
        derive_theta_max=derive,
        incidence_model=str(d.get("incidence_model", base.incidence_model)),
        min_standoff_m=r.num(d, "min_standoff_m") if "min_standoff_m" in d else base.min_standoff_m,
        instrument_height_span_m=(
            r.num(d, "instrument_height_span_m") if "instrument_height_span_m" in d else base.instrument_height_span_m
        ),
        overlap=r.num(d, "overlap") if "overlap" in d else base.overlap,
        sigma_req_m=sigma_req if sigma_req is not None else base.sigma_req_m,
        budget=budget,
        instrument_height_m=r.length(d, "instrument_height", base.instrument_height_m),
        max_slant_range_m=r.length(d, "max_slant_range", None),
    )
    if d.get("drawing_scale") is not None:
        params = params.with_scale(d["drawing_scale"])
    return params


def _zones(
    r: InstanceReader,
    entries: list[Any],
    tolerance: ClosureTolerance,
    corrections: tuple[Correction, ...],
    accepted: tuple[AcceptedMisclosure, ...],
) -> tuple[Zone, ...]:
    if not entries:
        raise r.fail("an instance needs at least one zone", field="zones", value=0)
    tables: list[ZoneTable] = []
    zones: list[Zone | None] = []
    levels: list[tuple[float, float | None]] = []  # floor_level_m, ceiling_height_m of each zone
    for k, entry in enumerate(entries, 1):
        if isinstance(entry, dict) and "table_csv" in entry:
            e = r.obj(entry, "zones entry", {"table_csv", "zones"}, row=f"zones[{k}]")
            name = r.text(e, "table_csv")
            if not (r.path.parent / name).is_file():  # a folder, or nothing: name the instance's entry
                raise r.fail("names no file beside the instance", row=f"zones[{k}]", field="table_csv", value=name)
            found = read_table_csv(r.path.parent / name)
            wanted = e.get("zones")
            if wanted is not None and (not isinstance(wanted, list) or not all(isinstance(w, str) for w in wanted)):
                raise r.fail("must be a list of the CSV's zone names", row=f"zones[{k}]", field="zones", value=wanted)
            if wanted is not None:
                missing = sorted(set(wanted) - {t.zone for t in found})
                if missing:
                    raise r.fail("zone not in the CSV", zone=missing[0], field="zones")
                found = [t for t in found if t.zone in wanted]
            tables += found
            zones += [None] * len(found)
            levels += [(0.0, None)] * len(found)  # a table CSV: floor at 0, no ceiling
        elif isinstance(entry, dict) and "table" in entry:
            tables.append(_inline_table(r, entry, k))
            zones.append(None)
            levels.append(_levels(r, entry, tables[-1].zone))
        else:
            zones.append(_coordinate_zone(r, entry, k))
            levels.append((0.0, None))  # read by _coordinate_zone itself
    table_iter = iter(tables)
    result = []
    for z, given in zip(zones, levels):
        if z is None:
            t = next(table_iter)
            acc = next((a for a in accepted if a.zone == t.zone), None)
            z = zone_from_table(t, tolerance, [c for c in corrections if c.zone == t.zone], acc)
            if given != (0.0, None):
                z = replace(z, floor_level_m=given[0], ceiling_height_m=given[1])
        result.append(z)
    return tuple(result)


LEVEL_KEYS = {"floor_level_m", "ceiling_height_m"}


def _levels(r: InstanceReader, e: dict[str, Any], zone: str) -> tuple[float, float | None]:
    """The zone's ``floor_level_m`` (default 0) and ``ceiling_height_m`` (default and ``null``: no ceiling); the zone
    checks their ranges."""
    floor = r.num(e, "floor_level_m", zone=zone) if "floor_level_m" in e else 0.0
    ceiling = r.num(e, "ceiling_height_m", zone=zone) if e.get("ceiling_height_m") is not None else None
    return floor, ceiling


def _inline_table(r: InstanceReader, entry: dict[str, Any], k: int) -> ZoneTable:
    e = r.obj(entry, "zones entry", {"id", "scan_side", "table"} | LEVEL_KEYS, row=f"zones[{k}]")
    zone = r.text(e, "id")
    side = _scan_side(r, e, zone)
    rows = []
    for i, raw in enumerate(e["table"] if isinstance(e["table"], list) else [], 1):
        d = r.obj(raw, "table row", set(NUMBER_COLUMNS) | {"index"}, zone=zone, row=i)
        index = r.whole(d, "index", zone=zone, row=i) if "index" in d else i
        rows.append(TableRow(index=index, **{c: r.num(d, c, zone=zone, row=i) for c in NUMBER_COLUMNS}))  # type: ignore[arg-type]
    rows.sort(key=lambda t: t.index)
    if [t.index for t in rows] != list(range(1, len(rows) + 1)):
        raise r.fail(f"indices must run 1..{len(rows)}", zone=zone, field="index")
    return ZoneTable(zone=zone, scan_side=side.value, rows=tuple(rows), file=r.file)


def _scan_side(r: InstanceReader, e: dict[str, Any], zone: str) -> ScanSide:
    try:
        return ScanSide(e.get("scan_side"))
    except ValueError:
        raise r.fail(
            "must be inside, outside or both", zone=zone, field="scan_side", value=e.get("scan_side")
        ) from None


def _coordinate_zone(r: InstanceReader, entry: Any, k: int) -> Zone:
    keys = {"id", "scan_side", "coordinates", "vertex_heights_m", "height_m", "wall_heights_m", "holes"} | LEVEL_KEYS
    e = r.obj(entry, "zones entry", keys, row=f"zones[{k}]")
    zone = r.text(e, "id")
    side = _scan_side(r, e, zone)
    xy = as_vertices(e.get("coordinates"), what="coordinates", zone=zone)
    n = len(xy)
    if "vertex_heights_m" in e and "height_m" in e:  # two values, one would be dropped silently
        raise r.fail("give vertex_heights_m or height_m, not both", zone=zone, field="height_m", value=e["height_m"])
    if "vertex_heights_m" in e:
        raw = _per_vertex(r, e, "vertex_heights_m", n, zone)
        heights = [to_float(h, field="vertex_heights_m", file=r.file, zone=zone, row=i) for i, h in enumerate(raw, 1)]
    else:  # checked here, named as written (the zone would call it its vertex heights)
        heights = [_height(r, r.num(e, "height_m", zone=zone), "height_m", zone=zone)] * n
    printed: list[float | None] = [None] * n
    if "wall_heights_m" in e:
        printed = [_wall_height(r, h, zone, i) for i, h in enumerate(_per_vertex(r, e, "wall_heights_m", n, zone), 1)]
    notes: tuple[str, ...] = ()
    if n >= 3 and signed_area(xy) < 0:
        # keep vertex 1; reversed walk: new wall j joins given vertices -j and -j-1, i.e. given wall -j-1
        order = [(-j) % n for j in range(n)]
        xy, heights = xy[order], [heights[i] for i in order]
        printed = [printed[(-j - 1) % n] for j in range(n)]
        notes = ("given clockwise; stored counter-clockwise from the same first vertex",)
    holes = [_hole(r, h, zone, j) for j, h in enumerate(e.get("holes") or [], 1)]
    floor, ceiling = _levels(r, e, zone)
    return Zone(
        id=zone,
        scan_side=side,
        vertices=tuple(map(tuple, xy.tolist())),
        vertex_heights_m=tuple(heights),
        printed_wall_heights_m=tuple(printed) if any(p is not None for p in printed) else (),
        notes=notes,
        holes=tuple(ring for ring, _ in holes),
        hole_heights_m=tuple(hs for _, hs in holes),
        floor_level_m=floor,
        ceiling_height_m=ceiling,
    )


def _per_vertex(r: InstanceReader, e: dict[str, Any], key: str, n: int, zone: str) -> list[Any]:
    """``e[key]``, a list of one value per vertex."""
    raw = e[key]
    if not isinstance(raw, list) or len(raw) != n:
        raise r.fail(f"needs a list of {n} heights", zone=zone, field=key)
    return raw


def _height(r: InstanceReader, h: float, field: str, **where: Any) -> float:
    """``h``, a height > 0 and <= MAX_HEIGHT_M."""
    if not 0 < h <= MAX_HEIGHT_M:
        raise r.fail(f"must be a height > 0 and <= {MAX_HEIGHT_M:g} m", **where, field=field, value=h)
    return h


def _wall_height(r: InstanceReader, raw: Any, zone: str, wall: int) -> float:
    """A printed wall height, checked as a table's ``wall_height_m`` (-3 or 0 is no height)."""
    where: dict[str, Any] = dict(zone=zone, row=f"wall {wall}")
    return _height(r, to_float(raw, field="wall_heights_m", file=r.file, **where), "wall_heights_m", **where)


def _hole(
    r: InstanceReader, entry: Any, zone: str, j: int
) -> tuple[tuple[tuple[float, float], ...], tuple[float, ...]]:
    """A free-standing block inside the zone: {coordinates, height_m}; stored clockwise."""
    e = r.obj(entry, "holes entry", {"coordinates", "height_m"}, row=f"hole {j}")
    xy = as_vertices(e.get("coordinates"), what=f"hole {j}", zone=zone)
    if signed_area(xy) > 0:
        xy = xy[::-1]
    h = r.num(e, "height_m", zone=zone)
    return tuple(map(tuple, xy.tolist())), (h,) * len(xy)


def _correction(r: InstanceReader, raw: Any, k: int) -> Correction:
    d = r.obj(
        raw,
        "correction",
        {"zone", "vertex", "side", "field", "printed", "corrected", "reason"},
        row=f"corrections[{k}]",
    )
    where = dict(row=f"corrections[{k}]")
    zone, fld = r.text(d, "zone", **where), r.text(d, "field", **where)
    kind = "vertex" if "vertex" in d else "side"
    if ("vertex" in d) == ("side" in d):
        raise r.fail("give exactly one of vertex or side", zone=zone, **where)
    allowed = VERTEX_FIELDS if kind == "vertex" else SIDE_FIELDS
    if fld not in allowed:
        raise r.fail(
            f"a {kind} correction changes one of {', '.join(allowed)}", zone=zone, field="field", value=fld, **where
        )
    return Correction(
        zone=zone,
        row=r.whole(d, kind, **where),
        field=fld,
        printed=r.num(d, "printed", **where),
        corrected=r.num(d, "corrected", **where),
        reason=r.text(d, "reason", **where),
    )


def _accepted(r: InstanceReader, raw: Any, k: int) -> AcceptedMisclosure:
    keys = {"zone", "angular_misclosure_deg", "linear_misclosure_m", "reason"}
    d = r.obj(raw, "accepted misclosure", keys, row=f"accepted_misclosures[{k}]")
    where = dict(row=f"accepted_misclosures[{k}]")
    return AcceptedMisclosure(
        zone=r.text(d, "zone", **where),
        angular_misclosure_deg=r.num(d, "angular_misclosure_deg", **where),
        linear_misclosure_m=r.num(d, "linear_misclosure_m", **where),
        reason=r.text(d, "reason", **where),
    )


def _check_references(
    r: InstanceReader,
    zones: tuple[Zone, ...],
    corrections: tuple[Correction, ...],
    accepted: tuple[AcceptedMisclosure, ...],
) -> None:
    table_zones = {z.id for z in zones if z.closure is not None}
    named = [(c.zone, "correction", "corrections") for c in corrections]
    for zone, what, key in named + [(a.zone, "accepted misclosure", "accepted_misclosures") for a in accepted]:
        if zone not in table_zones:
            raise r.fail(f"{what} names no table zone of this instance", zone=zone, field=key)


def _obstacle(r: InstanceReader, raw: Any, k: int) -> Obstacle:
    d = r.obj(raw, "obstacle", {"name", "polygon", "height_m"}, row=f"obstacles[{k}]")
    name = str(d.get("name", f"obstacle {k}"))
    return Obstacle(
        name=name, vertices=r.polygon(d.get("polygon"), "polygon", name), height_m=r.num(d, "height_m", zone=name)
    )


def _no_go(r: InstanceReader, raw: Any, k: int) -> NoGoArea:
    d = r.obj(raw, "no-go area", {"name", "polygon"}, row=f"no_go[{k}]")
    name = str(d.get("name", f"no-go {k}"))
    return NoGoArea(name=name, vertices=r.polygon(d.get("polygon"), "polygon", name))


def _control(r: InstanceReader, raw: Any, k: int) -> ControlPoint:
    keys = {"name", "x", "y", "z", "sigma_x_m", "sigma_x_mm", "sigma_y_m", "sigma_y_mm"}
    d = r.obj(raw, "control point", keys, row=f"control_points[{k}]")
    name = str(d.get("name", f"CP{k}"))
    return ControlPoint(
        name=name,
        x=r.num(d, "x", row=name),
        y=r.num(d, "y", row=name),
        z=r.num(d, "z", row=name) if d.get("z") is not None else None,
        sigma_x_m=r.length(d, "sigma_x", 0.0, row=name),
        sigma_y_m=r.length(d, "sigma_y", 0.0, row=name),
    )
