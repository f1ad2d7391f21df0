"""The arrangement of weighted coverage regions: where their weight is heaviest.

Geometric pricing asks two questions of the regions R_t (each with a dual weight y_t >= 0):

1. **Where to put a new candidate** (:func:`heaviest_points`): points of the *closed* arrangement of the regions as
   drawn (inner approximations), heaviest first. Where two regions only touch (along an edge or at a point) the weight
   is larger than on any open face beside it, so the samples are a point inside every face, the midpoint of every edge
   and every node, each weighed by the closed regions within ``TOUCH_M``.

2. **The heaviest weight anywhere in the plane** (:func:`outer_max_weight`), for a bound. The true coverage set C_t lies
   within ``grow_m`` of R_t, so each region is grown by ``grow_m`` plus a margin (circumscribed). Then the open disc of
   radius ``margin`` about any position p lies in every grown region of the t with p in C_t, and meets an open face
   inside all of them: the heaviest face weighs at least p's weight. Faces are weighed with closed containment, which
   can only add weight. If the faces found do not fill the union of the grown regions (a face lost by the polygoniser),
   the answer is the sum of all weights, always a bound.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray

#: a sample point weighs the closed regions within this distance of it (noding rounds node coordinates)
TOUCH_M = 1e-9
#: the grown regions reach this much beyond the tolerance: the radius of the disc in the proof above
MARGIN_M = 1e-6
#: segments per quarter circle of the grown regions (circumscribed: radius / cos(pi / (4 * QUAD_SEGS)))
QUAD_SEGS = 4
#: the faces must fill the union of the grown regions to this relative area
AREA_CHECK = 1e-6
#: a face is weighed at a point this far inside it (far above rounding, far below ``MARGIN_M``)
INSET_M = 1e-8


@dataclass(frozen=True)
class Sample:
    """A point of the arrangement and the weight of the closed regions holding it; ``kind`` says where it lies: ``face``
    (inside a face), ``edge`` (on an edge between faces) or ``vertex``."""

    x: float
    y: float
    weight: float
    kind: str


def _noded(polys: Sequence[shapely.Geometry]) -> shapely.Geometry:
    """The boundaries of ``polys`` noded against each other (one union)."""
    return shapely.union_all(shapely.boundary(np.asarray(polys, dtype=object)))


def _weigh(
    points: NDArray, tree: shapely.STRtree, w: NDArray[np.float64], predicate: str, work: list[int] | None = None
) -> NDArray[np.float64]:
    """Sum of the weights of the regions (the tree's) holding each point, closed containment; ``work``, where given,
    gets the number of (point, region) pairs found appended."""
    if len(points) == 0:
        return np.zeros(0)
    pi, ri = tree.query(points, predicate=predicate, distance=TOUCH_M if predicate == "dwithin" else None)
    if work is not None:
        work.append(len(pi))
    return np.asarray(np.bincount(pi, weights=w[ri], minlength=len(points)), dtype=np.float64)


def _edge_points(lines: shapely.Geometry) -> tuple[NDArray, NDArray]:
    """Midpoints of the noded edges and their end nodes (unique)."""
    parts = shapely.get_parts(lines)
    parts = parts[shapely.get_type_id(parts) == 1]  # linestrings
    if len(parts) == 0:
        return np.zeros(0, dtype=object), np.zeros(0, dtype=object)
    mids = shapely.line_interpolate_point(parts, 0.5, normalized=True)
    ends = np.vstack(
        [shapely.get_coordinates(shapely.get_point(parts, 0)), shapely.get_coordinates(shapely.get_point(parts, -1))]
    )
    ends = np.unique(np.round(ends, 12), axis=0)
    return mids, shapely.points(ends)


def heaviest_points(
    regions: Sequence[shapely.Geometry],
    weights: NDArray[np.float64],
    threshold: float,
    limit: int,
    work: list[int] | None = None,
) -> list[Sample]:
    """Points of the closed arrangement of ``regions`` weighing more than ``threshold`` (heaviest first, at most
    ``limit``; faces before edges before vertices at equal weight). ``work``, where given, gets the (point, region)
    pairs found in weighing them appended: a count that follows the cost of the call (weighing is its bulk)."""
    keep = [k for k, g in enumerate(regions) if not g.is_empty and g.area > 0]
    if not keep:
        return []
    polys = [regions[k] for k in keep]
    w = np.asarray(weights, float)[keep]
    lines = _noded(polys)
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(lines)))
    tree = shapely.STRtree(polys)
    reps = shapely.point_on_surface(faces) if len(faces) else np.zeros(0, dtype=object)
    mids, nodes = _edge_points(lines)
    groups = (
        ("face", reps, _weigh(reps, tree, w, "within", work)),
        ("edge", mids, _weigh(mids, tree, w, "dwithin", work)),
        ("vertex", nodes, _weigh(nodes, tree, w, "dwithin", work)),
    )
    pts = np.concatenate([g[1] for g in groups])
    wts = np.concatenate([g[2] for g in groups])
    kinds = np.concatenate([np.full(len(g[1]), k, dtype=object) for k, g in enumerate(groups)])
    if len(pts) == 0:
        return []
    order = np.lexsort((kinds, -wts))
    order = order[wts[order] > threshold][:limit]
    xy = shapely.get_coordinates(pts[order]) if order.size else np.zeros((0, 2))
    return [Sample(float(px), float(py), float(wts[k]), groups[int(kinds[k])][0]) for (px, py), k in zip(xy, order)]


def grown_reach(grow_m: float) -> float:
    """How far :func:`grown` moves a region's boundary at most: its buffer distance (the circumscribing polygon's
    vertices lie on that circle, its edges inside it)."""
    return (grow_m + MARGIN_M) / math.cos(math.pi / (4 * QUAD_SEGS))


def grown(regions: Sequence[shapely.Geometry], grow_m: float) -> list[shapely.Geometry]:
    """Each region grown by ``grow_m + MARGIN_M`` as a polygon circumscribing the round buffer."""
    return list(shapely.buffer(np.asarray(list(regions), dtype=object), grown_reach(grow_m), quad_segs=QUAD_SEGS))


def outer_max_weight(
    regions: Sequence[shapely.Geometry],
    weights: NDArray[np.float64],
    grow_m: float,
    grown_regions: Sequence[shapely.Geometry] | None = None,
) -> float:
    """An upper bound on the weight sum_{t: p in C_t} y_t at any position p, where every true coverage set C_t lies
    within ``grow_m`` of ``regions[t]`` (see the module docstring for the proof). ``grown_regions``: the regions
    already grown by :func:`grown` with ``grow_m`` (one per region), where the caller has them."""
    w_all = np.asarray(weights, float)
    keep = [k for k, g in enumerate(regions) if not g.is_empty and w_all[k] > 0]
    if not keep:
        return 0.0
    if grown_regions is None:
        polys = grown([regions[k] for k in keep], grow_m)
    else:
        polys = [grown_regions[k] for k in keep]
    w = w_all[keep]
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(_noded(polys))))
    if len(faces) == 0:
        return float(w.sum())
    tree = shapely.STRtree(polys)
    reps, inside = interior_points(faces)
    ones = np.ones(len(polys))
    held = _weigh(reps, tree, ones, "intersects") > 0  # faces inside some region (not holes)
    held[~inside] = _weigh(reps[~inside], tree, ones, "dwithin") > 0
    union = shapely.union_all(np.asarray(polys, dtype=object))
    if abs(float(shapely.area(faces[held]).sum()) - union.area) > AREA_CHECK * max(union.area, 1.0):
        return float(w.sum())  # a face lost by the polygoniser: the trivial bound
    weight = _weigh(reps, tree, w, "intersects")
    weight[~inside] = _weigh(reps[~inside], tree, w, "dwithin")  # on a sliver's edge: the regions near it, closed
    return float(weight.max())


def interior_points(faces: NDArray) -> tuple[NDArray, NDArray[np.bool_]]:
    """A point of each face at least ``INSET_M`` inside it, and where that was found. ``point_on_surface`` may return a
    point on the face's edge, which rounding then puts outside a region that holds the whole face (seen 1e-14 m off at
    coordinates near 1,000 m): such a face would weigh too little, or count as a hole. Inset first; a face too thin to
    inset keeps ``point_on_surface`` (the caller weighs those within ``TOUCH_M``, closed: never too little)."""
    reps = shapely.point_on_surface(faces)
    inner = shapely.buffer(faces, -INSET_M, quad_segs=1, join_style="mitre")
    inside = ~shapely.is_empty(inner)
    if inside.any():
        reps[inside] = shapely.point_on_surface(inner[inside])
    return reps, inside
