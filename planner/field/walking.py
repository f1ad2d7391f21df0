"""Walking distances between stations inside the accessible area of a site.

The walkable area of a frame is the open ground (the site boundary, or the zones' bounding box grown by
:data:`OPEN_MARGIN_M`, less every zone outline) joined with the inside zones (less their free-standing
blocks) and a passage through every door or gate (its gap, :data:`~planner.coverage.openings.OPENING_DEPTH_M`
deep on each side: a door goes through the whole wall); less obstacles, no-go areas and a strip of
:data:`WALL_CLEARANCE_M` around every solid part of every wall (windows are wall for walking). Shortest
paths in such a polygon bend only at its reflex corners, so the visibility graph over those corners and
the stations (an edge where the straight segment stays inside the area) gives exact shortest walks.
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import shapely
import shapely.ops
from numpy.typing import NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components, dijkstra
from shapely.geometry.polygon import orient

from planner.coverage.openings import OPENING_DEPTH_M, PASSABLE, opening_segments, solid_intervals, wall_gaps
from planner.site.model import SITE_FRAME, ScanSide, Site
from planner.site.placement import tangent_normal

#: open ground around the zones of a frame without a site boundary (m)
OPEN_MARGIN_M = 20.0
#: no walk passes closer to a solid wall than this (m)
WALL_CLEARANCE_M = 0.05
#: a point this close to the walkable area is joined to it by a straight step (m)
SNAP_M = 0.5


@dataclass(frozen=True, eq=False)
class WalkSpace:
    """The walkable area of one frame and what bounds it (for checks and figures)."""

    frame: str
    area: shapely.Geometry
    solid_walls: tuple[tuple[tuple[float, float], tuple[float, float]], ...]
    blocked: shapely.Geometry  # obstacles and no-go areas

    def contains(self, xy: tuple[float, float]) -> bool:
        """Whether ``xy`` lies in the walkable area (or on its edge)."""
        return bool(self.area.covers(shapely.Point(xy)))


def _passages(site: Site, frame: str) -> tuple[list[shapely.Geometry], list]:
    """Door and gate passages (rectangles through the wall) and the passable opening segments of ``frame``."""
    segs = [s for s in opening_segments(site, frame) if s[2] in PASSABLE]
    rects = []
    for _zi, _w, _kind, ends in segs:
        n = (OPENING_DEPTH_M + WALL_CLEARANCE_M) * tangent_normal(ends)[1]
        rects.append(shapely.Polygon([ends[0] + n, ends[1] + n, ends[1] - n, ends[0] - n]))
    return rects, segs


def walk_space(site: Site, frame: str, points: Sequence[tuple[float, float]] = ()) -> WalkSpace:
    """The walkable area of ``frame`` (see the module text); without a site boundary the open ground is the bounding box
    of the zones and of ``points`` (stations standing far out), grown by :data:`OPEN_MARGIN_M`."""
    zones = [(zi, z) for zi, z in enumerate(site.zones) if z.frame == frame]
    outlines = shapely.union_all([shapely.Polygon(z.xy) for _, z in zones])
    if frame == SITE_FRAME and site.boundary is not None:
        base = shapely.Polygon(site.boundary)
    else:
        lo, hi = np.array(outlines.bounds[:2]), np.array(outlines.bounds[2:])
        if len(points):
            xy = np.asarray(points, dtype=float).reshape(-1, 2)
            lo, hi = np.minimum(lo, xy.min(axis=0)), np.maximum(hi, xy.max(axis=0))
        base = shapely.box(*(lo - OPEN_MARGIN_M), *(hi + OPEN_MARGIN_M))
    rooms = [z.polygon for _, z in zones if ScanSide.INSIDE in z.scan_side.sides]
    rects, segs = _passages(site, frame)
    free = shapely.union_all([base.difference(outlines), *rooms, *rects])
    walls = []
    for zi, z in zones:
        for w in z.walls:
            a, b = np.asarray(w.start, float), np.asarray(w.end, float)
            u = (b - a) / w.length_m
            for lo_s, hi_s in solid_intervals(w.length_m, wall_gaps(site, zi, w, segs)):
                p, q = a + lo_s * u, a + hi_s * u
                walls.append(((float(p[0]), float(p[1])), (float(q[0]), float(q[1]))))
    rings = [a.vertices for a in site.obstacles] + [a.vertices for a in site.no_go_areas] if frame == SITE_FRAME else []
    blocked_parts = [shapely.Polygon(r) for r in rings]
    blocked = shapely.union_all(blocked_parts) if blocked_parts else shapely.Polygon()
    strip = (
        shapely.union_all(shapely.linestrings([list(w) for w in walls])).buffer(WALL_CLEARANCE_M, quad_segs=2)
        if walls
        else shapely.Polygon()
    )
    area = free.difference(shapely.union_all([strip, blocked])).intersection(base)
    area = shapely.set_precision(area, 1e-6)
    return WalkSpace(frame, area, tuple(walls), blocked)


def reflex_corners(area: shapely.Geometry) -> NDArray[np.float64]:
    """Corners of ``area`` where a shortest path may bend: reflex as seen from inside the area."""
    out = []
    for poly in getattr(area, "geoms", [area]):
        if poly.is_empty or poly.geom_type != "Polygon":
            continue
        poly = orient(poly, 1.0)  # exterior counter-clockwise, holes clockwise: the area is on the left
        for ring in (poly.exterior, *poly.interiors):
            xy = np.asarray(ring.coords)[:-1]
            if len(xy) < 3:
                continue
            prev, nxt = np.roll(xy, 1, axis=0), np.roll(xy, -1, axis=0)
            cross = (xy[:, 0] - prev[:, 0]) * (nxt[:, 1] - xy[:, 1]) - (xy[:, 1] - prev[:, 1]) * (nxt[:, 0] - xy[:, 0])
            out.append(xy[cross < -1e-12])
    return np.vstack(out) if out else np.zeros((0, 2))


@dataclass(frozen=True, eq=False)
class WalkGraph:
    """Shortest walks between ``points`` (stations, start) of one walkable area, each snapped into it (``snapped``):
    ``dist[i, j]`` in m (inf: not reachable), ``component[i]`` the part of the area point i stands in."""

    space: WalkSpace
    points: NDArray[np.float64]
    snapped: NDArray[np.float64]
    nodes: NDArray[np.float64]  # corners, then the snapped points
    dist: NDArray[np.float64]
    predecessors: NDArray[np.int32]
    component: NDArray[np.int32]

    def path(self, i: int, j: int) -> list[tuple[float, float]]:
        """The walk from point i to point j as a polyline (the points themselves at its ends)."""
        m = len(self.nodes) - len(self.points)
        pts = [tuple(map(float, self.nodes[k])) for k in walk_nodes(self.predecessors, i, j, m)]
        out = [tuple(map(float, self.points[i]))] + pts + [tuple(map(float, self.points[j]))]
        return [p for k, p in enumerate(out) if k == 0 or math.dist(p, out[k - 1]) > 1e-9]  # type: ignore[misc]


def walk_nodes(predecessors: NDArray[np.int32], i: int, j: int, offset: int = 0) -> list[int]:
    """The graph nodes of the shortest walk from point i (node ``offset + i``) to point j, from the predecessors
    of Dijkstra's runs from the points (row i: the run from point i)."""
    at, chain = offset + j, [offset + j]
    while at != offset + i:
        at = int(predecessors[i, at])
        if at < 0:
            raise ValueError(f"no walk from point {i} to point {j}")
        chain.append(at)
    return chain[::-1]


def snap_distance(space: WalkSpace, xy: tuple[float, float]) -> float:
    """How far ``xy`` lies from the walkable area (0 inside)."""
    return float(space.area.distance(shapely.Point(xy)))


_CORNER_SIGHT: weakref.WeakKeyDictionary[WalkSpace, tuple[NDArray[np.float64], shapely.Geometry, NDArray[np.bool_]]]
_CORNER_SIGHT = weakref.WeakKeyDictionary()


def _corner_sight(space: WalkSpace) -> tuple[NDArray[np.float64], shapely.Geometry, NDArray[np.bool_]]:
    """The reflex corners of ``space``, its area grown by 1e-6 m (prepared) and which pairs of corners see each other
    (in ``np.triu_indices`` order): most of a visibility graph's segment tests, made once per walkable area however
    many point sets are walked in it (the sheet walks the stations twice: to find the start, then in order)."""
    known = _CORNER_SIGHT.get(space)
    if known is None:
        corners = reflex_corners(space.area)
        fat = space.area.buffer(1e-6, quad_segs=1)
        shapely.prepare(fat)
        i, j = np.triu_indices(len(corners), k=1)
        seen = shapely.covers(fat, shapely.linestrings(np.stack([corners[i], corners[j]], axis=1)))
        known = _CORNER_SIGHT[space] = (corners, fat, np.asarray(seen, dtype=bool))
    return known


def walk_graph(space: WalkSpace, points: Sequence[tuple[float, float]]) -> WalkGraph:
    """The visibility graph of ``space`` with ``points`` added, and the shortest walks between the points. A point
    farther than :data:`SNAP_M` from the area is left unjoined (unreachable; the caller decides what that means).
    Cost: C corners and P points, (C + P)^2 / 2 segment tests in vectorised shapely calls (the C^2 / 2 among the
    corners once per walkable area, :func:`_corner_sight`), then P Dijkstra runs."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    snapped = pts.copy()
    for k, p in enumerate(pts):
        pt = shapely.Point(p)
        if not space.area.covers(pt) and space.area.distance(pt) <= SNAP_M:
            q = shapely.ops.nearest_points(space.area, pt)[0]
            # a hair inside, so that segments from it test as inside
            v = np.array([q.x, q.y]) - p
            snapped[k] = np.array([q.x, q.y]) + 1e-6 * v / max(float(np.hypot(*v)), 1e-12)
    corners, fat, seen = _corner_sight(space)
    nodes = np.vstack([corners, snapped])
    n = len(nodes)
    i, j = np.triu_indices(n, k=1)
    m = len(corners)
    ok = np.empty(len(i), dtype=bool)
    among = j < m  # the corner pairs, in the order of their own triangle
    ok[among] = seen
    lines = shapely.linestrings(np.stack([nodes[i[~among]], nodes[j[~among]]], axis=1))
    ok[~among] = shapely.covers(fat, lines)
    far = np.array([space.area.distance(shapely.Point(p)) > SNAP_M for p in pts], dtype=bool)
    bad = np.concatenate([np.zeros(m, dtype=bool), far])
    ok &= ~bad[i] & ~bad[j]
    w = np.hypot(*(nodes[i[ok]] - nodes[j[ok]]).T)
    w = np.maximum(w, 1e-9)  # csgraph drops explicit zeros
    g = coo_matrix(
        (np.concatenate([w, w]), (np.concatenate([i[ok], j[ok]]), np.concatenate([j[ok], i[ok]]))), shape=(n, n)
    ).tocsr()
    d, pred = dijkstra(g, directed=False, indices=np.arange(m, n), return_predecessors=True)
    step = np.hypot(*(snapped - pts).T)  # the step from each point into the area
    dist = d[:, m:] + step[:, None] + step[None, :]
    np.fill_diagonal(dist, 0.0)
    _, comp = connected_components(g, directed=False)
    return WalkGraph(space, pts, snapped, nodes, dist, pred.astype(np.int32), comp[m:].astype(np.int32))
