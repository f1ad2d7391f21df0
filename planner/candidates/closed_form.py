"""Placing the closed-form candidates of chapter 3 on a zone (vertex, wall and circle candidates)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely
from shapely.ops import polylabel

from planner.candidates.formulas import VertexGeometry, WallPlan, horizontal_reach_m, vertex_geometry, wall_plan
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Zone
from planner.site.traverse import table_from_polygon

SIDE_TAG = {ScanSide.INSIDE: "in", ScanSide.OUTSIDE: "out"}


@dataclass(frozen=True)
class Limits:
    """The limits the closed form needs: slant range, incidence, overlap, instrument height."""

    max_slant_range_m: float
    theta_max_deg: float
    overlap: float
    instrument_height_m: float = 0.0


@dataclass(frozen=True)
class ZoneSidePlan:
    """The closed-form result for one zone seen from one side."""

    zone: str
    side: ScanSide
    vertices: tuple[VertexGeometry | None, ...]  # per vertex (table index - 1); None = cancelled
    walls: tuple[WallPlan, ...]
    candidates: tuple[Candidate, ...]
    circle_replaced_vertices: bool = False


def rotate(v: np.ndarray, deg: float) -> np.ndarray:
    """``v`` (2-D) turned counter-clockwise by ``deg``."""
    a = math.radians(deg)
    return np.array([v[0] * math.cos(a) - v[1] * math.sin(a), v[0] * math.sin(a) + v[1] * math.cos(a)])


def scan_side_angles(zone: Zone, side: ScanSide) -> np.ndarray:
    """Polygon angle at each vertex measured on the scanning side (deg)."""
    _, interior = table_from_polygon(np.asarray(zone.xy))
    return interior if side is ScanSide.INSIDE else 360.0 - interior


def plan_zone_side(zone: Zone, side: ScanSide, limits: Limits) -> ZoneSidePlan:
    """Vertex candidates, wall candidates and (inside, when no wall needs one) the circle candidate."""
    xy = np.asarray(zone.xy, dtype=float)
    angles = scan_side_angles(zone, side)
    reach = [horizontal_reach_m(limits.max_slant_range_m, h, limits.instrument_height_m) for h in zone.vertex_heights_m]
    vgeo = tuple(vertex_geometry(float(angles[i]), reach[i], limits.theta_max_deg) for i in range(len(xy)))
    vertex_cands = _vertex_candidates(zone, side, xy, vgeo)
    wplans, wall_cands = _wall_candidates(zone, side, xy, vgeo, limits)
    candidates = tuple(vertex_cands + wall_cands)
    replaced = False
    if side is ScanSide.INSIDE and not wall_cands:
        circle = circle_candidate(zone, vgeo, reach)
        if circle is not None:
            candidates, replaced = (circle,), True
    return ZoneSidePlan(zone.id, side, vgeo, tuple(wplans), candidates, replaced)


def side_candidate(
    zone: str, side: ScanSide, frame: str, name: str, x: float, y: float, kind: CandidateKind, **more: Any
) -> Candidate:
    """The candidate ``name`` of a zone-side (id ``zone-in-name`` / ``zone-out-name``) at (x, y) of ``frame``."""
    return Candidate(f"{zone}-{SIDE_TAG[side]}-{name}", zone, side, frame, x, y, kind, **more)


def side_sign(side: ScanSide) -> float:
    """+1 inside (to the left of each CCW wall), -1 outside."""
    return 1.0 if side is ScanSide.INSIDE else -1.0


def _vertex_candidates(
    zone: Zone, side: ScanSide, xy: np.ndarray, vgeo: tuple[VertexGeometry | None, ...]
) -> list[Candidate]:
    """One candidate per vertex not cancelled, on its bisector at the distance HD."""
    out_cands = []
    for i, g in enumerate(vgeo):
        if g is None:
            continue
        out = xy[(i + 1) % len(xy)] - xy[i]
        p = xy[i] + g.hd_m * rotate(out / np.linalg.norm(out), side_sign(side) * g.angle_deg / 2.0)
        geometry = dict(vertex=i + 1, alpha_deg=g.alpha_deg, hd_m=g.hd_m, gamma_deg=g.gamma_deg, covered_m=g.covered_m)
        x, y = float(p[0]), float(p[1])
        out_cands.append(side_candidate(zone.id, side, zone.frame, f"V{i + 1}", x, y, CandidateKind.VERTEX, **geometry))
    return out_cands


def _wall_candidates(
    zone: Zone, side: ScanSide, xy: np.ndarray, vgeo: tuple[VertexGeometry | None, ...], limits: Limits
) -> tuple[list[WallPlan], list[Candidate]]:
    """Each wall's plan (the length its vertex candidates leave) and its wall candidates, in site coordinates."""
    n = len(xy)
    wplans, wall_cands = [], []
    for i, wall in enumerate(zone.outer_walls):
        l1, l2 = (g.covered_m if g else 0.0 for g in (vgeo[i], vgeo[(i + 1) % n]))
        reach_c = horizontal_reach_m(limits.max_slant_range_m, wall.height_m, limits.instrument_height_m)
        wp = wall_plan(wall.length_m, reach_c, l1, l2, limits.theta_max_deg, limits.overlap)
        wplans.append(wp)
        start = xy[i]
        t = (xy[(i + 1) % n] - start) / wall.length_m
        nrm = side_sign(side) * np.array([-t[1], t[0]])

        def at(x: float, y: float, start: np.ndarray = start, t: np.ndarray = t, nrm: np.ndarray = nrm):
            q = start + x * t + y * nrm
            return (float(q[0]), float(q[1]))

        for k, st in enumerate(wp.stations, 1):
            field = (
                at(st.x_m - st.half_base_m, st.y_m),
                at(st.x_m + st.half_base_m, st.y_m),
                at(st.x_m, st.y_m - st.height_m),
            )
            local = dict(wall=i + 1, local_x_m=st.x_m, local_y_m=st.y_m, field=field)
            size = dict(field_half_base_m=st.half_base_m, field_height_m=st.height_m)
            px, py = at(st.x_m, st.y_m)
            w = side_candidate(zone.id, side, zone.frame, f"W{i + 1}.{k}", px, py, CandidateKind.WALL, **local, **size)
            wall_cands.append(w)
    return wplans, wall_cands


def circle_radii(vgeo: tuple[VertexGeometry | None, ...], reach: list[float]) -> list[float]:
    """Radius of each vertex circle: sqrt(S_max^2 - h_V^2), or the K^B HD at a reflex vertex (table 4.5)."""
    return [g.hd_m if (g is not None and g.reflex) else r for g, r in zip(vgeo, reach)]


#: local coordinates are rounded to this (m) so that a turned or moved site gives bit-identical input
FRAME_SNAP_DECIMALS = 6


def _basis(axis: np.ndarray) -> np.ndarray:
    ux = np.asarray(axis, dtype=float) / float(np.hypot(*axis))
    return np.column_stack([ux, [-ux[1], ux[0]]])  # columns: the frame's x and y axes


def to_frame(geom: shapely.Geometry, origin: np.ndarray, axis: np.ndarray) -> shapely.Geometry:
    """``geom`` in the coordinates of a frame (``origin``, x along ``axis``), rounded to 1e-6 m."""
    basis = _basis(axis)
    return shapely.transform(geom, lambda xy: np.round((xy - origin) @ basis, FRAME_SNAP_DECIMALS))


def from_frame(xy: np.ndarray, origin: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Frame coordinates (rows) back in the site's."""
    return np.asarray(origin, dtype=float) + np.asarray(xy, dtype=float) @ _basis(axis).T


def pole_in_frame(region: shapely.Polygon, origin: np.ndarray, axis: np.ndarray) -> shapely.Point:
    """The pole of inaccessibility of ``region`` (shapely's ``polylabel``, 1 cm tolerance), searched in the coordinates
    of a frame (``origin``, ``axis``: a zone's first vertex and wall). Where the pole is not unique (a rectangle's
    centres form a segment) ``polylabel``'s axis-aligned cells and the last bits of the input decide; in the frame's own
    (rounded) coordinates a turned or moved site gives the same point, moved."""
    p = polylabel(to_frame(region, origin, axis), tolerance=0.01)
    return shapely.Point(from_frame(np.array([[p.x, p.y]]), origin, axis)[0])


def circle_candidate(zone: Zone, vgeo: tuple[VertexGeometry | None, ...], reach: list[float]) -> Candidate | None:
    """One station inside the zone and inside every vertex circle (fig. 3.13), or None if they do not meet. The station
    is put at the pole of inaccessibility of that region (the centre of its largest inscribed circle), the point with
    the most room to move."""
    # in the zone's own coordinates (first vertex, first wall): the circles' polygons and the pole turn with the site
    origin, axis = np.asarray(zone.xy[0], dtype=float), np.subtract(zone.xy[1], zone.xy[0])
    region = to_frame(zone.polygon, origin, axis)
    centres = np.asarray(shapely.get_coordinates(to_frame(shapely.MultiPoint(zone.xy), origin, axis)))
    for (x, y), r in zip(centres, circle_radii(vgeo, reach)):
        region = region.intersection(shapely.Point(x, y).buffer(r, quad_segs=64))
        if region.is_empty:
            return None
    if not isinstance(region, shapely.Polygon):
        region = max(getattr(region, "geoms", []), key=lambda g: g.area, default=None)
        if region is None or region.area <= 0:
            return None
    pole = polylabel(region, tolerance=0.01)
    (x, y), *_ = from_frame(np.array([[pole.x, pole.y]]), origin, axis).tolist()
    field = tuple((float(a), float(b)) for a, b in from_frame(np.asarray(region.exterior.coords[:-1]), origin, axis))
    return side_candidate(
        zone.id, ScanSide.INSIDE, zone.frame, "C", float(x), float(y), CandidateKind.CIRCLE, field=field
    )
