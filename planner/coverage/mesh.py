"""A site's blockers as triangles in 3-D: the scene the 3-D sight test (:mod:`planner.coverage.rays`) casts into.

Walls stand from their zone's floor up to their linear top edge (:class:`planner.site.model.Wall`), cut at openings
(full-height gaps); obstacles (site frame only) are capped prisms from 0 m to ``height_m``. A zone scanned from inside
may add its floor and ceiling as horizontal plates; a :class:`Slab` is any other one. A wall quad with a linear top is
planar: two triangles cover it exactly. Each triangle keeps its ``source``, so that a sight line can skip the surface
its target lies on:

- a wall: :func:`planner.coverage.visibility.wall_key` of (zone index, 1-based wall index), >= 0, the key the plan-view
  blockers use;
- obstacle k (index into ``site.obstacles``): :func:`obstacle_key` ``= -1 - k``;
- slab k (index into the slabs given): :func:`slab_key` ``= SLAB_KEY_BASE - k``;
- the floor and the ceiling of zone i: :func:`floor_key` and :func:`ceiling_key`, ``SURFACE_KEY_BASE - 2i`` and ``- 2i -
  1``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.coverage.openings import opening_segments, solid_intervals, wall_gaps
from planner.coverage.visibility import wall_key
from planner.site.geometry import read_only
from planner.site.model import SITE_FRAME, ScanSide, Site

#: ``kind`` of a triangle: a wall, an obstacle prism (side or top), a slab, a zone's floor, a zone's ceiling
KIND_WALL, KIND_OBSTACLE, KIND_SLAB, KIND_FLOOR, KIND_CEILING = 0, 1, 2, 3, 4
#: slab keys count down from here (obstacle keys count down from -1 and stay above it)
SLAB_KEY_BASE = -(2**40)
#: zones' floor and ceiling keys count down from here (slab keys stay above it)
SURFACE_KEY_BASE = -(2**41)

Floats = NDArray[np.float64]


# the source keys of the module docstring


def obstacle_key(k: int) -> int:
    return -1 - k


def slab_key(k: int) -> int:
    return SLAB_KEY_BASE - k


def floor_key(zone_index: int) -> int:
    return SURFACE_KEY_BASE - 2 * zone_index


def ceiling_key(zone_index: int) -> int:
    return SURFACE_KEY_BASE - 2 * zone_index - 1


@dataclass(frozen=True)
class Slab:
    """A horizontal plate at height ``z_m``: ``outline`` (a simple polygon) less its ``holes`` (stairwells)."""

    outline: tuple[tuple[float, float], ...]
    z_m: float
    holes: tuple[tuple[tuple[float, float], ...], ...] = ()
    name: str = ""


@dataclass(frozen=True, eq=False)
class SiteMesh:
    """Triangles in 3-D with the surface each came from. ``vertices`` is V x 3 (x, y, z in metres), ``triangles`` T x 3
    indices into it, ``source`` (T,) the source key of each triangle (see the module docstring) and ``kind`` (T,) its
    ``KIND_*``. The arrays are read-only; the mesh compares by identity, so that :mod:`planner.coverage.rays` can keep
    its index."""

    vertices: NDArray[np.float64]
    triangles: NDArray[np.int64]
    source: NDArray[np.int64]
    kind: NDArray[np.int8]

    def __post_init__(self) -> None:
        for name in ("vertices", "triangles", "source", "kind"):
            object.__setattr__(self, name, read_only(getattr(self, name)))
        if self.vertices.ndim != 2 or self.vertices.shape[1] != 3:
            raise ValueError(f"vertices must be V x 3, got {self.vertices.shape}")
        if self.triangles.ndim != 2 or self.triangles.shape[1] != 3:
            raise ValueError(f"triangles must be T x 3, got {self.triangles.shape}")
        if not len(self.source) == len(self.kind) == len(self.triangles):
            raise ValueError("source and kind need one entry per triangle")

    def __len__(self) -> int:
        return len(self.triangles)

    def corners(self) -> NDArray[np.float64]:
        """The triangles' corners, T x 3 (corner) x 3 (x, y, z)."""
        return self.vertices[self.triangles]

    def translated(self, dx_m: float, dy_m: float, dz_m: float = 0.0) -> SiteMesh:
        """The same mesh moved by (dx_m, dy_m, dz_m)."""
        return SiteMesh(self.vertices + np.array([dx_m, dy_m, dz_m]), self.triangles, self.source, self.kind)


def quads(a: Floats, b: Floats, z0: Floats, za: Floats, zb: Floats) -> tuple[Floats, NDArray[np.int64]]:
    """Vertical quads over the plan segments a-b (n x 2), from ``z0`` up to ``za`` at a and ``zb`` at b: 4n vertices and
    2n triangles (quad k: triangles 2k and 2k + 1)."""
    n = len(a)
    v = np.empty((n, 4, 3))
    v[:, 0, :2], v[:, 1, :2], v[:, 2, :2], v[:, 3, :2] = a, b, b, a
    v[:, 0, 2], v[:, 1, 2], v[:, 2, 2], v[:, 3, 2] = z0, z0, zb, za
    base = 4 * np.arange(n)[:, None, None]
    tri = base + np.array([[0, 1, 2], [0, 2, 3]])[None]
    return v.reshape(-1, 3), tri.reshape(-1, 3)


def cap(polygon: shapely.Polygon, z_m: float) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """A horizontal polygon (holes allowed) at ``z_m`` as triangles: the constrained Delaunay triangulation of GEOS, so
    a concave outline is covered exactly, nothing outside it. Returns 3m vertices, m triangles."""
    parts = shapely.get_parts(shapely.constrained_delaunay_triangles(polygon))
    xy = shapely.get_coordinates(shapely.get_exterior_ring(parts)).reshape(len(parts), 4, 2)[:, :3]
    v = np.concatenate([xy.reshape(-1, 2), np.full((3 * len(parts), 1), float(z_m))], axis=1)
    return v, np.arange(3 * len(parts)).reshape(-1, 3)


def site_mesh(
    site: Site,
    frame: str = SITE_FRAME,
    floors_m: Mapping[str, float] | None = None,
    slabs: Sequence[Slab] = (),
    floors: bool = False,
    ceilings: bool = False,
) -> SiteMesh:
    """Triangulate the blockers of ``frame``: its zones' walls (outline and holes, cut at openings), obstacles (site
    frame), ``slabs`` and, with ``floors``/``ceilings``, the floor and ceiling of each zone scanned from inside.
    ``floors_m``: a zone's floor level by zone id, in place of its ``floor_level_m``. O(walls + obstacle and slab
    vertices). Shared faces of placed zones are meshed once per zone (each under its own key); zone holes (piers) get no
    top cap: a line entering one through its top leaves through a wall."""
    levels = floors_m or {}
    parts = _Parts()
    walls = _wall_quads(site, frame, levels)
    if walls is not None:
        parts.add(*walls, KIND_WALL)
    if frame == SITE_FRAME:
        for k, ob in enumerate(site.obstacles):
            xy = np.asarray(ob.vertices, float)
            n = len(xy)
            v, t = quads(xy, np.roll(xy, -1, axis=0), np.zeros(n), np.full(n, ob.height_m), np.full(n, ob.height_m))
            parts.add(v, t, obstacle_key(k), KIND_OBSTACLE)
            parts.add(*cap(shapely.Polygon(xy), ob.height_m), obstacle_key(k), KIND_OBSTACLE)
    for k, s in enumerate(slabs):
        parts.add(*cap(shapely.Polygon(s.outline, list(s.holes)), s.z_m), slab_key(k), KIND_SLAB)
    for zi, zone in enumerate(site.zones):
        if zone.frame != frame or ScanSide.INSIDE not in zone.scan_side.sides:
            continue
        level = float(levels.get(zone.id, zone.floor_level_m))
        if floors:
            parts.add(*cap(zone.polygon, level), floor_key(zi), KIND_FLOOR)
        if ceilings and zone.ceiling_height_m is not None:
            parts.add(*cap(zone.polygon, level + zone.ceiling_height_m), ceiling_key(zi), KIND_CEILING)
    return parts.mesh()


def _wall_quads(
    site: Site, frame: str, levels: Mapping[str, float]
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64]] | None:
    """The solid parts of the walls of ``frame``'s zones as quads (vertices, triangles, source key per triangle), cut at
    openings; None when there is none."""
    segments = opening_segments(site, frame)
    a, b, z0, za, zb, key = [], [], [], [], [], []
    for zi, zone in enumerate(site.zones):
        if zone.frame != frame:
            continue
        floor = float(levels.get(zone.id, zone.floor_level_m))
        for w in zone.walls:
            start, end, length = np.asarray(w.start, float), np.asarray(w.end, float), w.length_m
            gaps = wall_gaps(site, zi, w, segments) if segments else []
            for lo, hi in solid_intervals(length, gaps):
                a.append(start + (end - start) * (lo / length))
                b.append(start + (end - start) * (hi / length))
                z0.append(floor)
                za.append(floor + float(w.height_at(lo / length)))
                zb.append(floor + float(w.height_at(hi / length)))
                key.append(int(wall_key(zi, w.index)))
    if not a:
        return None
    v, t = quads(np.array(a), np.array(b), np.array(z0), np.array(za), np.array(zb))
    return v, t, np.repeat(np.array(key, np.int64), 2)


class _Parts:
    """Triangle sets collected for a :class:`SiteMesh`, each with its source key(s) and kind."""

    def __init__(self) -> None:
        self.verts: list[NDArray[np.float64]] = []
        self.tris: list[NDArray[np.int64]] = []
        self.sources: list[NDArray[np.int64]] = []
        self.kinds: list[NDArray[np.int8]] = []

    def add(self, v: NDArray[np.float64], t: NDArray[np.int64], src: NDArray[np.int64] | int, kind: int) -> None:
        self.tris.append(t + sum(len(x) for x in self.verts))
        self.verts.append(v)
        self.sources.append(np.broadcast_to(np.asarray(src, np.int64), (len(t),)))
        self.kinds.append(np.full(len(t), kind, np.int8))

    def mesh(self) -> SiteMesh:
        if not self.tris:
            return SiteMesh(np.zeros((0, 3)), np.zeros((0, 3), np.int64), np.zeros(0, np.int64), np.zeros(0, np.int8))
        cat = np.concatenate
        return SiteMesh(cat(self.verts), cat(self.tris), cat(self.sources), cat(self.kinds))
