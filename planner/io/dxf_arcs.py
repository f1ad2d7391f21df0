"""Size checks of a DXF entity's arcs (polyline bulges, circles) before they are flattened.

Flattening an arc to ``flatten_m`` costs vertices in proportion to ``sqrt(radius / flatten_m)``: a bulge of 1e12 on a 10
m chord is an arc of radius 2.5e12 m, whose flattening to 0.01 m would not end (and would fill the memory) before the
coordinate check of the polygon could refuse it. So each arc's reach is checked against
:data:`~planner.site.geometry.MAX_COORDINATE_M` and the vertices its flattening would give are counted, first.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from planner.core.errors import InputError
from planner.site.geometry import MAX_COORDINATE_M

#: an entity whose arcs would flatten to more vertices than this is refused (a round apse of 5,000
#: vertices is read; this is 20 times that)
MAX_ARC_VERTICES = 100_000


@dataclass(frozen=True)
class Arc:
    """One arc in drawing units: its centre-side anchor (chord midpoint or circle centre) in WCS x/y, the farthest its
    points lie from that anchor, its radius and sweep (radians)."""

    vertex: int | None  # 1-based vertex whose bulge it is; None for a circle
    bulge: float | None
    anchor: tuple[float, float]
    reach: float
    radius: float
    sweep: float


def entity_arcs(e: Any) -> list[Arc]:
    """The arcs of a LWPOLYLINE, 2-D POLYLINE or CIRCLE (none for straight polylines)."""
    kind = e.dxftype()
    if kind == "CIRCLE":
        r = abs(float(e.dxf.radius))
        return [Arc(None, None, _wcs(e, e.dxf.center), r, r, 2 * math.pi)]
    if kind == "LWPOLYLINE":
        elev = float(e.dxf.get("elevation", 0.0))
        pts = [(float(x), float(y), elev, float(b)) for x, y, b in e.get_points("xyb")]
    else:  # a 2-D POLYLINE: its elevation is the z of a point
        elev = float(e.dxf.get("elevation", (0.0, 0.0, 0.0))[2])
        pts = [
            (float(v.dxf.location.x), float(v.dxf.location.y), elev, float(v.dxf.get("bulge", 0.0))) for v in e.vertices
        ]
    closed = bool(e.closed) if kind == "LWPOLYLINE" else bool(e.is_closed)
    ends = len(pts) if closed else len(pts) - 1
    return [_bulge_arc(e, k, pts[k], pts[(k + 1) % len(pts)]) for k in range(max(ends, 0)) if pts[k][3] != 0.0]


def _bulge_arc(e: Any, k: int, p: tuple[float, float, float, float], q: tuple[float, float, float, float]) -> Arc:
    """The arc from ``p`` to ``q`` with ``p``'s bulge (tan of a quarter of the sweep)."""
    b = abs(p[3])
    chord = math.hypot(q[0] - p[0], q[1] - p[1])
    # the points of a minor arc (b <= 1) lie within half the chord of its midpoint; a major arc's
    # farthest point from it is the bulge point, at the sagitta b * chord / 2
    reach = 0.5 * chord * max(1.0, b)
    radius = chord * (1.0 + b * b) / (4.0 * b) if chord > 0 else 0.0
    mid = ((p[0] + q[0]) / 2, (p[1] + q[1]) / 2, p[2])
    return Arc(k + 1, p[3], _wcs(e, mid), reach, radius, 4.0 * math.atan(b))


def _wcs(e: Any, point: Any) -> tuple[float, float]:
    """x, y in world coordinates of a point in the entity's object coordinate system."""
    w = e.ocs().to_wcs(point)
    return float(w.x), float(w.y)


def flattened_count(arcs: list[Arc], flatten: float) -> float:
    """About how many vertices flattening ``arcs`` to a deviation of ``flatten`` gives (same units)."""
    total = 0.0
    for a in arcs:
        if a.radius > flatten / 2:  # a segment of half-angle h deviates radius * (1 - cos h) from the arc
            total += a.sweep / (4.0 * math.asin(math.sqrt(flatten / (2.0 * a.radius))))
        total += 1.0
    return total


def check_arcs(e: Any, scale: float, flatten_m: float, **where: Any) -> None:
    """Refuse an arc that reaches beyond +-MAX_COORDINATE_M, or arcs whose flattening would give more than
    MAX_ARC_VERTICES vertices; ``scale`` converts drawing units to metres."""
    arcs = entity_arcs(e)
    if not arcs:
        return
    for a in arcs:
        if a.bulge is not None and not math.isfinite(a.bulge):
            raise InputError("bulge must be a finite number", **_at(a, where), field="bulge", value=a.bulge)
        far = (max(abs(a.anchor[0]), abs(a.anchor[1])) + a.reach) * scale
        if not math.isfinite(far) or far > MAX_COORDINATE_M:
            raise InputError(
                f"an arc of radius {a.radius * scale:.4g} m reaches {far:.4g} m out, beyond +-{MAX_COORDINATE_M:g} m",
                **_at(a, where),
                **_value(a, scale),
            )
    n = flattened_count(arcs, flatten_m / scale)
    if n > MAX_ARC_VERTICES:
        many = f"{n:,.0f}" if n < 1e12 else f"{n:.3g}"
        big = max(arcs, key=lambda a: a.radius)
        raise InputError(
            f"flattening its arcs to {flatten_m:g} m would give about {many} vertices (limit "
            f"{MAX_ARC_VERTICES:,}; largest radius {big.radius * scale:.4g} m): draw the curve with "
            "vertices, or flatten coarser (DxfOptions.flatten_m)",
            **_at(big, where),
            **_value(big, scale),
        )


def _at(a: Arc, where: dict[str, Any]) -> dict[str, Any]:
    """``where`` with the arc's vertex added to the row."""
    if a.vertex is None or where.get("row") is None:
        return where
    return where | {"row": f"{where['row']} vertex {a.vertex}"}


def _value(a: Arc, scale: float) -> dict[str, Any]:
    """The field and value that name the arc: its bulge, or a circle's radius (m)."""
    if a.bulge is not None:
        return {"field": "bulge", "value": a.bulge}
    return {"field": "radius", "value": a.radius * scale}
