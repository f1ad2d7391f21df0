"""Coverage regions of floor and ceiling patches, and candidates from their arrangement.

A station sees a patch P (:mod:`planner.coverage.surface_sight`) when every point of P lies between the blind cone and
the incidence limit, within range, and in plan view. In the plane of the instrument that reads:

- every point of P within the reach ``r_out`` (range and incidence) of the station: the farthest point of a polygon
  from any position is a vertex, so this holds exactly in the intersection of the discs of radius ``r_out`` about P's
  vertices;
- no point of P within the blind radius ``r_in``: the station outside P grown by ``r_in`` (the Minkowski sum with the
  disc), as the sight test measures the distance to P itself;
- the station on the floor of P's zone, where a station may stand (the walls' stand area: stand-off, obstacles,
  no-go areas);
- no blocker (:func:`planner.coverage.plan_sight.plan_blockers`) on a segment from the station to a point of P. A
  segment [q, p] from q in P that meets a blocker edge e = c-d first meets it after its last point of P's boundary, so
  the positions that lose P behind e are those that lose an edge f = a-b of P: the shadow of e from a, from b, and
  the wedges at c and d of the rays from f through them (as for wall pieces in :mod:`planner.coverage.regions`).
  Only blockers within ``r_out`` of P matter: every segment from a position within ``r_out`` of P's vertices stays
  within ``r_out`` of P.

``patch_regions`` draws that set, ``inner`` (discs inscribed, the blind disc circumscribed: a point in it passes the
test up to the sight test's own tolerances) for candidates, or ``outer`` (discs circumscribed, the blind disc inscribed,
the stand area's outer approximation) for a bound. :func:`arrangement_candidates` puts a candidate in every face of the
arrangement of a zone's patch and wall regions whose set of regions no other face's holds, so that for every position
of the plane the pool has one that sees at least what it sees, up to the approximations.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry.polygon import orient
from shapely.ops import polylabel

from planner.coverage.plan_sight import EPS_PLAN_M
from planner.coverage.regions import FrameSpace, coverage_regions, frame_space
from planner.coverage.surface_sight import SurfaceLayer, SurfaceLimits, surface_layer
from planner.coverage.surfaces import CEILING, FLOOR, SurfaceTargets, open_area
from planner.coverage.targets import SIDE_CODE, Targets
from planner.coverage.visibility import SightLimits
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Site

#: segments per quarter circle of the range discs and the blind disc (a 64-gon: 4.5 mm of sagitta at 3.7 m)
QUAD_SEGS = 16
#: a zone whose patch and wall regions number more than this gets no arrangement candidates (the floor grid stays)
MAX_REGIONS = 90
#: and one whose arrangement has more faces than this
MAX_FACES = 60_000
#: the regions of all zones together: zones past it (in site order) keep the floor grid alone
MAX_SITE_REGIONS = 400
#: the longest arc step of the shadow cones' far ends (rad)
ARC_STEP = math.pi / 12
#: a cone whose apex angle has a sine below this is a ray: no area
EPS_CONE = 1e-12


def _disc(x: float, y: float, r: float, outer: bool) -> shapely.Geometry:
    """The disc of radius ``r``: inscribed (its vertices on the circle), or circumscribed with ``outer``."""
    grow = 1.0 / math.cos(math.pi / (4 * QUAD_SEGS)) if outer else 1.0
    return shapely.Point(x, y).buffer(r * grow, quad_segs=QUAD_SEGS)


def _cone(apex: NDArray, a0: float, a1: float, radius: float) -> shapely.Geometry | None:
    """The cone from ``apex`` between the directions ``a0`` and ``a1`` (counter-clockwise, less than pi apart) cut at
    ``radius``, as a polygon inside the cone that holds all of it within ``radius * cos(ARC_STEP / 2)``."""
    span = (a1 - a0) % (2 * math.pi)
    if span <= EPS_CONE or span >= math.pi:
        return None
    n = max(1, math.ceil(span / ARC_STEP))
    ang = a0 + span * np.arange(n + 1) / n
    ring = np.vstack([apex, apex + radius * np.column_stack([np.cos(ang), np.sin(ang)])])
    return shapely.Polygon(ring)


def _ccw(apex: NDArray, p: NDArray, q: NDArray) -> tuple[float, float]:
    """The directions from ``apex`` to ``p`` and ``q`` ordered counter-clockwise (the short way round)."""
    u, v = p - apex, q - apex
    a, b = math.atan2(u[1], u[0]), math.atan2(v[1], v[0])
    return (a, b) if u[0] * v[1] - u[1] * v[0] >= 0 else (b, a)


def _span(apex: NDArray, points: NDArray) -> tuple[float, float] | None:
    """The smallest counter-clockwise range of directions from ``apex`` that holds every direction to ``points`` (None
    when it is half a turn or more: the apex lies within their hull)."""
    rel = points - apex
    ang = np.sort(np.arctan2(rel[:, 1], rel[:, 0]))
    gaps = np.diff(np.concatenate([ang, ang[:1] + 2 * math.pi]))
    k = int(np.argmax(gaps))  # the range starts after the largest gap
    if gaps[k] <= math.pi:
        return None
    return float(ang[(k + 1) % len(ang)]), float(ang[k])


def _shadow(corners: NDArray, e: tuple[NDArray, NDArray], radius: float) -> list[shapely.Geometry]:
    """The positions from which a segment to a point of the convex patch with ``corners`` meets edge ``e`` (within
    ``radius`` of the apexes): the shadows of ``e`` from the corners, and the wedges at e's ends of the rays from the
    patch through them."""
    out: list[shapely.Geometry | None] = []
    c, d = e
    for apex in corners:  # beyond e as seen from the apex: the cone over e less the triangle apex-c-d
        a0, a1 = _ccw(apex, c, d)
        cone = _cone(apex, a0, a1, radius)
        if cone is not None:
            out.append(cone.difference(shapely.Polygon([apex, c, d])))
    for end in e:  # rays from the patch through e's end: the cone at the end spanned by end - corner
        span = _span(end, 2 * end - corners)
        if span is not None:
            out.append(_cone(end, span[0], span[1], radius))
    return [g for g in out if g is not None and not g.is_empty]


def _front(ring: NDArray, corners: NDArray) -> list[tuple[NDArray, NDArray]]:
    """The edges of a counter-clockwise blocker ring that face some corner of the patch (a segment from outside the
    blocker enters it through such an edge first)."""
    out = []
    for c, d in zip(ring[:-1], ring[1:]):
        normal = np.array([d[1] - c[1], c[0] - d[0]])  # outward for a counter-clockwise ring
        if np.any((corners - c) @ normal > 0):
            out.append((c, d))
    return out


def _hidden(
    corners: NDArray, convex_patch: bool, blockers: Sequence[shapely.Geometry], reach: float
) -> shapely.Geometry:
    """Where some blocker hides part of the patch with ``corners`` (within ``reach`` of it). A patch that is not
    convex is taken edge by edge (each edge is convex; a segment from the patch meets a blocker first after its last
    point of the patch's boundary)."""
    if not blockers:
        return shapely.Polygon()
    size = float(np.ptp(corners, axis=0).max())
    lights = [corners] if convex_patch else [np.array(f) for f in zip(corners, np.roll(corners, -1, axis=0))]
    parts: list[shapely.Geometry] = []
    for b in blockers:
        b = orient(b, 1.0)
        radius = 2.0 * (reach + size + float(shapely.distance(b, shapely.Polygon(corners)))) + 1.0
        rings = [np.asarray(shapely.get_coordinates(r)) for r in [b.exterior, *b.interiors]]
        edges = _front(rings[0], corners) + [e for r in rings[1:] for e in zip(r[:-1], r[1:])]
        for e in edges:
            for light in lights:
                parts += _shadow(light, e, radius)
    return shapely.union_all(parts) if parts else shapely.Polygon()


def patch_region(
    layer: SurfaceLayer, t: int, stand: shapely.Geometry, outer: bool, blockers: Sequence[shapely.Geometry]
) -> shapely.Geometry:
    """The positions of the plane from which a station sees patch ``t`` of ``layer`` (module docstring): inner for
    candidates, ``outer`` for bounds. ``stand``: where a station of the patch's zone may stand; ``blockers``: those
    near the patch."""
    p = layer.patches
    corners = p.corners[t, : int(p.n_corners[t])]
    region = stand
    for x, y in corners:
        region = region.intersection(_disc(float(x), float(y), layer.reach_m, outer))
        if region.is_empty:
            return region
    if layer.blind_m > 0:  # the blind disc: circumscribed for candidates, inscribed for a bound
        grow = 1.0 if outer else 1.0 / math.cos(math.pi / (4 * QUAD_SEGS))
        region = region.difference(p.polygon[t].buffer(layer.blind_m * grow, quad_segs=QUAD_SEGS))
    if region.is_empty or not blockers:
        return region
    return region.difference(_hidden(corners, bool(layer.is_convex[t]), blockers, layer.reach_m))


def _stand_area(site: Site, zi: int, space: FrameSpace | None) -> shapely.Geometry:
    """Zone ``zi``'s floor (grown by the sight test's tolerance) where a station of the zone may stand."""
    floor = open_area(site, zi).buffer(EPS_PLAN_M, join_style="mitre")
    if space is None or zi not in space.inside:
        return floor
    return floor.intersection(space.inside[zi])


def patch_regions(
    site: Site,
    patches: SurfaceTargets,
    limits: SurfaceLimits,
    sight: SightLimits,
    which: Sequence[int] | NDArray[np.integer],
    spaces: dict[str, FrameSpace],
    outer: bool = False,
) -> dict[int, shapely.Geometry]:
    """The coverage region of each patch ``which`` (:func:`patch_region`; empty for a patch no station can see).
    ``spaces``: the walls' frame spaces (inner, or outer with ``outer``), made here where missing."""
    which = np.asarray(which, dtype=np.int64).reshape(-1)
    out: dict[int, shapely.Geometry] = {int(t): shapely.Polygon() for t in which}
    is_convex = patches.is_convex
    for zi in np.unique(patches.zone[which]) if which.size else []:
        frame = site.zones[int(zi)].frame
        if frame not in spaces:
            spaces[frame] = frame_space(site, frame, sight, outer)
        stand = _stand_area(site, int(zi), spaces[frame])
        for kind in (FLOOR, CEILING):
            mine = which[(patches.zone[which] == zi) & (patches.kind[which] == kind)]
            layer = surface_layer(site, int(zi), kind, patches, limits, is_convex) if mine.size else None
            if layer is None:
                continue
            tree = layer.blockers.tree
            for t in np.intersect1d(mine, layer.ts):
                near: list[shapely.Geometry] = []
                if tree is not None:
                    near = list(tree.geometries[tree.query(patches.polygon[t], "dwithin", layer.reach_m)])
                out[int(t)] = patch_region(layer, int(t), stand, outer, near)
    return out


def _faces(regions: list[shapely.Geometry]) -> tuple[NDArray[np.object_], NDArray[np.bool_]] | None:
    """The faces of the arrangement of ``regions`` and, per face and region, whether the face lies in it (None: more
    than :data:`MAX_FACES` faces)."""
    # on a 1-nm grid: the round ends of many discs about shared corners otherwise lose faces to the polygoniser
    snapped = shapely.set_precision(np.asarray(regions, dtype=object), 1e-9)
    lines = shapely.union_all(shapely.boundary(snapped))
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(lines)))
    if len(faces) > MAX_FACES:
        return None
    reps = shapely.point_on_surface(faces)
    tree = shapely.STRtree(snapped)
    fi, ri = tree.query(reps, predicate="within")
    member = np.zeros((len(faces), len(regions)), dtype=bool)
    member[fi, ri] = True
    return faces, member


def undominated(member: NDArray[np.bool_], block: int = 512) -> NDArray[np.int64]:
    """The rows of ``member`` (faces x regions) whose set of regions is not empty and no other row's set holds
    strictly, one row per distinct set (the first)."""
    sets, first = np.unique(member, axis=0, return_index=True)
    size = sets.sum(axis=1)
    dense = sets.astype(np.float32)
    keep = size > 0
    for i0 in range(0, len(sets), block):
        shared = dense[i0 : i0 + block] @ dense.T  # |S_i & S_j|, exact in float32 below 2^24 regions
        holds = (shared >= size[i0 : i0 + block, None] - 0.5) & (size[None, :] > size[i0 : i0 + block, None])
        keep[i0 : i0 + block] &= ~holds.any(axis=1)
    return np.sort(first[keep]).astype(np.int64)


def arrangement_candidates(
    site: Site,
    patches: SurfaceTargets,
    limits: SurfaceLimits,
    targets: Targets,
    sight: SightLimits,
    spaces: dict[str, FrameSpace],
    region_cache: dict[int, Any],
) -> tuple[list[Candidate], list[str]]:
    """A candidate at the pole of every undominated face (:func:`undominated`) of the arrangement of each inside
    zone's patch regions and its inside wall pieces' regions (``region_cache``/``spaces``: the walls' regions drawn
    in this run, filled in here); and a note per zone left to the floor grid (more than :data:`MAX_REGIONS` regions
    or :data:`MAX_FACES` faces, or past :data:`MAX_SITE_REGIONS` in all)."""
    out: list[Candidate] = []
    notes: list[str] = []
    budget = MAX_SITE_REGIONS
    for zi, zone in enumerate(site.zones):
        mine = np.flatnonzero(patches.zone == zi)
        if mine.size == 0:
            continue
        walls = np.flatnonzero((targets.zone == zi) & (targets.side == SIDE_CODE[ScanSide.INSIDE]))
        n = mine.size + walls.size
        if n > min(MAX_REGIONS, budget):
            notes.append(f"{zone.id}: {n} regions (more than {min(MAX_REGIONS, budget)} left): floor grid only")
            continue
        budget -= n
        missing = [int(w) for w in walls if int(w) not in region_cache]
        region_cache.update(coverage_regions(site, targets, sight, missing, spaces))
        drawn = patch_regions(site, patches, limits, sight, mine, spaces)
        regions = [g for g in [*drawn.values(), *(region_cache[int(w)] for w in walls)] if g.area > 0]
        if not regions:
            continue
        found = _faces(regions)
        if found is None:
            notes.append(f"{zone.id}: more than {MAX_FACES:,} faces: floor grid only")
            continue
        faces, member = found
        for k, f in enumerate(undominated(member), 1):
            face = faces[f]
            pole = polylabel(face, tolerance=max(1e-3 * math.sqrt(face.area), 1e-6))
            name = f"{zone.id}-in-S{k}"
            out.append(Candidate(name, zone.id, ScanSide.INSIDE, zone.frame, pole.x, pole.y, CandidateKind.REGION))
    return out, notes
