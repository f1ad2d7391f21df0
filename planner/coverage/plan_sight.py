"""The plan-view part of the floor and ceiling sight test: do the segments from a station to every point of a patch keep
clear of what can hide it?

A patch of zone z is hidden by its *blockers*: the footprints of z's blocks (holes, obstacles) of at least a given
height and the pockets between z's outline and its convex hull, each shrunk by ``EPS_PLAN_M`` so that only touching one
stays clear. The segments from station s to a patch P sweep P's *fan*: for P convex and s outside its bounding box, P
with the triangle (s, c-, c+) over the corners that bound P's angular extent; otherwise the union of the triangles (s,
a, b) over P's edges. A pair is clear when no blocker meets the triangles; P itself is tested once
(:func:`PlanBlockers.hits`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.coverage.surfaces import zone_blocks
from planner.site.model import Site

#: blockers are shrunk by this, so that touching one is clear
EPS_PLAN_M = 1e-6
#: a triangle station-edge thinner than this sine of its apex angle is a segment, covered by its neighbours
EPS_DEGENERATE = 1e-12


@dataclass(frozen=True, eq=False)
class PlanBlockers:
    """The shrunk footprints that can hide a patch in plan, in an STRtree (None: nothing can)."""

    tree: shapely.STRtree | None

    def hits(self, geoms: NDArray[np.object_]) -> NDArray[np.bool_]:
        """For each geometry, True when it meets a blocker."""
        out = np.zeros(len(geoms), dtype=bool)
        if self.tree is not None and len(geoms):
            gi, _ = self.tree.query(geoms, predicate="intersects")
            out[gi] = True
        return out


def plan_blockers(site: Site, zi: int, reaching_m: float) -> PlanBlockers:
    """The blockers of zone ``zi``: its blocks at least ``reaching_m`` high and the pockets of its outline."""
    outline = shapely.Polygon(site.zones[zi].xy)
    parts = [poly for poly, h in zone_blocks(site, zi) if h >= reaching_m]
    parts += list(shapely.get_parts(outline.convex_hull.difference(outline)))
    if not parts:
        return PlanBlockers(None)
    shrunk = shapely.buffer(np.asarray(parts, dtype=object), -EPS_PLAN_M, join_style="mitre")
    shrunk = shrunk[~shapely.is_empty(shrunk)]
    return PlanBlockers(shapely.STRtree(shrunk) if len(shrunk) else None)


def _edge_triangles(s: NDArray, corners: NDArray, n: NDArray) -> tuple[NDArray[np.int64], NDArray[np.object_]]:
    """The triangles station-edge over every edge of each patch (degenerate ones left out), with their rows."""
    m = np.arange(corners.shape[1])
    nxt = np.where(m[None, :] + 1 < n[:, None], m[None, :] + 1, 0)
    a, b = corners, np.take_along_axis(corners, nxt[..., None], axis=1)
    sa, sb = a - s[:, None, :], b - s[:, None, :]
    cross = sa[..., 0] * sb[..., 1] - sa[..., 1] * sb[..., 0]
    real = np.abs(cross) > EPS_DEGENERATE * np.hypot(sa[..., 0], sa[..., 1]) * np.hypot(sb[..., 0], sb[..., 1])
    row, col = np.nonzero(real)
    return row, shapely.polygons(np.stack([s[row], a[row, col], b[row, col]], axis=1))


def _tangent_triangles(s: NDArray, corners: NDArray) -> NDArray[np.object_]:
    """For stations outside their patch's bounding box: the triangle over the corners at the two ends of the patch's
    angular extent (measured from the direction to the box's centre, so no angle wraps)."""
    ref = (corners.min(axis=1) + corners.max(axis=1)) / 2.0 - s
    rel = corners - s[:, None, :]
    ang = np.arctan2(ref[:, None, 0] * rel[..., 1] - ref[:, None, 1] * rel[..., 0], np.einsum("pj,pkj->pk", ref, rel))
    rows = np.arange(len(s))
    lo, hi = corners[rows, ang.argmin(axis=1)], corners[rows, ang.argmax(axis=1)]
    return shapely.polygons(np.stack([s, lo, hi], axis=1))


def fans_clear(
    blockers: PlanBlockers, s: NDArray[np.float64], corners: NDArray[np.float64], n: NDArray, is_convex: NDArray
) -> NDArray[np.bool_]:
    """For each pair (row: station ``s``, patch ``corners`` with ``n`` own corners, ``is_convex``), True when its fan
    meets no blocker (the patch itself is not tested here)."""
    clear = np.ones(len(s), dtype=bool)
    if blockers.tree is None or len(s) == 0:
        return clear
    over = np.all((s >= corners.min(axis=1) - EPS_PLAN_M) & (s <= corners.max(axis=1) + EPS_PLAN_M), axis=1)
    single = np.flatnonzero(is_convex & ~over)
    clear[single[blockers.hits(_tangent_triangles(s[single], corners[single]))]] = False
    rest = np.flatnonzero(~(is_convex & ~over))
    if rest.size:
        row, tris = _edge_triangles(s[rest], corners[rest], n[rest])
        clear[rest[row[blockers.hits(tris)]]] = False
    return clear
