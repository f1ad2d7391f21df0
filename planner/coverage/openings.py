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


def accessible_areas(site: Site) -> dict[tuple[str, str], int]:
    """Each space (see :func:`space_of`) mapped to the number of its accessible area."""
    g = nx.Graph()
    for z in site.zones:
        g.add_nodes_from(space_of(z, s) for s in z.scan_side.sides)
    for frame in dict.fromkeys(z.frame for z in site.zones):
        inside = [(z, z.polygon) for z in site.zones if z.frame == frame and ScanSide.INSIDE in z.scan_side.sides]
        for zi, _w, kind, ends in opening_segments(site, frame):
            if kind not in PASSABLE:
                continue
            zone = site.zones[zi]
            t = (ends[1] - ends[0]) / np.hypot(*(ends[1] - ends[0]))
            left = np.array([-t[1], t[0]])
            mid = ends.mean(axis=0)
            for side in zone.scan_side.sides:
                behind = -left if side is ScanSide.INSIDE else left
                g.add_edge(space_of(zone, side), _space_behind(zone, side, mid, behind, inside))
    for stair in site.stairs:
        g.add_edge(("in", stair.lower_zone), ("in", stair.upper_zone))
    return {
        space: k for k, comp in enumerate(sorted(nx.connected_components(g), key=lambda c: sorted(c))) for space in comp
    }


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
