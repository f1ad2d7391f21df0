"""A brute-force oracle of the floor and ceiling sight rules (docs/surfaces.md), written apart from
planner.coverage.surface_sight: plain Python over every station, patch and corner, no shapely, no numpy.

It answers True (seen), False (not seen) or None (too close to a limit to call: within ``MARGIN_M`` or ``MARGIN_DEG`` of
it), so that a property test compares only the decided pairs. It knows one convex room (counter-clockwise) and at most
one axis-aligned box obstacle.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

MARGIN_M = 1e-5
MARGIN_DEG = 1e-5

Point = tuple[float, float]


@dataclass(frozen=True)
class Scene:
    room: Sequence[Point]  # convex, counter-clockwise
    floor_level: float
    ceiling: float | None
    box: tuple[float, float, float, float] | None  # x0, y0, x1, y1 of the obstacle
    box_height: float
    ih: float
    s_max: float
    theta: float
    theta_floor: float | None
    nadir: float | None
    zenith: float | None


def and3(*values: bool | None) -> bool | None:
    """Three-valued AND: False if any is False, else None if any is undecided, else True."""
    if any(v is False for v in values):
        return False
    return None if any(v is None for v in values) else True


def at_most(value: float, limit: float, margin: float) -> bool | None:
    """value <= limit, decided only outside the margin."""
    if value <= limit - margin:
        return True
    return False if value > limit + margin else None


def in_room(p: Point, room: Sequence[Point]) -> bool | None:
    """p inside the convex counter-clockwise room (the distance to each side line, signed)."""
    out = []
    for k in range(len(room)):
        (ax, ay), (bx, by) = room[k], room[(k + 1) % len(room)]
        length = math.hypot(bx - ax, by - ay)
        left = ((bx - ax) * (p[1] - ay) - (by - ay) * (p[0] - ax)) / length
        out.append(at_most(-left, 0.0, MARGIN_M))
    return and3(*out)


def in_box(p: Point, box: tuple[float, float, float, float]) -> bool | None:
    """p strictly inside the box (the depth inside, decided outside the margin)."""
    x0, y0, x1, y1 = box
    depth = min(p[0] - x0, x1 - p[0], p[1] - y0, y1 - p[1])
    return None if abs(depth) <= MARGIN_M else depth > 0


def nearest(p: Point, poly: Sequence[Point]) -> float:
    """Distance from p to the polygon (0 inside: even-odd ray casting)."""
    inside = False
    best = math.inf
    for k in range(len(poly)):
        (ax, ay), (bx, by) = poly[k], poly[(k + 1) % len(poly)]
        if (ay > p[1]) != (by > p[1]) and p[0] < ax + (p[1] - ay) * (bx - ax) / (by - ay):
            inside = not inside
        dx, dy = bx - ax, by - ay
        t = max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / (dx * dx + dy * dy or 1.0)))
        best = min(best, math.hypot(p[0] - ax - t * dx, p[1] - ay - t * dy))
    return 0.0 if inside else best


def separation(tri: Sequence[Point], box: tuple[float, float, float, float]) -> float:
    """Separating-axis gap between a triangle and a box: > 0 apart, < 0 overlapping by that depth."""
    x0, y0, x1, y1 = box
    corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    axes = [(1.0, 0.0), (0.0, 1.0)]
    for k in range(3):
        (ax, ay), (bx, by) = tri[k], tri[(k + 1) % 3]
        n = math.hypot(bx - ax, by - ay)
        if n > 1e-12:
            axes.append((-(by - ay) / n, (bx - ax) / n))
    gap = -math.inf
    for ux, uy in axes:
        t = [x * ux + y * uy for x, y in tri]
        b = [x * ux + y * uy for x, y in corners]
        gap = max(gap, min(b) - max(t), min(t) - max(b))
    return gap


def oracle_sees(scene: Scene, station: Point, kind: str, height: float, poly: Sequence[Point]) -> bool | None:
    """Does the station see the whole patch ``poly`` (its vertices) of ``kind`` at ``height``?"""
    box = scene.box
    standing = in_room(station, scene.room)  # on the floor: in the room and not in the obstacle
    if box is not None:
        inside = in_box(station, box)
        standing = and3(standing, None if inside is None else not inside)
    dz = height - (scene.floor_level + scene.ih)
    front = at_most(dz, 0.0, MARGIN_M) if kind == "floor" else at_most(-dz, 0.0, MARGIN_M)
    if front is not True:
        return and3(standing, front)
    normal_z = 1.0 if kind == "floor" else -1.0
    theta = scene.theta_floor if scene.theta_floor is not None else scene.theta
    checks: list[bool | None] = [standing]
    for cx, cy in poly:
        vx, vy = cx - station[0], cy - station[1]
        r = math.sqrt(vx * vx + vy * vy + dz * dz)
        checks.append(at_most(r, scene.s_max, MARGIN_M))
        cos_i = -(dz * normal_z) / r  # the ray from the surface back to the instrument, against the normal
        checks.append(at_most(math.degrees(math.acos(max(-1.0, min(1.0, cos_i)))), theta, MARGIN_DEG))
    cone = scene.nadir if dz < 0 else scene.zenith
    if cone is not None and cone > 0:
        off_axis = math.degrees(math.atan2(nearest(station, poly), abs(dz)))
        checks.append(at_most(cone, off_axis, MARGIN_DEG))
    if box is not None:
        blocks = True if kind == "floor" else at_most(scene.ih, scene.box_height, MARGIN_M)
        if blocks is not False:
            for k in range(len(poly)):
                gap = separation((station, poly[k], poly[(k + 1) % len(poly)]), box)
                clear = True if gap > MARGIN_M else (False if gap < -MARGIN_M else None)
                checks.append(None if blocks is None and clear is False else clear)
    return and3(*checks)
