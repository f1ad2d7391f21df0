"""Two faces of one wall: sides of two zones placed together that lie on the same line.

The two faces of a shared wall lie on one line only to within the placement residuals, so one may lie a hair IN FRONT of
the other and, as a blocker, hide it from its own room. A face is never hidden by the other face of its own wall: each
shared stretch blocks sight under the key of its partner face, which the sight test skips for the partner's pieces.
Where a wall of B meets A's wall (a junction), B's wall end may poke a hair into A: such ends are cut back by
``JUNCTION_M`` and their vertices dropped (A's wall still blocks beyond), leaving a gap of at most 2 x ``JUNCTION_M``
that a sight line would have to pass twice.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.coverage.visibility import wall_key
from planner.site.geometry import cross_z
from planner.site.model import Site

#: faces of one wall lie within this distance of each other's line where they overlap (placement residuals and
#: printed-data misfits)
COINCIDENT_M = 0.15
#: wall ends within this distance of another zone's boundary are cut back by it (junctions)
JUNCTION_M = 0.05
#: and run parallel within this angle
PARALLEL_DEG = 2.0


def partner_stretches(site: Site, frame: str) -> dict[tuple[int, int], list[tuple[float, float, int]]]:
    """For each wall (zone index, wall index) of ``frame`` that shares a stretch with a face of another zone: the
    stretches (s0, s1) in metres along it and the partner's wall key."""
    walls = [(zi, w) for zi, z in enumerate(site.zones) if z.frame == frame for w in z.walls]
    if len({zi for zi, _ in walls}) < 2:
        return {}
    lines = shapely.linestrings([[w.start, w.end] for _, w in walls])
    tree = shapely.STRtree(lines)
    left, right = tree.query(lines, predicate="dwithin", distance=COINCIDENT_M)
    cos_tol = math.cos(math.radians(PARALLEL_DEG))
    out: dict[tuple[int, int], list[tuple[float, float, int]]] = {}
    for i, j in zip(left.tolist(), right.tolist()):
        (zi, wi), (zj, wj) = walls[i], walls[j]
        if zi == zj:
            continue
        stretch = _shared(wi.start, wi.end, wj.start, wj.end, cos_tol)
        if stretch is not None:
            out.setdefault((zi, wi.index), []).append((*stretch, int(wall_key(zj, wj.index))))
    return out


def _shared(a0, a1, b0, b1, cos_tol: float) -> tuple[float, float] | None:
    """The stretch of segment a (metres along it) that segment b covers, when b lies on a's line."""
    a0, a1, b0, b1 = (np.asarray(p, dtype=float) for p in (a0, a1, b0, b1))
    la = float(np.hypot(*(a1 - a0)))
    u = (a1 - a0) / la
    v = b1 - b0
    if abs(float(np.dot(u, v))) < cos_tol * float(np.hypot(*v)):
        return None
    (t0, o0), (t1, o1) = sorted((float(np.dot(p - a0, u)), cross_z(u, p - a0)) for p in (b0, b1))
    lo, hi = max(t0, 0.0), min(t1, la)
    if hi <= lo + JUNCTION_M:
        return None
    off = lambda t: o0 + (o1 - o0) * (t - t0) / (t1 - t0)  # noqa: E731  b's offset from a's line at t
    return (lo, hi) if max(abs(off(lo)), abs(off(hi))) <= COINCIDENT_M else None


def keyed_parts(
    lo: float, hi: float, own_key: int, stretches: list[tuple[float, float, int]]
) -> list[tuple[float, float, int]]:
    """Split the solid part lo..hi of a wall at its shared stretches: (s0, s1, key) pieces."""
    cuts = sorted({lo, hi, *(min(max(x, lo), hi) for s0, s1, _ in stretches for x in (s0, s1))})
    out = []
    for s0, s1 in zip(cuts[:-1], cuts[1:]):
        if s1 <= s0 + 1e-9:
            continue
        mid = (s0 + s1) / 2
        key = next((k for t0, t1, k in stretches if t0 <= mid <= t1), own_key)
        out.append((s0, s1, key))
    return out


def trim_at_junctions(
    site: Site, zi: int, a: NDArray[np.float64], b: NDArray[np.float64], key: NDArray[np.int64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64], NDArray[np.float64]]:
    """Blocking parts of zone ``zi`` with their ends cut back by ``COINCIDENT_M`` where they meet another zone's
    boundary (a wall of B that starts at A's wall may poke a hair into A), and the vertices of the parts away from other
    zones' boundaries. A shared stretch (partner key) is cut back at both ends too: its end may pass a hair beyond the
    partner's corner."""
    zone = site.zones[zi]
    others = [z.polygon.boundary for j, z in enumerate(site.zones) if j != zi and z.frame == zone.frame]
    if not len(a) or not others:
        return a, b, key, np.concatenate([a, b])
    near = shapely.union_all(others)
    d0 = shapely.distance(near, shapely.points(a)) <= JUNCTION_M
    d1 = shapely.distance(near, shapely.points(b)) <= JUNCTION_M
    length = np.hypot(*(b - a).T)
    u = (b - a) / np.maximum(length, 1e-300)[:, None]
    cut0 = np.where(d0, JUNCTION_M, 0.0)
    cut1 = np.where(d1, JUNCTION_M, 0.0)
    keep = length > cut0 + cut1 + 1e-9
    a2 = (a + u * cut0[:, None])[keep]
    b2 = (b - u * cut1[:, None])[keep]
    verts = np.concatenate([a[~d0], b[~d1]])
    return a2, b2, key[keep], verts
