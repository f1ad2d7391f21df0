"""Sight in 3-D: does anything of the site's mesh stand between a station and a point?

:func:`occluded` answers, for N segments origin -> end at once, whether each comes within ``EPS_TOUCH_M`` of a triangle
of a :class:`planner.coverage.mesh.SiteMesh` (other than those of ``skip[i]``, the surface the end lies on). The
conventions are those of the plan-view test (:mod:`planner.coverage.visibility`):

- touching counts as blocked (distance at most ``EPS_TOUCH_M``): a line grazing a wall's top edge is blocked;
- each segment stops ``EPS_SHORTEN_M`` (at most half its length) before its end, so that a point on a wall is not hidden
  by the walls that meet it there; the origin (a station, off every surface) is kept.

How: the pieces (at most ``PIECE_M`` in plan) of each chunk of segments query an STRtree of the triangles' plan boxes;
conservative filters (:meth:`RayIndex.pairs`) thin the pairs, and :func:`segment_hits_triangles` tests the rest exactly,
in batches. Work grows with the pairs whose plan boxes meet; no N x T array anywhere.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from planner.coverage.mesh import SiteMesh
from planner.coverage.visibility import EPS_SHORTEN_M, EPS_SIGHT_M

#: a segment within this distance of a triangle is blocked by it (the plan view's EPS_SIGHT_M)
EPS_TOUCH_M = EPS_SIGHT_M
#: segments per tree query: the pairs of a chunk (and their memory) grow with it
SEGMENT_CHUNK = 4096
#: pairs per exact test (bounds the memory of its arrays)
PAIR_BATCH = 1 << 16
#: the filters before the exact test keep pairs within MARGIN * eps_m (rounding of absolute coordinates is far less)
MARGIN = 2.0
#: segments are cut into pieces of at most this length (plan view) for the tree query, so a long diagonal segment meets
#: the triangles near it, not all those in its bounding box
PIECE_M = 6.0
#: the ``skip`` of a segment that skips nothing (no source key has this value)
NO_SKIP = int(np.iinfo(np.int64).min)


def _dot(u: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.einsum("ij,ij->i", u, v)


@dataclass(frozen=True, eq=False)
class RayIndex:
    """What :func:`occluded` keeps of a mesh (T triangles): corners (T x 3 x 3); plan-view boxes (T x 4: centre x, y,
    half size x, y) and in an STRtree; height ranges; unit normals (T x 3) and plane offsets; sources."""

    corners: NDArray[np.float64]
    plan: NDArray[np.float64]
    zlo: NDArray[np.float64]
    zhi: NDArray[np.float64]
    normal: NDArray[np.float64]
    offset: NDArray[np.float64]
    source: NDArray[np.int64]
    tree: shapely.STRtree

    def pairs(
        self, o: NDArray[np.float64], e: NDArray[np.float64], skip: NDArray[np.int64], eps_m: float
    ) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
        """(segment, triangle) pairs, sorted, that may come within ``eps_m``, by conservative filters (each with a
        margin of ``MARGIN`` * eps_m): 1. the plan box of a piece (at most ``PIECE_M``) of the segment meets the
        triangle's (the tree); 2. the segment's plan line passes within reach of that box; 3. the triangle is not
        skipped and the height ranges overlap; 4. the segment's ends are not both beyond the triangle's plane on one
        side."""
        m = MARGIN * eps_m
        lo, hi = np.minimum(o, e), np.maximum(o, e)
        d = e[:, :2] - o[:, :2]
        length = np.hypot(d[:, 0], d[:, 1])
        k = np.maximum(1, np.ceil(length / PIECE_M)).astype(np.int64)  # pieces per segment
        seg = np.repeat(np.arange(len(o)), k)
        j = (np.arange(len(seg)) - np.repeat(np.cumsum(k) - k, k)).astype(float)
        p0 = o[seg, :2] + d[seg] * (j / k[seg])[:, None]
        p1 = o[seg, :2] + d[seg] * ((j + 1) / k[seg])[:, None]
        plo, phi = np.minimum(p0, p1) - m, np.maximum(p0, p1) + m
        pi, ti = self.tree.query(shapely.box(plo[:, 0], plo[:, 1], phi[:, 0], phi[:, 1]))
        si = seg[pi]
        nx, ny = -d[:, 1] / np.where(length > 0, length, 1.0), d[:, 0] / np.where(length > 0, length, 1.0)
        line = np.column_stack([nx, ny, np.abs(nx), np.abs(ny), nx * o[:, 0] + ny * o[:, 1]])[si]
        box = self.plan[ti]  # centre x, centre y, half x, half y
        gap = np.abs(line[:, 0] * box[:, 0] + line[:, 1] * box[:, 1] - line[:, 4])
        keep = gap <= line[:, 2] * box[:, 2] + line[:, 3] * box[:, 3] + m
        si, ti = si[keep], ti[keep]
        keep = (self.source[ti] != skip[si]) & (lo[si, 2] <= self.zhi[ti] + m) & (hi[si, 2] >= self.zlo[ti] - m)
        si, ti = si[keep], ti[keep]
        n, off = self.normal[ti], self.offset[ti]
        s0, s1 = _dot(n, o[si]) - off, _dot(n, e[si]) - off
        keep = ~(((s0 > m) & (s1 > m)) | ((s0 < -m) & (s1 < -m)))
        pair = np.unique(si[keep] * len(self.source) + ti[keep])  # a triangle near two pieces: once
        return pair // len(self.source), pair % len(self.source)


_INDEX: weakref.WeakKeyDictionary[SiteMesh, RayIndex] = weakref.WeakKeyDictionary()


def ray_index(mesh: SiteMesh) -> RayIndex:
    """The index of ``mesh`` for :func:`occluded`, built once per mesh and kept while it lives."""
    idx = _INDEX.get(mesh)
    if idx is None:
        c = mesh.corners()
        lo, hi = c.min(axis=1), c.max(axis=1)
        n = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
        nn = np.sqrt(_dot(n, n))
        unit = n / np.where(nn > 0, nn, 1.0)[:, None]  # a degenerate triangle: normal 0, never out by its plane
        idx = RayIndex(
            corners=c,
            plan=np.concatenate([(lo[:, :2] + hi[:, :2]) / 2.0, (hi[:, :2] - lo[:, :2]) / 2.0], axis=1),
            zlo=lo[:, 2],
            zhi=hi[:, 2],
            normal=unit,
            offset=_dot(unit, c[:, 0]),
            source=mesh.source,
            tree=shapely.STRtree(shapely.box(lo[:, 0], lo[:, 1], hi[:, 0], hi[:, 1])),
        )
        _INDEX[mesh] = idx
    return idx


def _inside(
    n: NDArray[np.float64], a: NDArray[np.float64], b: NDArray[np.float64], c: NDArray[np.float64], x: NDArray
) -> NDArray[np.bool_]:
    """Points x of the triangles' planes (normal n, any length) inside or on the closed triangles a-b-c."""
    ok = _dot(n, np.cross(b - a, x - a)) >= 0
    ok &= _dot(n, np.cross(c - b, x - b)) >= 0
    ok &= _dot(n, np.cross(a - c, x - c)) >= 0
    return ok


def segment_distance2(
    p1: NDArray[np.float64], d1: NDArray[np.float64], p2: NDArray[np.float64], d2: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Squared distance between the segments p1 + s d1 and p2 + t d2 (s, t in [0, 1]), row-wise. Ericson, *Real-Time
    Collision Detection* (2005), 5.1.9: the closest points of the lines, clamped to the segments; parallel and
    zero-length segments included. O(rows)."""
    r = p1 - p2
    a, e, f, c, b = _dot(d1, d1), _dot(d2, d2), _dot(d2, r), _dot(d1, r), _dot(d1, d2)
    sa, se = np.where(a > 0, a, 1.0), np.where(e > 0, e, 1.0)
    denom = a * e - b * b
    general = (a > 0) & (e > 0) & (denom > 1e-14 * a * e)
    s = np.where(general, np.clip((b * f - c * e) / np.where(general, denom, 1.0), 0.0, 1.0), 0.0)
    t = np.where(e > 0, (b * s + f) / se, 0.0)
    s = np.where(t < 0, np.clip(-c / sa, 0.0, 1.0), np.where(t > 1, np.clip((b - c) / sa, 0.0, 1.0), s))
    s = np.where(a > 0, s, 0.0)
    t = np.clip(t, 0.0, 1.0)
    diff = r + d1 * s[:, None] - d2 * t[:, None]
    return _dot(diff, diff)


def segment_hits_triangles(
    o: NDArray[np.float64], e: NDArray[np.float64], tri: NDArray[np.float64], eps_m: float = EPS_TOUCH_M
) -> NDArray[np.bool_]:
    """Row-wise: is the closed segment o-e within ``eps_m`` of the closed triangle ``tri`` (P x 3 x 3)? The distance is
    0 where the segment crosses the triangle, else reached at an end of the segment (over the face) or on an edge of the
    triangle; so the segment is blocked when 1. it crosses the plane inside the triangle, 2. an end lies within
    ``eps_m`` of the plane and projects inside the triangle, or 3. an edge comes within ``eps_m`` of it
    (:func:`segment_distance2`). Segments with both ends beyond ``eps_m`` on one side of the plane are out first.
    Everything is relative to ``o`` (a translation of the scene changes only the last bits)."""
    o, e, tri = np.asarray(o, float), np.asarray(e, float), np.asarray(tri, float)
    hit = np.zeros(len(o), dtype=bool)
    d = e - o
    a, b, c = tri[:, 0] - o, tri[:, 1] - o, tri[:, 2] - o
    n = np.cross(b - a, c - a)
    nn = np.sqrt(_dot(n, n))
    unit = n / np.where(nn > 0, nn, 1.0)[:, None]
    s0 = -_dot(unit, a)
    s1 = s0 + _dot(unit, d)
    near = np.flatnonzero(~(((s0 > eps_m) & (s1 > eps_m)) | ((s0 < -eps_m) & (s1 < -eps_m))))
    if near.size == 0:
        return hit
    d, a, b, c, n, unit, s0, s1 = d[near], a[near], b[near], c[near], n[near], unit[near], s0[near], s1[near]
    flat = nn[near] > 0
    den = s0 - s1
    crosses = flat & (s0 * s1 <= 0) & (den != 0)
    x = d * np.where(crosses, s0 / np.where(den != 0, den, 1.0), 0.0)[:, None]
    h = crosses & _inside(n, a, b, c, x)
    for q, s in ((np.zeros_like(d), s0), (d, s1)):  # an end over the face
        h |= flat & (np.abs(s) <= eps_m) & _inside(n, a, b, c, q - unit * s[:, None])
    rest = np.flatnonzero(~h)
    if rest.size:
        zero, dr = np.zeros((rest.size, 3)), d[rest]
        ar, br, cr = a[rest], b[rest], c[rest]
        d2 = np.minimum(segment_distance2(zero, dr, ar, br - ar), segment_distance2(zero, dr, br, cr - br))
        d2 = np.minimum(d2, segment_distance2(zero, dr, cr, ar - cr))
        h[rest] = d2 <= eps_m * eps_m
    hit[near] = h
    return hit


def shortened_ends(
    origins: NDArray[np.float64], ends: NDArray[np.float64], shorten_m: float = EPS_SHORTEN_M
) -> NDArray[np.float64]:
    """Each end moved ``shorten_m`` towards its origin (at most half the segment's length)."""
    v = origins - ends
    length = np.sqrt(_dot(v, v))
    step = np.minimum(shorten_m, length / 2.0) / np.where(length > 0, length, 1.0)
    return ends + v * step[:, None]


def occluded(
    mesh: SiteMesh,
    origins: ArrayLike,
    ends: ArrayLike,
    skip: ArrayLike | None = None,
    *,
    eps_m: float = EPS_TOUCH_M,
    shorten_m: float = EPS_SHORTEN_M,
    chunk: int = SEGMENT_CHUNK,
) -> NDArray[np.bool_]:
    """Whether each segment ``origins[i]`` -> ``ends[i]`` (N x 3, m) is blocked (module docstring). ``skip``: N source
    keys (or None) whose triangles do not block segment i (the target's own wall; ``NO_SKIP``: none). Skip only a wall:
    an obstacle skipped would no longer hide its far side. Memory O(a chunk's pairs)."""
    o = np.asarray(origins, dtype=float).reshape(-1, 3)
    e = np.asarray(ends, dtype=float).reshape(-1, 3)
    if o.shape != e.shape:
        raise ValueError(f"origins and ends differ in shape: {o.shape} vs {e.shape}")
    n = len(o)
    sk = np.full(n, NO_SKIP, np.int64) if skip is None else np.asarray(skip, dtype=np.int64).reshape(-1)
    if len(sk) != n:
        raise ValueError(f"skip needs {n} keys, got {len(sk)}")
    out = np.zeros(n, dtype=bool)
    if n == 0 or len(mesh) == 0:
        return out
    e = shortened_ends(o, e, shorten_m)
    idx = ray_index(mesh)
    for c0 in range(0, n, chunk):
        oc, ec, kc = o[c0 : c0 + chunk], e[c0 : c0 + chunk], sk[c0 : c0 + chunk]
        blocked = out[c0 : c0 + chunk]  # a view: writes go to out
        si, ti = idx.pairs(oc, ec, kc, eps_m)
        for p0 in range(0, len(si), PAIR_BATCH):
            ps, pt = si[p0 : p0 + PAIR_BATCH], ti[p0 : p0 + PAIR_BATCH]
            live = ~blocked[ps]
            ps, pt = ps[live], pt[live]
            if ps.size:
                blocked[ps[segment_hits_triangles(oc[ps], ec[ps], idx.corners[pt], eps_m)]] = True
    return out
