"""Plan geometry of IFC elements: footprints from their meshes, openings found on zone walls.

IfcOpenShell's geometry kernel places every element in world coordinates (its local placements applied) and returns
metres whatever the file's length unit, so nothing here assumes a unit or a placement.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.core.errors import InputError
from planner.site.model import Opening, Wall

#: triangles whose plan area is below this (m^2) are vertical faces, not part of the footprint
MIN_TRIANGLE_AREA_M2 = 1e-8
#: vertices closer than this (m) along a footprint outline are merged
SIMPLIFY_TOL_M = 1e-3
#: an opening stands in a wall at most this thick (m), measured from the zone's wall face outwards
MAX_WALL_THICKNESS_M = 0.6
#: a door lining may stand this far (m) into the zone from the wall face
MAX_PROTRUSION_M = 0.05
#: an opening must share at least this length (m) with a wall to count
MIN_OPENING_M = 0.2
#: its long axis within this angle (degrees) of the wall
MAX_OPENING_SKEW_DEG = 10.0


@dataclass(frozen=True)
class Solid:
    """One element's mesh in world coordinates (metres): its plan footprint and height range."""

    footprint: shapely.Polygon | shapely.MultiPolygon
    z_min_m: float
    z_max_m: float

    @property
    def height_m(self) -> float:
        return self.z_max_m - self.z_min_m


def geometry_settings() -> Any:
    """IfcOpenShell settings: world coordinates (placements applied), triangulated, SI units."""
    import ifcopenshell.geom

    settings = ifcopenshell.geom.settings()
    settings.set("use-world-coords", True)
    # openings cut in walls change no footprint that matters here and cost most of the time
    settings.set("disable-opening-subtractions", True)
    return settings


def solid_of(element: Any, settings: Any) -> Solid | None:
    """The footprint and height range of ``element``, or None when it has no body geometry. A representation
    IfcOpenShell cannot build a shape from (damaged geometry: a reference to an entity of the wrong kind) is an
    InputError naming the element: dropping it would plan rooms without that wall, column or door."""
    import ifcopenshell.geom

    if getattr(element, "Representation", None) is None:
        return None
    try:
        shape = ifcopenshell.geom.create_shape(settings, element)
    except RuntimeError as exc:
        raise InputError(
            "IfcOpenShell builds no shape from its representation (damaged geometry?): "
            + (str(exc).splitlines() or [""])[0].split(". Product:")[0],
            row=f"#{element.id()}",
            field=element.is_a(),
            value=getattr(element, "Name", None) or element.GlobalId,
        ) from None
    verts = np.asarray(shape.geometry.verts, dtype=float).reshape(-1, 3)
    faces = np.asarray(shape.geometry.faces, dtype=np.int64).reshape(-1, 3)
    if len(faces) == 0:
        return None
    footprint = footprint_of(verts, faces)
    if footprint.is_empty:
        return None
    return Solid(footprint, float(verts[:, 2].min()), float(verts[:, 2].max()))


def footprint_of(verts: NDArray[np.float64], faces: NDArray[np.int64]) -> shapely.Polygon | shapely.MultiPolygon:
    """The union of a mesh's triangles projected on the plan (vertical faces dropped)."""
    tri = verts[faces][:, :, :2]
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    tri = tri[area > MIN_TRIANGLE_AREA_M2]
    if len(tri) == 0:
        return shapely.Polygon()
    polys = shapely.polygons(np.concatenate([tri, tri[:, :1]], axis=1))
    merged = shapely.union_all(polys, grid_size=1e-6)
    merged = shapely.simplify(merged, SIMPLIFY_TOL_M)
    if isinstance(merged, shapely.GeometryCollection) and not isinstance(merged, shapely.MultiPolygon):
        merged = shapely.MultiPolygon([g for g in merged.geoms if isinstance(g, shapely.Polygon)])
    return merged


def largest_polygon(geom: shapely.Geometry) -> shapely.Polygon:
    """The polygon of largest area in ``geom`` (itself when it is one), oriented: outline CCW, holes CW."""
    if isinstance(geom, shapely.Polygon):
        poly = geom
    else:
        parts = [g for g in getattr(geom, "geoms", ()) if isinstance(g, shapely.Polygon)]
        poly = max(parts, key=lambda g: g.area) if parts else shapely.Polygon()
    return shapely.geometry.polygon.orient(poly, sign=1.0)


def opening_on_wall(wall: Wall, footprint: shapely.Geometry, kind: str, name: str) -> Opening | None:
    """The stretch of ``wall`` that an opening's footprint stands in, or None.

    The opening counts when its footprint lies on the outer side of the wall face (the zone is to the left of the wall),
    within ``MAX_WALL_THICKNESS_M`` of it, runs along it (its long axis within ``MAX_OPENING_SKEW_DEG``) and shares at
    least ``MIN_OPENING_M`` of its length.
    """
    length = wall.length_m
    if length <= MIN_OPENING_M:
        return None
    a = np.asarray(wall.start, dtype=float)
    u = (np.asarray(wall.end, dtype=float) - a) / length
    n_left = np.array([-u[1], u[0]])  # towards the zone
    pts = shapely.get_coordinates(footprint)
    if len(pts) < 3:
        return None
    s = (pts - a) @ u
    d = (pts - a) @ n_left
    if d.max() > MAX_PROTRUSION_M or d.max() < -MAX_WALL_THICKNESS_M:
        return None
    if not _along(pts, u):
        return None
    s0, s1 = max(0.0, float(s.min())), min(length, float(s.max()))
    if s1 - s0 < MIN_OPENING_M:
        return None
    return Opening(wall=wall.index, s0_m=round(s0, 4), s1_m=round(s1, 4), kind=kind, name=name)


def _along(pts: NDArray[np.float64], u: NDArray[np.float64]) -> bool:
    """True when the long side of the points' minimum rotated rectangle runs along ``u``."""
    rect = shapely.get_coordinates(shapely.minimum_rotated_rectangle(shapely.multipoints(pts)))
    if len(rect) < 4:
        return False
    sides = [rect[1] - rect[0], rect[2] - rect[1]]
    longest = max(sides, key=lambda v: float(np.hypot(*v)))
    norm = float(np.hypot(*longest))
    if norm == 0:
        return False
    cos = abs(float(longest @ u)) / norm
    return cos >= math.cos(math.radians(MAX_OPENING_SKEW_DEG))
