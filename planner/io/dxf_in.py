"""Read a floor plan from DXF: closed polylines on named layers become zones, obstacles and no-go areas.

docs/exchange.md tables what is read: the entities (:mod:`planner.io.dxf_entities`; arcs checked, then flattened,
:mod:`planner.io.dxf_arcs`), heights (XDATA of application ``TLS_PLANNER`` as :mod:`planner.io.dxf_out` writes it, else
the thickness, else the layer default), holes, zone ids, scan sides and units. Vertex order is made counter-clockwise:
DXF has no orientation convention (a mirrored block reverses it). Nothing in the file is executed; ezdxf only parses
tags, after the file is checked whole (:mod:`planner.io.dxf_check`: the end marker, the group-code/value pairs).
"""

from __future__ import annotations

import logging
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from planner.core.errors import InputError, PlannerError, located_in
from planner.core.fileio import MAX_INPUT_BYTES
from planner.io.dxf_check import check_dxf_pairs, read_dxf_bytes
from planner.io.dxf_entities import APPID, Shape, read_shapes
from planner.io.dxf_options import ZONE_LAYERS, DxfOptions
from planner.io.params_io import record_from_dxf, with_record
from planner.site.geometry import check_simple_polygon, signed_area
from planner.site.model import SITE_FRAME, NoGoArea, Obstacle, ScanSide, Site, Zone
from planner.site.params import Parameters

__all__ = ["APPID", "ZONE_LAYERS", "DxfOptions", "read_dxf_site"]

#: ezdxf logs what it repairs while loading; unconfigured, Python prints that on stderr beside the planner's one line
#: (a damaged file is refused by the checks instead, a sound one needs no note)
logging.getLogger("ezdxf").addHandler(logging.NullHandler())


def _scale(doc: Any, file: str) -> tuple[float, str | None]:
    from ezdxf import units

    code = int(doc.header.get("$INSUNITS", 0))
    if code == 0:
        return 1.0, "drawing units not set ($INSUNITS = 0): read as metres"
    try:
        return float(units.conversion_factor(code, units.M)), None
    except Exception:
        raise InputError("unsupported drawing units", file=file, field="$INSUNITS", value=code) from None


def _tags(xdata: list[tuple[int, Any]]) -> tuple[dict[str, str], list[float]]:
    kv = dict(str(v).split("=", 1) for c, v in xdata if c == 1000 and "=" in str(v))
    return kv, [float(v) for c, v in xdata if c == 1040]


def _located(exc: PlannerError, s: Shape, file: str) -> PlannerError:
    """``exc`` naming the file and the shape's layer and handle (before a row it names, e.g. a side)."""
    if exc.row is None:
        exc.row = s.where
    elif s.where not in str(exc.row):
        exc.row = f"{s.where} {'row ' if str(exc.row).isdigit() else ''}{exc.row}"
    return exc.located(file)


def _label(s: Shape, texts: list[tuple[str, str, tuple]]) -> str | None:
    """The first TEXT/MTEXT of the shape's layer that stands inside it (an outline of fewer than 3 vertices holds none:
    the zone's check says why it is no polygon)."""
    if len(s.xy) < 3:
        return None
    poly = shapely.Polygon(s.xy)
    return next((t for lay, t, p in texts if lay == s.layer.upper() and t and shapely.contains_xy(poly, *p)), None)


def _side(s: Shape, kv: dict[str, str], options: DxfOptions) -> ScanSide:
    """The layer's own scan side, else XDATA ``side=``, else the default; an unknown XDATA side is refused."""
    raw = kv.get("side")
    known = [m.value for m in ScanSide]
    if raw is not None and raw not in known:  # a typo ("outsde") must not fall back to the default silently
        raise InputError(f"unknown scan side in XDATA (known: {', '.join(known)})", field="side", value=raw)
    return options.layer_side(s.layer) or (ScanSide(raw) if raw is not None else options.default_side)


def _heights(s: Shape, options: DxfOptions, scale: float, what: str) -> list[float]:
    """One height per vertex: XDATA (one per vertex), else the thickness or the layer default."""
    _, heights = _tags(s.xdata)
    if heights:
        if len(heights) != len(s.xy):
            raise InputError(f"XDATA has {len(heights)} heights for {len(s.xy)} vertices", field="height")
        return [h * scale for h in heights]
    h = s.height(options)
    if h is None:
        raise InputError(
            f"no wall height{what}: set the polyline's thickness or give a layer default height",
            field="thickness",
            value=s.thickness,
        )
    return [h] * len(s.xy)


def _zone(s: Shape, k: int, options: DxfOptions, texts: list, note: str | None, scale: float) -> Zone:
    kv, _ = _tags(s.xdata)
    zid = kv.get("zone") or _label(s, texts) or f"{s.layer}-{k}"
    try:
        heights = _heights(s, options, scale, "")
        side = _side(s, kv, options)
    except PlannerError as exc:
        exc.zone = zid
        raise
    xy = s.xy
    if signed_area(xy) <= 0:
        xy, heights = xy[::-1], heights[::-1]
    return Zone(
        id=zid,
        scan_side=side,
        vertices=tuple(map(tuple, xy.tolist())),
        vertex_heights_m=tuple(heights),
        frame=kv.get("frame", SITE_FRAME),
        notes=(note,) if note else (),
    )


def _hole_ring(s: Shape, zones: list[Zone], options: DxfOptions, scale: float) -> tuple[int, np.ndarray, list[float]]:
    """The index of the inside zone that holds the hole, and its ring (clockwise) with its heights."""
    heights = _heights(s, options, scale, " for a hole")
    check_simple_polygon(s.xy, what="polygon")  # before shapely builds it: two vertices are no ring
    inner = shapely.Polygon(s.xy)
    k = next(
        (i for i, z in enumerate(zones) if z.scan_side is ScanSide.INSIDE and shapely.Polygon(z.xy).contains(inner)),
        None,
    )
    if k is None:
        raise InputError("a hole must lie inside a zone scanned inside", field="HOLES")
    if signed_area(s.xy) > 0:
        return k, s.xy[::-1], heights[::-1]
    return k, s.xy, heights


def _place_holes(zones: list[Zone], holes: list[Shape], options: DxfOptions, scale: float, file: str) -> list[Zone]:
    """Free-standing blocks (layer HOLES) go into the inside zone that contains them, clockwise."""
    rings: dict[int, list[tuple[np.ndarray, list[float]]]] = {}
    for s in holes:
        try:
            k, xy, heights = _hole_ring(s, zones, options, scale)
        except PlannerError as exc:
            raise _located(exc, s, file) from None
        rings.setdefault(k, []).append((xy, heights))
    out = list(zones)
    with located_in(file):
        for k, rs in rings.items():
            out[k] = replace(
                out[k],
                holes=out[k].holes + tuple(tuple(map(tuple, r.tolist())) for r, _ in rs),
                hole_heights_m=out[k].hole_heights_m + tuple(tuple(h) for _, h in rs),
            )
    return out


def _other(s: Shape, k: int, role: str, options: DxfOptions) -> Obstacle | NoGoArea:
    """An obstacle (one height) or a no-go area."""
    kv, _ = _tags(s.xdata)
    name, verts = kv.get("name", f"{s.layer}-{k}"), tuple(map(tuple, s.xy.tolist()))
    if role == "no_go":
        return NoGoArea(name, verts)
    h = s.height(options)
    if h is None:
        raise InputError(
            "no obstacle height: set the polyline's thickness or a layer default", field="thickness", value=s.thickness
        )
    return Obstacle(name, verts, h)


def _open(path: Path) -> Any:
    """The parsed drawing, after a size check."""
    import ezdxf

    file = str(path)
    try:
        size = path.stat().st_size
    except OSError as exc:
        raise InputError(f"cannot read file: {exc.strerror}", file=file) from None
    if size > MAX_INPUT_BYTES:
        raise InputError(f"file too large ({size:,} bytes; limit {MAX_INPUT_BYTES:,})", file=file, value=size)
    if not path.is_file():
        raise InputError("not a file", file=file)
    check_dxf_pairs(read_dxf_bytes(path, file), file)  # whole, its pairs intact: ezdxf reads past some damage
    try:
        return ezdxf.readfile(path)
    except Exception as exc:  # ezdxf's parser fails on damaged input in many ways (DXFError, ValueError, StopIteration)
        first = (str(exc).splitlines() or [type(exc).__name__])[0] or type(exc).__name__
        raise InputError(f"not a readable DXF file ({first})", file=file) from None


def read_dxf_site(path: Path | str, options: DxfOptions | None = None, parameters: Parameters | None = None) -> Site:
    """Read a site from a DXF drawing (see the module docstring). InputError, one line naming the file, the layer
    and entity handle: unreadable or malformed DXF, open polylines, zero-area or self-intersecting ones, a missing
    height, an arc too large to flatten, an entity of a kind not read on a zone layer, no closed polyline on a zone
    layer."""
    options = options or DxfOptions()
    path = Path(path)
    file = str(path)
    doc = _open(path)
    scale, note = _scale(doc, file)
    with located_in(file):
        shapes, texts = read_shapes(doc.modelspace(), options, file, scale)
    zones: list[Zone] = []
    others: dict[str, list] = {"obstacle": [], "no_go": []}
    for k, s in enumerate(shapes, 1):
        role = options.role(s.layer)
        try:
            if role == "zone":
                zones.append(_zone(s, len(zones) + 1, options, texts, note, scale))
            elif role in others:
                others[str(role)].append(_other(s, k, str(role), options))
        except PlannerError as exc:
            raise _located(exc, s, file) from None
    if not zones:
        layers = ", ".join(options.zone_layers)
        raise InputError(f"no closed polyline on a zone layer ({layers})", file=file, field="zones", value=0)
    zones = _place_holes(zones, [s for s in shapes if options.role(s.layer) == "hole"], options, scale, file)
    site = Site(
        name=path.stem,
        zones=tuple(zones),
        parameters=parameters or Parameters(),
        obstacles=tuple(others["obstacle"]),
        no_go_areas=tuple(others["no_go"]),
        source=file,
    )
    # planner's own export carries the name, instrument and parameters in the header
    return with_record(site, record_from_dxf(list(doc.header.custom_vars), file), parameters)
