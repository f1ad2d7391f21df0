"""Read a floor plan from GeoJSON: Polygon features with a ``role`` (zone, obstacle, no_go) and heights
(docs/exchange.md lists the properties read).

Interior rings of a zone are holes. Features of an exported plan's other roles are skipped, so an exported plan.geojson
reads back as its site. With ``crs`` the coordinates are lon/lat (RFC 7946), projected to that metric CRS.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from planner.core.errors import InputError, PlannerError
from planner.core.fileio import read_json, to_float
from planner.io.crs import to_projected
from planner.io.params_io import RECORD_KEY, read_site_record, with_record
from planner.site.geometry import signed_area
from planner.site.model import SITE_FRAME, NoGoArea, Obstacle, ScanSide, Site, Zone
from planner.site.params import Parameters

ROLES = ("zone", "obstacle", "no_go")
#: the roles of an exported plan's other features (planner/io/geojson_out.py), read past
PLAN_ROLES = ("coverage", "station", "tripod_disc", "network", "control")


def _ring(raw: Any, where: dict[str, Any], fwd: Any) -> np.ndarray:
    if not isinstance(raw, list) or len(raw) < 4:
        raise InputError("a polygon ring needs at least 4 positions (closed)", **where, field="coordinates")
    pts = np.array(
        [
            [to_float(c, field="coordinates", **where) for c in p[:2]]
            if isinstance(p, list) and len(p) >= 2
            else [np.nan, np.nan]
            for p in raw
        ],
        dtype=float,
    )
    if np.isnan(pts).any():
        raise InputError("positions must be [x, y] numbers", **where, field="coordinates")
    if not np.allclose(pts[0], pts[-1], rtol=0, atol=1e-12):
        raise InputError("ring is not closed (first position != last)", **where, field="coordinates")
    pts = pts[:-1]
    return fwd(pts) if fwd else pts


def _ccw(xy: np.ndarray, heights: list[float] | None, want_ccw: bool = True) -> tuple[np.ndarray, list[float] | None]:
    if (signed_area(xy) > 0) != want_ccw:
        return xy[::-1], heights[::-1] if heights else heights
    return xy, heights


def _heights(props: dict, n: int, where: dict[str, Any]) -> list[float]:
    given = [key for key in ("height_m", "height") if key in props]
    if "vertex_heights_m" in props:
        if given:  # two heights for one zone: one would be dropped silently
            raise InputError(
                f"give vertex_heights_m or {given[0]}, not both", **where, field=given[0], value=_shown(props[given[0]])
            )
        raw = props["vertex_heights_m"]
        if not isinstance(raw, list) or len(raw) != n:
            raise InputError(f"needs a list of {n} heights", **where, field="vertex_heights_m")
        return [to_float(h, field="vertex_heights_m", **where) for h in raw]
    if len(given) == 2:  # two values, one would be dropped silently
        raise InputError("give height_m or height, not both", **where, field="height", value=_shown(props["height"]))
    if given:
        return [to_float(props[given[0]], field=given[0], **where)] * n
    raise InputError("no height: give height_m or vertex_heights_m", **where, field="properties")


def _shown(value: Any) -> Any:
    """A JSON value as a message shows it: text and numbers as found, a list or an object by its kind."""
    return value if isinstance(value, (str, int, float)) or value is None else type(value).__name__


def _member(f: dict, key: str, where: dict[str, Any]) -> dict:
    """``f[key]`` as an object (missing or null: an empty one)."""
    raw = f.get(key)
    if raw is None:
        return {}
    if not isinstance(raw, dict):
        raise InputError("must be an object", **where, field=key, value=type(raw).__name__)
    return raw


def _scan_side(props: dict, where: dict[str, Any]) -> ScanSide:
    side = props.get("scan_side", "inside")
    if not isinstance(side, str) or side not in {s.value for s in ScanSide}:
        raise InputError(
            f"unknown scan side (known: {', '.join(s.value for s in ScanSide)})",
            **where,
            field="scan_side",
            value=_shown(side),
        )
    return ScanSide(side)


def _feature(f: Any, k: int, file: str, fwd: Any) -> tuple[str, Any] | None:
    where: dict[str, Any] = dict(file=file, row=f"features[{k}]")
    if not isinstance(f, dict) or f.get("type") != "Feature":
        raise InputError("must be a GeoJSON Feature", **where)
    props = _member(f, "properties", where)
    geom = _member(f, "geometry", where)
    role = props.get("role", "zone")
    if not isinstance(role, str):
        raise InputError(
            f"unknown role (known: {', '.join(ROLES + PLAN_ROLES)})", **where, field="role", value=_shown(role)
        )
    if role in PLAN_ROLES:
        return None  # stations, coverage ... of an exported plan
    if role not in ROLES:  # a typo ("obstacel") must not drop a feature silently
        raise InputError(f"unknown role (known: {', '.join(ROLES + PLAN_ROLES)})", **where, field="role", value=role)
    if geom.get("type") != "Polygon":
        raise InputError(f"a {role} must be a Polygon", **where, field="geometry.type", value=_shown(geom.get("type")))
    rings = geom.get("coordinates")
    if not isinstance(rings, list) or not rings:
        raise InputError("needs coordinates", **where, field="geometry.coordinates")
    name = str(props.get("id", props.get("name", f"{role}-{k}")))
    where["zone"] = name
    outer = _ring(rings[0], where, fwd)
    holes = [_ring(r, where, fwd) for r in rings[1:]]
    if role == "zone":
        xy, h = _ccw(outer, _heights(props, len(outer), where))
        hole_xy = [_ccw(r, None, want_ccw=False)[0] for r in holes]
        side = _scan_side(props, where)
        hh = (
            to_float(props["hole_height_m"], field="hole_height_m", **where)
            if "hole_height_m" in props
            else max(h or [0.0])
        )
        return role, Zone(
            id=name,
            scan_side=side,
            vertices=tuple(map(tuple, xy.tolist())),
            vertex_heights_m=tuple(h or ()),
            frame=str(props.get("frame", SITE_FRAME)),
            holes=tuple(tuple(map(tuple, r.tolist())) for r in hole_xy),
            hole_heights_m=tuple((hh,) * len(r) for r in hole_xy),
        )
    if holes:
        raise InputError(f"a {role} cannot have holes", **where, field="geometry.coordinates")
    verts = tuple(map(tuple, outer.tolist()))
    if role == "obstacle":
        return role, Obstacle(name, verts, _heights(props, len(outer), where)[0])
    return role, NoGoArea(name, verts)


def read_geojson_site(path: Path | str, parameters: Parameters | None = None, crs: str | None = None) -> Site:
    """Read a site from a GeoJSON FeatureCollection (see the module docstring)."""
    path = Path(path)
    file = str(path)
    data = read_json(path)
    if (
        not isinstance(data, dict)
        or data.get("type") != "FeatureCollection"
        or not isinstance(data.get("features"), list)
    ):
        raise InputError(
            "must be a GeoJSON FeatureCollection",
            file=file,
            field="type",
            value=data.get("type") if isinstance(data, dict) else type(data).__name__,
        )
    fwd = to_projected(crs) if crs else None
    out: dict[str, list] = {r: [] for r in ROLES}
    for k, f in enumerate(data["features"], 1):
        try:
            got = _feature(f, k, file, fwd)
        except PlannerError as exc:
            raise exc.located(file) from None
        if got:
            out[got[0]].append(got[1])
    if not out["zone"]:
        raise InputError("no zone polygon", file=file, field="features", value=0)
    if fwd is None:
        _not_degrees(out["zone"], file)
    meta = data.get("planner")
    record = read_site_record(meta[RECORD_KEY], file) if isinstance(meta, dict) and RECORD_KEY in meta else None
    site = Site(
        name=path.stem,
        zones=tuple(out["zone"]),
        parameters=parameters or Parameters(),
        obstacles=tuple(out["obstacle"]),
        no_go_areas=tuple(out["no_go"]),
        source=file,
    )
    return with_record(site, record, parameters)


#: zones all smaller than this (in the file's units) are no rooms in metres; with coordinates that are
#: valid longitudes and latitudes they are degrees, RFC 7946's default, given without ``--crs``
_TINY = 0.5


def _not_degrees(zones: list[Zone], file: str) -> None:
    """Refuse a plan in lon/lat degrees read as metres (a room 0.001 m across that plans nothing)."""
    xy = np.vstack([z.xy for z in zones])
    extent = float(max(np.ptp(xy[:, 0]), np.ptp(xy[:, 1])))
    if extent < _TINY and np.all(np.abs(xy[:, 0]) <= 180) and np.all(np.abs(xy[:, 1]) <= 90):
        raise InputError(
            f"the zones span {extent:.3g} units: these look like lon/lat degrees (GeoJSON's default), "
            "read as metres; give --crs EPSG:<metric CRS> to project them (docs/exchange.md)",
            file=file,
            field="coordinates",
            value=f"{xy[0, 0]:.6f}, {xy[0, 1]:.6f}",
        )
