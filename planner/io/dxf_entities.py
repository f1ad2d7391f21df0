"""The DXF reader's first pass: the entities on the layers it reads, as closed outlines and labels.

Block references are expanded; LWPOLYLINE, 2-D POLYLINE and CIRCLE become outlines (their arcs checked for size, then
flattened), TEXT and MTEXT labels. Annotation (dimensions, leaders, images) draws nothing and is read past; every other
entity on a zone, hole, obstacle or no-go layer is refused with what to draw instead, so that no drawn shape is dropped
silently.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from planner.core.errors import InputError
from planner.io.dxf_arcs import check_arcs
from planner.io.dxf_options import DxfOptions

APPID = "TLS_PLANNER"
CLOSED_TOL_M = 1e-9
#: entities read as outlines, and as zone labels
OUTLINE_KINDS = ("LWPOLYLINE", "POLYLINE", "CIRCLE")
LABEL_KINDS = ("TEXT", "MTEXT")
#: annotation: it draws no outline, so it is read past on every layer
ANNOTATION_KINDS = frozenset(
    ("DIMENSION", "ARC_DIMENSION", "LARGE_RADIAL_DIMENSION", "LEADER", "MLEADER", "MULTILEADER", "TOLERANCE")
    + ("ATTDEF", "ATTRIB", "VIEWPORT", "IMAGE", "WIPEOUT", "ACAD_TABLE")
)
#: why an entity of a kind not read is refused (other kinds: "is not read on this layer")
REFUSED_KINDS = {
    **dict.fromkeys(("LINE", "ARC", "SPLINE", "ELLIPSE", "XLINE", "RAY", "MLINE"), "is open geometry"),
    **dict.fromkeys(
        ("SOLID", "TRACE", "HATCH", "MPOLYGON", "3DFACE", "REGION"),
        "is a filled area, not its outline (trace its boundary)",
    ),
    "POINT": "marks a point, not an outline",
}


@dataclass
class Shape:
    """A closed outline read from one entity: vertices in metres, thickness (m) and XDATA."""

    layer: str
    handle: str
    xy: np.ndarray
    thickness: float
    xdata: list[tuple[int, Any]]

    @property
    def where(self) -> str:
        """The row of an error about it: ``layer L handle H``."""
        return f"layer {self.layer} handle {self.handle}"

    def height(self, options: DxfOptions) -> float | None:
        """One height for every vertex: the thickness, else the layer default (None: neither)."""
        return self.thickness if self.thickness > 0 else options.layer_height(self.layer)


def expand(entities: Any, layer: str | None = None, where: str = "", depth: int = 0) -> Iterator[tuple[Any, str]]:
    """Entities with block references replaced by their (transformed) content, each with its handle (for block content:
    the block name and the handle of the INSERT)."""
    for e in entities:
        if depth and layer and e.dxf.get("layer", "0") == "0":
            e.dxf.layer = layer
        handle = where or str(e.dxf.get("handle", "?"))
        if e.dxftype() == "INSERT":
            if depth > 32:
                raise InputError("block references nested deeper than 32", field="INSERT", value=e.dxf.name)
            inner = f"{handle} (block {e.dxf.name})" if not where else where
            yield from expand(e.virtual_entities(), e.dxf.layer, inner, depth + 1)
        else:
            yield e, handle


def _xdata(e: Any) -> list[tuple[int, Any]]:
    try:
        return [(t.code, t.value) for t in e.get_xdata(APPID)]
    except Exception:  # no XDATA of our application (ezdxf raises DXFValueError)
        return []


def _points(e: Any, handle: str, options: DxfOptions, scale: float, file: str) -> np.ndarray:
    """The entity's closed outline in metres, its arcs flattened to ``options.flatten_m``."""
    from ezdxf import path as dxfpath

    kind = e.dxftype()
    where: dict[str, Any] = dict(file=file, row=f"layer {e.dxf.layer} handle {handle}")
    if kind == "POLYLINE" and not e.is_2d_polyline:
        raise InputError("only 2-D polylines are read", **where, field="POLYLINE")
    closed = kind == "CIRCLE" or (e.closed if kind == "LWPOLYLINE" else e.is_closed if kind == "POLYLINE" else False)
    check_arcs(e, scale, options.flatten_m, **where)  # before flattening: a huge arc would not flatten in time
    pts = np.array([(v.x, v.y) for v in dxfpath.make_path(e).flattening(options.flatten_m / scale)], dtype=float)
    if len(pts) >= 2 and np.allclose(pts[0], pts[-1], atol=CLOSED_TOL_M, rtol=0):
        pts, closed = pts[:-1], True
    if not closed:
        raise InputError("open polyline: zones, obstacles and no-go areas must be closed", **where, field=kind)
    return pts * scale


def _refuse(kind: str, layer: str, handle: str, file: str) -> None:
    why = REFUSED_KINDS.get(kind, "is not read on a zone, hole, obstacle or no-go layer")
    raise InputError(
        f"{kind} {why}: draw zones, obstacles and no-go areas as closed polylines",
        file=file,
        row=f"layer {layer} handle {handle}",
        field=kind,
    )


def read_shapes(
    msp: Any, options: DxfOptions, file: str, scale: float
) -> tuple[list[Shape], list[tuple[str, str, tuple]]]:
    """The outlines and the labels (layer in capitals, text, position in metres) on the layers read."""
    shapes, texts = [], []
    for e, handle in expand(msp):
        kind = e.dxftype()
        if not e.dxf.is_supported("layer"):  # a kind ezdxf does not know (a custom object, or a value shifted there)
            raise InputError(
                "an entity of a kind not known to DXF readers (a custom object: explode it into polylines; or damaged "
                "pairs): its layer cannot be read",
                file=file,
                row=f"handle {handle}",
                field="entity",
                value=kind,
            )
        layer = e.dxf.get("layer", "0")
        if options.role(layer) is None or kind in ANNOTATION_KINDS:
            continue
        if kind in LABEL_KINDS:
            p = e.dxf.insert
            text = e.plain_text() if kind == "MTEXT" else e.dxf.text
            texts.append((layer.upper(), text.strip(), (p.x * scale, p.y * scale)))
        elif kind in OUTLINE_KINDS:
            xy = _points(e, handle, options, scale, file)
            # a mirrored block turns the extrusion over and with it the sign of the thickness
            shapes.append(Shape(layer, handle, xy, abs(float(e.dxf.get("thickness", 0.0))) * scale, _xdata(e)))
        else:
            _refuse(kind, layer, handle, file)
    return shapes, texts
