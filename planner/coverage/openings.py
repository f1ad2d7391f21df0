"""Openings (doors, gates, windows, passages) as gaps in walls, and the accessible areas they join.

An opening is declared on one wall of one zone, in metres along it. It is a gap in EVERY wall face of the frame that
runs parallel to its wall (within ``PARALLEL_DEG``) at most ``OPENING_DEPTH_M`` in front of or behind it (a placed
neighbour's face of the same wall): a door goes through the whole wall. Sight passes through a gap; a gap holds no
targets.

Accessible areas: each inside zone is a space, and the outside of a frame's outside-scanned zones is one. A door, gate
or passage joins its zone's space with the space just behind the wall (none found: the frame's outside); windows join
nothing. A stair (``Site.stairs``) joins its lower zone's space with its upper one's.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import networkx as nx
import numpy as np
import shapely
from numpy.typing import NDArray

from planner.site.geometry import cross_z
from planner.site.model import ScanSide, Site, Wall, Zone

#: the deepest wall an opening goes through (faces of one wall are at most this far apart)
OPENING_DEPTH_M = 1.0
#: faces of one wall are parallel within this angle
PARALLEL_DEG = 2.0
#: kinds of opening one can walk (and carry a scanner) through: a passage (no door in it) as a door
PASSABLE = ("door", "gate", "passage")


def opening_segments(site: Site, frame: str) -> list[tuple[int, Wall, str, NDArray[np.float64]]]:
    """(zone index, wall, kind, 2x2 end points) of every opening of a zone in ``frame``."""
    out = []
    for zi, z in enumerate(site.zones):
        if z.frame != frame or not z.openings:
            continue
        walls = z.walls
        for op in z.openings:
            w = walls[op.wall - 1]
            a, b = np.asarray(w.start, float), np.asarray(w.end, float)
            u = (b - a) / w.length_m
            out.append((zi, w, op.kind, np.array([a + op.s0_m * u, a + op.s1_m * u])))
    return out


def wall_gaps(
    site: Site, zone_index: int, wall: Wall, segments: list[tuple[int, Wall, str, NDArray[np.float64]]] | None = None
) -> list[tuple[float, float]]:
    """Intervals (s0, s1) in metres along ``wall`` that are open: its own openings and those of any wall face of the
    same frame parallel to it and within ``OPENING_DEPTH_M``; merged, sorted."""
    zone = site.zones[zone_index]
    segs = opening_segments(site, zone.frame) if segments is None else segments
    a, b = np.asarray(wall.start, float), np.asarray(wall.end, float)
    length = wall.length_m
    u = (b - a) / length
    cos_tol = math.cos(math.radians(PARALLEL_DEG))
    found = []
    for zi, w, _kind, ends in segs:
        if zi != zone_index or w.index != wall.index:  # another face: parallel and close enough
            v = ends[1] - ends[0]
            if abs(float(np.dot(v, u))) < cos_tol * float(np.hypot(*v)):
                continue
            if max(abs(cross_z(u, e - a)) for e in ends) > OPENING_DEPTH_M:
                continue
        s = sorted(float(np.dot(e - a, u)) for e in ends)
        lo, hi = max(s[0], 0.0), min(s[1], length)
        if hi > lo + 1e-9:
            found.append((lo, hi))
    merged: list[tuple[float, float]] = []
    for lo, hi in sorted(found):
        if merged and lo <= merged[-1][1] + 1e-9:
            merged[-1] = (merged[-1][0], max(merged[-1][1], hi))
        else:
            merged.append((lo, hi))
    return merged


def solid_intervals(length_m: float, gaps: Sequence[tuple[float, float]]) -> list[tuple[float, float]]:
    """The parts of a wall of ``length_m`` outside the gaps."""
    out, at = [], 0.0
    for lo, hi in gaps:
        if lo > at + 1e-9:
            out.append((at, lo))
        at = max(at, hi)
    if length_m > at + 1e-9:
        out.append((at, length_m))
    return out


def space_of(zone: Zone, side: ScanSide) -> tuple[str, str]:
    """The space a station of ``zone`` scanning ``side`` stands in."""
    return ("in", zone.id) if side is ScanSide.INSIDE else ("out", zone.frame)


def opening_spaces(
    site: Site, passable_only: bool = True
) -> list[tuple[NDArray[np.float64], tuple[str, str], tuple[str, str]]]:
    """Each opening (of a kind in ``PASSABLE``, or any kind) as (2x2 end points, the space on one side, the space on
    the other), for every side its zone is scanned from; both spaces are the same where nothing lies behind it."""
    out = []
    for frame in dict.fromkeys(z.frame for z in site.zones):
        inside = [(z, z.polygon) for z in site.zones if z.frame == frame and ScanSide.INSIDE in z.scan_side.sides]
        for zi, _w, kind, ends in opening_segments(site, frame):
            if passable_only and kind not in PASSABLE:
                continue
            zone = site.zones[zi]
            t = (ends[1] - ends[0]) / np.hypot(*(ends[1] - ends[0]))
            left = np.array([-t[1], t[0]])
            mid = ends.mean(axis=0)
            for side in zone.scan_side.sides:
                behind = -left if side is ScanSide.INSIDE else left
                out.append((ends, space_of(zone, side), _space_behind(zone, side, mid, behind, inside)))
    return out


def accessible_areas(site: Site) -> dict[tuple[str, str], int]:
    """Each space (see :func:`space_of`) mapped to the number of its accessible area."""
    g = nx.Graph()
    for z in site.zones:
        g.add_nodes_from(space_of(z, s) for s in z.scan_side.sides)
    g.add_edges_from((a, b) for _ends, a, b in opening_spaces(site))
    for stair in site.stairs:
        g.add_edge(("in", stair.lower_zone), ("in", stair.upper_zone))
    return {
        space: k for k, comp in enumerate(sorted(nx.connected_components(g), key=lambda c: sorted(c))) for space in comp
    }


def seen_through(region: shapely.Geometry, ends: NDArray[np.float64], reach_m: float) -> shapely.Geometry:
    """The positions within ``reach_m`` of the middle of the opening ``ends`` whose segment to some point of
    ``region`` crosses the opening: where a station may stand to see a station of ``region`` through it (a link's first
    condition, :func:`planner.coverage.links.opening_links`; sight is not tested). Such a segment joins the two sides of
    the opening's line, so each side's part of ``region`` is taken in turn (its hull: a superset where it is not
    convex). For a convex part on one side the crossing point moves monotonically as the far end moves along a line, so
    its extremes over the part are at vertices, and a position qualifies when some vertex's segment crosses at or before
    one end and some vertex's at or after the other: the union of the half-planes bounded by the lines through a vertex
    and an end, intersected; the reach's disc is a circumscribed polygon (at most 0.13 % past it)."""
    a, b = np.asarray(ends[0], float), np.asarray(ends[1], float)
    mid, big = (a + b) / 2, 4 * reach_m + float(np.hypot(*(b - a)))
    disc = shapely.Point(*mid).buffer(reach_m / math.cos(math.pi / 64), quad_segs=16)  # circumscribed
    out = []
    for side in (1.0, -1.0):
        part = shapely.intersection(region, _half(a, b, mid + side * _normal(a, b), big))
        verts = np.asarray(shapely.get_coordinates(shapely.convex_hull(part)))
        if part.is_empty or not len(verts):
            continue
        beyond = _half(a, b, mid - side * _normal(a, b), big)
        # a vertex on the line crosses it where it stands: before b (after a) for every position, or for none
        along = (verts - a) @ (b - a) / float(np.dot(b - a, b - a))
        on = np.abs((verts - a) @ _normal(a, b)) <= 1e-9 * big
        near_b = _either(beyond, [_half(v, b, a, big) for v in verts[~on]], bool(np.any(along[on] <= 1.0)))
        near_a = _either(beyond, [_half(v, a, b, big) for v in verts[~on]], bool(np.any(along[on] >= 0.0)))
        out.append(shapely.intersection_all([beyond, near_b, near_a, disc]))
    return shapely.union_all(out) if out else shapely.Polygon()


def _either(whole: shapely.Geometry, halves: list[shapely.Geometry], always: bool) -> shapely.Geometry:
    """``whole`` where ``always``, else the union of ``halves`` (empty where there are none)."""
    if always:
        return whole
    return shapely.union_all(halves) if halves else shapely.Polygon()


def _normal(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """The unit normal to the left of a -> b."""
    d = (b - a) / max(float(np.hypot(*(b - a))), 1e-12)
    return np.array([-d[1], d[0]])


def _half(p: NDArray[np.float64], q: NDArray[np.float64], keep: NDArray[np.float64], big: float) -> shapely.Polygon:
    """The half-plane bounded by the line p-q on the side of ``keep``, as a square of side ``big`` (clipped later)."""
    d = (q - p) / max(float(np.hypot(*(q - p))), 1e-12)
    n = np.array([-d[1], d[0]])
    n = n if float(np.dot(keep - p, n)) >= 0 else -n
    return shapely.Polygon([p - big * d, p + big * d, p + big * d + big * n, p - big * d + big * n])


def _space_behind(
    zone: Zone,
    side: ScanSide,
    mid: NDArray[np.float64],
    behind: NDArray[np.float64],
    inside: list[tuple[Zone, shapely.Polygon]],
) -> tuple[str, str]:
    for depth in (0.01, 0.1, 0.5, OPENING_DEPTH_M + 0.1):
        p = shapely.Point(*(mid + depth * behind))
        hit = next(
            (z for z, poly in inside if (z.id != zone.id or side is not ScanSide.INSIDE) and poly.contains(p)), None
        )
        if hit is not None:
            return ("in", hit.id)
    return ("out", zone.frame)
