"""Read a floor plan from DXF: closed polylines on named layers become zones, obstacles and no-go areas.

- Entities: LWPOLYLINE and 2-D POLYLINE (closed flag, or first point = last point), CIRCLE;
  bulges (arcs) and circles are flattened to ``flatten_m``. Block references (INSERT) are
  expanded recursively with their transformation, mirrored ones too; entities on layer 0
  inside a block take the INSERT's layer (the CAD convention).
- Heights, in this order: XDATA of application ``TLS_PLANNER`` (one 1040 real per vertex, as
  written by :mod:`planner.exchange.dxf_out`), the entity's thickness, the layer default of
  ``DxfOptions.layer_heights_m``; otherwise an error.
- Holes: closed polylines on ``HOLES`` are free-standing blocks of the inside zone that contains
  them (their walls are scanned from the zone); heights as for zones.
- Zone id: XDATA ``zone=...``, else a TEXT/MTEXT of the same layer inside the polygon, else
  ``LAYER-n``. Scan side: the layer's own (``ZONES-OUTSIDE`` ...), else XDATA ``side=``, else
  ``DxfOptions.default_side``.
- Units: ``$INSUNITS`` (mm, cm, m, inch, foot ...) scaled to metres; 0 (unitless) is read as metres
  and said in the zone notes.
Vertex order is made counter-clockwise: DXF has no orientation convention (a mirrored block
reverses it), so this changes no data. Nothing in the file is executed; ezdxf only parses tags.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from planner.errors import InputError, PlannerError, located_in
from planner.params import Parameters
from planner.site.fileio import MAX_INPUT_BYTES
from planner.site.geometry import signed_area
from planner.site.model import SITE_FRAME, NoGoArea, Obstacle, ScanSide, Site, Zone

APPID = "TLS_PLANNER"
ZONE_LAYERS: dict[str, ScanSide | None] = {
    "WALLS": None, "ZONES": None, "ZONES-INSIDE": ScanSide.INSIDE, "ZONES-OUTSIDE": ScanSide.OUTSIDE,
    "ZONES-BOTH": ScanSide.BOTH,
}
CLOSED_TOL_M = 1e-9


@dataclass(frozen=True)
class DxfOptions:
    """Which layers hold what (names compared case-insensitively) and the defaults."""

    zone_layers: dict[str, ScanSide | None] = field(default_factory=lambda: dict(ZONE_LAYERS))
    obstacle_layers: tuple[str, ...] = ("OBSTACLES",)
    hole_layers: tuple[str, ...] = ("HOLES",)
    nogo_layers: tuple[str, ...] = ("NOGO", "NO-GO")
    layer_heights_m: dict[str, float] = field(default_factory=dict)
    default_side: ScanSide = ScanSide.INSIDE
    flatten_m: float = 0.01

    def role(self, layer: str) -> str | None:
        u = layer.upper()
        if u in {k.upper() for k in self.zone_layers}:
            return "zone"
        if u in {k.upper() for k in self.obstacle_layers}:
            return "obstacle"
        if u in {k.upper() for k in self.nogo_layers}:
            return "no_go"
        if u in {k.upper() for k in self.hole_layers}:
            return "hole"
        return None

    def layer_side(self, layer: str) -> ScanSide | None:
        return {k.upper(): v for k, v in self.zone_layers.items()}.get(layer.upper())

    def layer_height(self, layer: str) -> float | None:
        return {k.upper(): v for k, v in self.layer_heights_m.items()}.get(layer.upper())


@dataclass
class _Shape:
    layer: str
    handle: str
    xy: np.ndarray
    thickness: float
    xdata: list[tuple[int, Any]]

    def height(self, options: DxfOptions) -> float | None:
        """One height for every vertex: the thickness, else the layer default (None: neither)."""
        return self.thickness if self.thickness > 0 else options.layer_height(self.layer)


def _expand(entities: Any, layer: str | None = None, where: str = "", depth: int = 0) -> Iterator[tuple[Any, str]]:
    """Entities with block references replaced by their (transformed) content, each with its handle
    (for block content: the block name and the handle of the INSERT)."""
    for e in entities:
        if depth and layer and e.dxf.get("layer", "0") == "0":
            e.dxf.layer = layer
        handle = where or str(e.dxf.get("handle", "?"))
        if e.dxftype() == "INSERT":
            if depth > 32:
                raise InputError("block references nested deeper than 32", field="INSERT", value=e.dxf.name)
            inner = f"{handle} (block {e.dxf.name})" if not where else where
            yield from _expand(e.virtual_entities(), e.dxf.layer, inner, depth + 1)
        else:
            yield e, handle


def _xdata(e: Any) -> list[tuple[int, Any]]:
    try:
        return [(t.code, t.value) for t in e.get_xdata(APPID)]
    except Exception:  # no XDATA of our application (ezdxf raises DXFValueError)
        return []


def _points(e: Any, handle: str, flatten_m: float, file: str) -> np.ndarray:
    from ezdxf import path as dxfpath

    kind = e.dxftype()
    where = dict(file=file, row=f"layer {e.dxf.layer} handle {handle}")
    if kind == "POLYLINE" and not e.is_2d_polyline:
        raise InputError("only 2-D polylines are read", **where, field="POLYLINE")
    closed = kind == "CIRCLE" or (e.closed if kind == "LWPOLYLINE" else e.is_closed if kind == "POLYLINE" else False)
    pts = np.array([(v.x, v.y) for v in dxfpath.make_path(e).flattening(flatten_m)], dtype=float)
    if len(pts) >= 2 and np.allclose(pts[0], pts[-1], atol=CLOSED_TOL_M, rtol=0):
        pts, closed = pts[:-1], True
    if not closed:
        raise InputError("open polyline: zones, obstacles and no-go areas must be closed", **where, field=kind)
    return pts


def _shapes(msp: Any, options: DxfOptions, file: str, scale: float) -> tuple[list[_Shape], list[tuple[str, str, tuple]]]:
    shapes, texts = [], []
    for e, handle in _expand(msp):
        kind, layer = e.dxftype(), e.dxf.get("layer", "0")
        role = options.role(layer)
        if role is None:
            continue
        if kind in ("TEXT", "MTEXT"):
            p = e.dxf.insert
            texts.append((layer.upper(), e.plain_text().strip() if kind == "MTEXT" else e.dxf.text.strip(),
                          (p.x * scale, p.y * scale)))
        elif kind in ("LWPOLYLINE", "POLYLINE", "CIRCLE"):
            xy = _points(e, handle, options.flatten_m / scale, file) * scale
            # a mirrored block turns the extrusion over and with it the sign of the thickness
            shapes.append(_Shape(layer, handle, xy, abs(float(e.dxf.get("thickness", 0.0))) * scale, _xdata(e)))
        elif kind in ("LINE", "ARC", "SPLINE", "ELLIPSE"):
            raise InputError(f"{kind} is open geometry: draw zones, obstacles and no-go areas as closed polylines",
                             file=file, row=f"layer {layer} handle {handle}", field=kind)
    return shapes, texts


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


def _zone(s: _Shape, k: int, options: DxfOptions, texts: list, scale: float, note: str | None, file: str) -> Zone:
    kv, heights = _tags(s.xdata)
    xy = s.xy
    ccw = signed_area(xy) > 0
    where = dict(file=file, row=f"layer {s.layer} handle {s.handle}")
    zid = kv.get("zone") or next((t for lay, t, p in texts if lay == s.layer.upper() and t
                                  and shapely.contains_xy(shapely.Polygon(xy), *p)), None) or f"{s.layer}-{k}"
    if heights:
        heights = [h * scale for h in heights]
        if len(heights) != len(xy):
            raise InputError(f"XDATA has {len(heights)} heights for {len(xy)} vertices", zone=zid, **where, field="height")
    else:
        h = s.height(options)
        if h is None:
            raise InputError("no wall height: set the polyline's thickness or give a layer default height",
                             zone=zid, **where, field="thickness", value=s.thickness)
        heights = [h] * len(xy)
    if not ccw:
        xy, heights = xy[::-1], heights[::-1]
    side = options.layer_side(s.layer) or (ScanSide(kv["side"]) if kv.get("side") in {m.value for m in ScanSide}
                                            else options.default_side)
    return Zone(id=zid, scan_side=side, vertices=tuple(map(tuple, xy.tolist())), vertex_heights_m=tuple(heights),
                frame=kv.get("frame", SITE_FRAME), notes=(note,) if note else ())


def _place_holes(zones: list[Zone], holes: list[_Shape], options: DxfOptions, scale: float, file: str) -> list[Zone]:
    """Free-standing blocks (layer HOLES) go into the inside zone that contains them, clockwise."""
    rings: dict[int, list[tuple[np.ndarray, list[float]]]] = {}
    for s in holes:
        where = dict(file=file, row=f"layer {s.layer} handle {s.handle}")
        _, heights = _tags(s.xdata)
        h = s.height(options)
        heights = [v * scale for v in heights] if len(heights) == len(s.xy) else ([h] * len(s.xy) if h else [])
        if not heights:
            raise InputError("no wall height for a hole: set thickness or a layer default", **where, field="thickness")
        inner = shapely.Polygon(s.xy)
        k = next((i for i, z in enumerate(zones) if z.scan_side is ScanSide.INSIDE and shapely.Polygon(z.xy).contains(inner)), None)
        if k is None:
            raise InputError("a hole must lie inside a zone scanned inside", **where, field="HOLES")
        xy = s.xy
        if signed_area(xy) > 0:
            xy, heights = xy[::-1], heights[::-1]
        rings.setdefault(k, []).append((xy, heights))
    out = list(zones)
    for k, rs in rings.items():
        try:
            out[k] = replace(out[k], holes=out[k].holes + tuple(tuple(map(tuple, r.tolist())) for r, _ in rs),
                             hole_heights_m=out[k].hole_heights_m + tuple(tuple(h) for _, h in rs))
        except PlannerError as exc:
            raise exc.located(file) from None
    return out


def read_dxf_site(path: Path | str, options: DxfOptions | None = None, parameters: Parameters | None = None) -> Site:
    """Read a site from a DXF drawing (see the module docstring for what is read and how).

    Raises
    ------
    InputError
        One line naming the file, the layer and entity handle: unreadable or malformed DXF, open
        polylines, zero-area or self-intersecting ones, a missing height, no closed polyline on a
        zone layer.
    """
    import ezdxf

    options = options or DxfOptions()
    path = Path(path)
    file = str(path)
    try:
        size = path.stat().st_size
    except OSError as exc:
        raise InputError(f"cannot read file: {exc.strerror}", file=file) from None
    if size > MAX_INPUT_BYTES:
        raise InputError(f"file too large ({size:,} bytes; limit {MAX_INPUT_BYTES:,})", file=file, value=size)
    try:
        doc = ezdxf.readfile(path)
    except (OSError, ezdxf.DXFError, ValueError, UnicodeDecodeError) as exc:
        first = (str(exc).splitlines() or [type(exc).__name__])[0]
        raise InputError(f"not a readable DXF file ({first})", file=file) from None
    scale, note = _scale(doc, file)
    with located_in(file):
        shapes, texts = _shapes(doc.modelspace(), options, file, scale)
    zones, obstacles, nogo = [], [], []
    for k, s in enumerate(shapes, 1):
        role = options.role(s.layer)
        try:
            if role == "zone":
                zones.append(_zone(s, sum(1 for t in shapes[:k] if options.role(t.layer) == "zone"), options, texts,
                                   scale, note, file))
            elif role == "hole":
                continue  # placed into their zones below
            elif role == "obstacle":
                kv, _ = _tags(s.xdata)
                h = s.height(options)
                if h is None:
                    raise InputError("no obstacle height: set the polyline's thickness or a layer default",
                                     row=f"layer {s.layer} handle {s.handle}", field="thickness", value=s.thickness)
                obstacles.append(Obstacle(kv.get("name", f"{s.layer}-{k}"), tuple(map(tuple, s.xy.tolist())), h))
            else:
                kv, _ = _tags(s.xdata)
                nogo.append(NoGoArea(kv.get("name", f"{s.layer}-{k}"), tuple(map(tuple, s.xy.tolist()))))
        except PlannerError as exc:
            if exc.row is None:
                exc.row = f"layer {s.layer} handle {s.handle}"
            raise exc.located(file) from None
    if not zones:
        layers = ", ".join(options.zone_layers)
        raise InputError(f"no closed polyline on a zone layer ({layers})", file=file, field="zones", value=0)
    zones = _place_holes(zones, [s for s in shapes if options.role(s.layer) == "hole"], options, scale, file)
    return Site(name=path.stem, zones=tuple(zones), parameters=parameters or Parameters(),
                obstacles=tuple(obstacles), no_go_areas=tuple(nogo), source=file)
