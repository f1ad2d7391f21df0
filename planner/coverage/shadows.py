"""The sight part of a coverage region (:mod:`planner.coverage.regions`): the positions from which a wall or obstacle
edge near a piece meets the view of the whole piece (its shadows), and the region minus them.

A region loses only the shadows that meet it: the union of those few is the same point set, inside the region, as the
union of all (a shadow apart from the region takes nothing from it), and far cheaper, as most shadows of the blockers
near a piece reach far past its region.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.coverage.targets import Targets
from planner.coverage.visibility import EPS_SHORTEN_M, EPS_SIGHT_M, Blockers, wall_key

#: the sight test blocks a line whose end, moved EPS_SHORTEN_M toward the station, lies within EPS_SIGHT_M of a wall
#: line through the piece's end: a sliver of this half-angle
GRAZE_DEG = math.degrees(math.asin(EPS_SIGHT_M / EPS_SHORTEN_M))
#: grid of the snap-rounded overlay used when GEOS's floating overlay of the shadows fails (1 um)
SNAP_GRID_M = 1e-6


def unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    n = np.hypot(v[..., 0], v[..., 1])
    return v / np.where(n > 0, n, 1.0)[..., None]


def _away(q: NDArray, x: NDArray) -> NDArray[np.float64]:
    """Unit directions from x to q, zero where q is x up to rounding (an edge ending at a piece's end, whose coordinates
    may differ in the last bit: the direction of a 1e-16 m vector is noise; _grazing covers it)."""
    v = q - x
    return np.where((np.hypot(v[..., 0], v[..., 1]) < 1e-6)[..., None], 0.0, unit(v))


def chunk_shadows(
    targets: Targets,
    idx: NDArray[np.int64],
    ks: NDArray[np.object_],
    blockers: Blockers | None,
    far: float,
    outer: bool,
    boxes: NDArray[np.float64] | None = None,
) -> tuple[NDArray[np.int64], NDArray[np.object_]]:
    """The shadows of the blockers near each piece of ``idx`` (a blocker meeting its ``ks`` region or the piece itself,
    other than the piece's own wall), drawn for all the pieces at once: (position in ``idx``, shadow), grouped by piece
    in the order :func:`piece_shadows` lists them. Shadows of the edge from each end of the piece, then the wedges of
    rays from the piece through each end of the edge (only the valid ones of non-zero area), then, unless ``outer``,
    the grazing slivers. ``boxes`` (xmin, ymin, xmax, ymax per piece): shadows whose bounds miss the piece's box are
    left out before they are drawn (they cannot meet a region inside it)."""
    tree = None if blockers is None else blockers._seg_tree  # type: ignore[attr-defined]
    if tree is None or blockers is None or not len(idx):
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=object)
    a, b = np.asarray(targets.a[idx], float).reshape(-1, 2), np.asarray(targets.b[idx], float).reshape(-1, 2)
    lo, hi = np.minimum(a, b) - 1e-6, np.maximum(a, b) + 1e-6
    near = [tree.query(ks, predicate="intersects"), tree.query(shapely.box(*lo.T, *hi.T), predicate="intersects")]
    nb = len(blockers.a)
    code = np.unique(np.concatenate([p * nb + h for p, h in near]))  # by piece, then by blocker
    pos, hit = code // nb, code % nb
    keep = blockers.key[hit] != wall_key(np.asarray(targets.zone[idx])[pos], np.asarray(targets.wall[idx])[pos])
    pos, hit = pos[keep], hit[keep]
    pa, pb, q1, q2, f = a[pos], b[pos], blockers.a[hit], blockers.b[hit], 2.0 * far
    groups = [(c, pos, True) for c in _shadows(pa, pb, q1, q2, f)]
    if not outer:
        groups += [(c, at, False) for c, at in _grazing(pa, pb, q1, q2, pos, f)]
    polys, where = [], []
    for coords, at, check in groups:
        if boxes is not None:
            box = boxes[at]
            lo, hi = coords.min(axis=1), coords.max(axis=1)
            near_box = np.all((lo <= box[:, 2:]) & (hi >= box[:, :2]), axis=1)
            coords, at = coords[near_box], at[near_box]
        g = shapely.polygons(coords) if len(coords) else np.zeros(0, dtype=object)
        ok = shapely.is_valid(g) & (shapely.area(g) > 0) if check else np.ones(len(g), bool)
        polys.append(g[ok])
        where.append(at[ok])
    at = np.concatenate(where)
    order = np.argsort(at, kind="stable")
    return at[order], np.concatenate(polys)[order]


def piece_shadows(
    targets: Targets, t: int, k: shapely.Geometry, blockers: Blockers | None, far: float, outer: bool
) -> list[shapely.Geometry]:
    """The shadows (and, unless ``outer``, the grazing slivers) of the blockers near piece ``t`` that meet ``k``."""
    ks = np.empty(1, dtype=object)
    ks[0] = k
    return list(chunk_shadows(targets, np.array([t], dtype=np.int64), ks, blockers, far, outer)[1])


def sight_stage(
    targets: Targets,
    idx: NDArray[np.int64],
    ks: NDArray[np.object_],
    stands: NDArray[np.object_],
    blockers: Blockers | None,
    far: float,
    outer: bool,
) -> list[shapely.Geometry]:
    """R_t of the pieces ``idx``: each region ``stands`` (after the stand stage) minus the union of those shadows of
    :func:`chunk_shadows` (picked with the regions ``ks`` before the stand stage) that meet it."""
    out = list(stands)
    rows = np.flatnonzero(~shapely.is_empty(stands))
    regions = stands[rows]
    pos, polys = chunk_shadows(targets, idx[rows], ks[rows], blockers, far, outer, shapely.bounds(regions))
    if not len(polys):
        return out
    shapely.prepare(regions)
    meet = shapely.intersects(regions[pos], polys)
    pos, polys = pos[meet], polys[meet]
    cuts = np.flatnonzero(np.diff(pos)) + 1
    for p, group in zip(pos[np.r_[0, cuts]] if len(pos) else [], np.split(polys, cuts)):
        out[int(rows[p])] = _minus_union(regions[p], group)
    return out


def _shadows(a: NDArray, b: NDArray, q1: NDArray, q2: NDArray, far: float) -> list[NDArray[np.float64]]:
    """Positions p from which edge q1-q2 (row-wise) meets the triangle p-a-b: shadow from a, from b, and the wedges of
    rays from the piece through each end of the edge (the corners of each group's polygons, row-wise)."""
    out = []
    for x in (a, b):
        d1, d2 = _away(q1, x), _away(q2, x)
        out.append(np.stack([q1, q2, q2 + far * d2, q1 + far * d1], axis=1))
    for q in (q1, q2):
        da, db = _away(q, a), _away(q, b)
        out.append(np.stack([q, q + far * da, q + far * db], axis=1))
    return out


def _grazing(
    a: NDArray, b: NDArray, q1: NDArray, q2: NDArray, pos: NDArray[np.int64], far: float
) -> list[tuple[NDArray[np.float64], NDArray[np.int64]]]:
    """Slivers along the lines of the edges that end at a piece's end: the sight test blocks those views (a line through
    a corner within its tolerance), so R_t leaves them out too. Row-wise: the slivers' corners and their rows' ``pos``,
    from a, then from b; for each edge the rays at +-half about its direction, then about the reverse."""
    out = []
    half = math.radians(GRAZE_DEG)
    c, s = math.cos(half), math.sin(half)
    for x in (a, b):
        touch = (np.hypot(*(q1 - x).T) < 1e-6) | (np.hypot(*(q2 - x).T) < 1e-6)
        w = unit(q2[touch] - q1[touch])
        d = np.stack([w, -w], axis=1).reshape(-1, 2)  # each edge's two directions, in turn
        left = np.column_stack([d[:, 0] * c - d[:, 1] * s, d[:, 0] * s + d[:, 1] * c])
        right = np.column_stack([d[:, 0] * c + d[:, 1] * s, d[:, 1] * c - d[:, 0] * s])
        xx = np.repeat(x[touch], 2, axis=0)
        out.append((np.stack([xx, xx + far * left, xx + far * right], axis=1), np.repeat(pos[touch], 2)))
    return out


def unshadowed(region: shapely.Geometry, shadows: list[shapely.Geometry]) -> shapely.Geometry:
    """``region`` minus the union of ``shadows``: only the shadows that meet ``region`` are unioned (the same point
    set)."""
    if not shadows:
        return region
    polys = np.asarray(shadows, dtype=object)
    shapely.prepare(region)
    polys = polys[shapely.intersects(region, polys)]
    return _minus_union(region, polys) if polys.size else region


def _minus_union(region: shapely.Geometry, polys: NDArray[np.object_]) -> shapely.Geometry:
    """``region`` minus the union of ``polys``, snap-rounded where GEOS's floating overlay fails."""
    try:
        return region.difference(shapely.union_all(polys))
    except shapely.errors.GEOSException:  # near-coincident sliver edges (doors, junction cuts): snap-round
        return shapely.difference(region, shapely.union_all(polys, grid_size=SNAP_GRID_M), grid_size=SNAP_GRID_M)
