"""Coverage regions: for a wall piece t, the set R_t of positions from which a station covers it.

R_t applies the rules of :mod:`planner.coverage.visibility` to a position instead of a candidate:

- the scan side and where a station may stand at all (:func:`frame_space`);
- the incidence limit at both ends: a wedge of half-angle theta_max about the face normal, or with 3-D incidence the
  convex region d >= cot(theta_max) sqrt(u^2 + dz^2), bounded by chords;
- the slant range to top and foot at both ends: inscribed discs of radius sqrt(S^2 - dz^2);
- sight: minus the shadow of every wall and obstacle edge near the piece (positions p for which the edge meets the
  triangle p-a-b);
- the stand-off: minus a circumscribed buffer around every wall and obstacle edge;
- the view error (single precision with an incidence model, horizontal incidence only, see :func:`regions_apply`): the
  region of :mod:`planner.coverage.region_precision` at each end.

Every approximation is from the inside, so a point in R_t passes the coverage test (up to its own sight tolerance); a
position that passes it but lies outside R_t is within :func:`region_tolerance_m` of R_t.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.coverage.matrix import ON_WALL_M, blockers_for, convex_alone
from planner.coverage.region_precision import PRECISION_CHORD_M, precision_region
from planner.coverage.targets import Targets
from planner.coverage.visibility import (
    EPS_FRONT_M,
    EPS_SHORTEN_M,
    EPS_SIGHT_M,
    Blockers,
    SightLimits,
    wall_key,
)
from planner.site.model import SITE_FRAME, Site

#: vertices of the polygon inscribed in each range disc
DISC_SEGMENTS = 512
#: largest distance of a 3-D incidence boundary from its chords (m)
HYPERBOLA_SAGITTA_M = 1e-3
#: the sight test blocks a line whose end, moved EPS_SHORTEN_M toward the station, lies within EPS_SIGHT_M of a wall
#: line through the piece's end: a sliver of this half-angle
GRAZE_DEG = math.degrees(math.asin(EPS_SIGHT_M / EPS_SHORTEN_M))
#: grid of the snap-rounded overlay used when GEOS's floating overlay of the shadows fails (1 um)
SNAP_GRID_M = 1e-6
#: segments per quarter circle of the stand-off buffers
STANDOFF_QUAD_SEGS = 16


def regions_apply(limits: SightLimits) -> bool:
    """Whether R_t models the coverage test for ``limits``: not for the incidence-dependent view error with 3-D
    incidence (along a ray from a piece's end the 3-D incidence falls while the range grows, so that region is not
    drawn)."""
    return not (limits.incidence_3d and limits.per_pair_precision)


def _standoff_buffer_m(standoff_m: float) -> float:
    """Buffer distance whose polygon (``STANDOFF_QUAD_SEGS``) circumscribes the stand-off circle."""
    return standoff_m / math.cos(math.pi / (4 * STANDOFF_QUAD_SEGS))


def region_tolerance_m(limits: SightLimits, standoff_m: float = 0.0) -> float:
    """How far outside R_t a covering position can lie: the sagitta of the largest inscribed disc (r (1 - cos(pi / n))),
    plus the sight test's tolerances, plus (with ``standoff_m``) the excess of the circumscribed stand-off buffers and
    (with a per-view precision test) twice the precision boundary's chord error."""
    r = limits.effective_range_m
    sag = r * (1.0 - math.cos(math.pi / DISC_SEGMENTS)) if math.isfinite(r) else 0.0
    extra = _standoff_buffer_m(standoff_m) - standoff_m if standoff_m > 0 else 0.0
    extra += 2.0 * PRECISION_CHORD_M if limits.per_pair_precision else 0.0
    return sag + (HYPERBOLA_SAGITTA_M if limits.incidence_3d else 0.0) + 1e-5 + extra


@dataclass(frozen=True, eq=False)
class FrameSpace:
    """Where stations may stand in one frame, per zone and side, and the frame's blockers."""

    frame: str
    inside: dict[int, shapely.Geometry]  # zone index -> stand area inside the zone
    outside: dict[int, shapely.Geometry]  # zone index -> stand area outside the zone (within ``box``)
    box: shapely.Geometry
    blockers: Blockers | None  # None: a lone convex zone, where nothing blocks a front-facing piece
    far_m: float


def _frame_bounds(site: Site, frame: str) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Lower-left and upper-right corners of a frame's zones (and, in the site frame, obstacles)."""
    geoms = [z.polygon for z in site.zones if z.frame == frame]
    if frame == SITE_FRAME:
        geoms += [shapely.Polygon(ob.vertices) for ob in site.obstacles]
    box = shapely.total_bounds(geoms)
    return box[:2], box[2:]


def frame_space(site: Site, frame: str, limits: SightLimits, outer: bool = False) -> FrameSpace:
    """The accessible area of each zone-side of ``frame``: inside (the zone) or outside (a box around the frame's zones
    grown by the horizontal reach), minus obstacles, no-go areas, what lies outside the site boundary (site frame) and a
    hair's breadth around every wall. ``outer``: the stand-off buffers inscribed in the true ones (they take away less:
    an outer approximation of the area)."""
    lo, hi = _frame_bounds(site, frame)
    diag = float(np.hypot(*(hi - lo)))
    reach = limits.effective_range_m if math.isfinite(limits.effective_range_m) else 2.0 * diag
    reach = min(reach, 4.0 * diag + 100.0)  # a station farther off than this sees nothing better
    box = shapely.box(lo[0] - reach, lo[1] - reach, hi[0] + reach, hi[1] + reach)
    forbidden = []
    if frame == SITE_FRAME:
        forbidden += [shapely.Polygon(ob.vertices) for ob in site.obstacles]
        forbidden += [shapely.Polygon(ng.vertices) for ng in site.no_go_areas]
        if site.boundary is not None:
            forbidden.append(box.difference(shapely.Polygon(site.boundary)))
    walls = [z.polygon.boundary for z in site.zones if z.frame == frame]
    standoff = site.parameters.min_standoff_m
    if standoff > 0:  # as station_places: no station closer than the stand-off to a wall or obstacle edge
        edges = walls + (
            [shapely.Polygon(ob.vertices).boundary for ob in site.obstacles] if frame == SITE_FRAME else []
        )
        grow = standoff if outer else _standoff_buffer_m(standoff)
        forbidden.append(shapely.union_all(edges).buffer(grow, quad_segs=STANDOFF_QUAD_SEGS))
    if not outer:
        forbidden.append(shapely.union_all(walls).buffer(ON_WALL_M, quad_segs=1))
    bad = shapely.union_all(forbidden)
    inside, outside = {}, {}
    for zi, zone in enumerate(site.zones):
        if zone.frame != frame:
            continue
        inside[zi] = zone.polygon.difference(bad)
        outside[zi] = box.difference(zone.polygon).difference(bad)
    blockers = None if convex_alone(site, frame) else blockers_for(site, frame)  # as the coverage build does
    return FrameSpace(
        frame, inside, outside, box, blockers, float(np.hypot(*(np.asarray(box.bounds[2:]) - box.bounds[:2])))
    )


def _unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    n = np.hypot(v[..., 0], v[..., 1])
    return v / np.where(n > 0, n, 1.0)[..., None]


def _incidence_region(
    end: NDArray, tangent: NDArray, normal: NDArray, theta_deg: float, dz: float, incidence_3d: bool, far: float
) -> shapely.Geometry:
    """Where the incidence at ``end`` is <= theta: a wedge (horizontal) or the region above a hyperbola (3-D), reaching
    ``far`` (the range disc's radius when the range is limited)."""
    cot = 1.0 / math.tan(math.radians(theta_deg))
    if not incidence_3d or dz <= 0:
        tan = math.tan(math.radians(theta_deg))  # the wedge, cut off by a line ``far`` in front of its apex
        return shapely.Polygon([end, end + far * (normal + tan * tangent), end + far * (normal - tan * tangent)])
    # u = dz sinh(s): a chord of parameter length h lies within about u h^2 / (8 sin theta) of the curve
    h = math.sqrt(8.0 * HYPERBOLA_SAGITTA_M * math.sin(math.radians(theta_deg)) / far)
    chords = min(4000, math.ceil(2.0 * math.asinh(far / dz) / h))
    u = np.sinh(np.linspace(-np.arcsinh(far / dz), np.arcsinh(far / dz), chords + 1)) * dz
    d = cot * np.sqrt(u**2 + dz**2)
    pts = end + np.outer(u, tangent) + np.outer(d, normal)
    top = max(2.0 * far, cot * (far + dz) + far)
    cap = end + np.outer([far, -far], tangent) + np.outer([top, top], normal)
    return shapely.Polygon(np.vstack([pts, cap]))


def _away(q: NDArray, x: NDArray) -> NDArray[np.float64]:
    """Unit directions from x to q, zero where q is x up to rounding (an edge ending at a piece's end, whose coordinates
    may differ in the last bit: the direction of a 1e-16 m vector is noise; _grazing covers it)."""
    v = q - x
    return np.where((np.hypot(v[..., 0], v[..., 1]) < 1e-6)[..., None], 0.0, _unit(v))


def _shadows(a: NDArray, b: NDArray, q1: NDArray, q2: NDArray, far: float) -> list[shapely.Geometry]:
    """Positions p from which edge q1-q2 (row-wise) meets the triangle p-a-b: shadow from a, from b, and the wedges of
    rays from the piece through each end of the edge."""
    out = []
    for x in (a, b):
        d1, d2 = _away(q1, x), _away(q2, x)
        out.append(shapely.polygons(np.stack([q1, q2, q2 + far * d2, q1 + far * d1], axis=1)))
    for q in (q1, q2):
        da, db = _away(q, a), _away(q, b)
        out.append(shapely.polygons(np.stack([q, q + far * da, q + far * db], axis=1)))
    polys = np.concatenate(out)
    return list(polys[shapely.is_valid(polys) & (shapely.area(polys) > 0)])


def _grazing(a: NDArray, b: NDArray, q1: NDArray, q2: NDArray, far: float) -> list[shapely.Geometry]:
    """Slivers along the lines of the edges that end at a piece's end: the sight test blocks those views (a line through
    a corner within its tolerance), so R_t leaves them out too."""
    out = []
    half = math.radians(GRAZE_DEG)
    c, s = math.cos(half), math.sin(half)
    for x in (a, b):
        touch = (np.hypot(*(q1 - x).T) < 1e-6) | (np.hypot(*(q2 - x).T) < 1e-6)
        for w in _unit(q2[touch] - q1[touch]):
            for d in (w, -w):  # the two rays at +-half about d
                left = np.array([d[0] * c - d[1] * s, d[0] * s + d[1] * c])
                right = np.array([d[0] * c + d[1] * s, d[1] * c - d[0] * s])
                out.append(shapely.Polygon([x, x + far * left, x + far * right]))
    return out


def coverage_regions(
    site: Site,
    targets: Targets,
    limits: SightLimits,
    which: Sequence[int] | None = None,
    spaces: dict[str, FrameSpace] | None = None,
    outer: bool = False,
) -> dict[int, shapely.Geometry]:
    """R_t for the pieces ``which`` (all by default), as shapely geometries (possibly empty). ``spaces`` caches
    :func:`frame_space` per frame between calls (one cache per ``outer``). ``outer``: the outer approximation O_t
    instead (:func:`piece_region`)."""
    spaces = spaces if spaces is not None else {}
    idx = range(len(targets)) if which is None else which
    out: dict[int, shapely.Geometry] = {}
    for t in idx:
        frame = targets.frames[int(targets.frame[t])]
        if frame not in spaces:
            spaces[frame] = frame_space(site, frame, limits, outer)
        out[int(t)] = piece_region(targets, int(t), limits, spaces[frame], outer)
    return out


def outer_tolerance_m(limits: SightLimits) -> float:
    """How far a covering position can lie outside the outer region O_t (:func:`piece_region` with ``outer``): the
    approximations left there are the 3-D incidence chords, the precision boundary's chord error and the sight test's
    tolerances (range discs are circumscribed, stand-off buffers inscribed, no grazing slivers)."""
    precision = 2.0 * PRECISION_CHORD_M if limits.per_pair_precision else 0.0
    return (HYPERBOLA_SAGITTA_M if limits.incidence_3d else 0.0) + 1e-5 + precision


def piece_region(
    targets: Targets, t: int, limits: SightLimits, space: FrameSpace, outer: bool = False
) -> shapely.Geometry:
    """R_t of one piece (see the module docstring). ``outer`` (with a ``space`` made with ``outer``): range discs
    circumscribed instead of inscribed and no grazing slivers, so that every covering position lies in the result or
    within :func:`outer_tolerance_m` of it (for bounds; ``R_t`` itself is for candidates)."""
    region = shapely.Polygon()
    for _, region in region_stages(targets, t, limits, space, outer):
        if region.is_empty:
            break
    return region


#: what each stage of :func:`region_stages` takes away, in words (why a region is empty)
STAGE_REASON = {
    "range": "beyond range (no position within S_max of both ends, top and foot)",
    "incidence": "beyond the incidence limit within range",
    "precision": "beyond the precision range at every incidence",
    "stand": "no place to stand in front of it (stand-off, obstacles, no-go areas, site boundary)",
    "sight": "hidden behind walls or obstacles from every position that meets the range and incidence limits",
}


def region_stages(
    targets: Targets, t: int, limits: SightLimits, space: FrameSpace, outer: bool = False
) -> Iterator[tuple[str, shapely.Geometry]]:
    """The region of piece ``t`` as it is built, one rule at a time: (stage, region so far) for the stages of
    :data:`STAGE_REASON` in order; the last is R_t. The first empty one says why R_t is empty."""
    a, b = np.asarray(targets.a[t], float), np.asarray(targets.b[t], float)
    n = np.asarray(targets.normal[t], float)
    tangent = _unit(b - a)
    ih = limits.instrument_height_m
    far = space.far_m
    front = shapely.Polygon(
        [
            a + EPS_FRONT_M * n - far * tangent,
            b + EPS_FRONT_M * n + far * tangent,
            b + far * n + far * tangent,
            a + far * n - far * tangent,
        ]
    )
    discs, wedges, fans = [front], [], []
    for end, h in ((a, float(targets.ha_m[t])), (b, float(targets.hb_m[t]))):
        dz = max(abs(h - ih), ih)
        s = limits.effective_range_m
        reach = far
        if math.isfinite(s) and s < far:
            if s <= dz:
                yield "range", shapely.Polygon()
                return
            reach = math.sqrt(s * s - dz * dz)
            disc = reach / math.cos(math.pi / DISC_SEGMENTS) if outer else reach
            discs.append(shapely.Point(end).buffer(disc, quad_segs=DISC_SEGMENTS // 4))
        wedges.append(_incidence_region(end, tangent, n, limits.theta_max_deg, dz, limits.incidence_3d, 1.01 * reach))
        if limits.per_pair_precision:
            fans.append(precision_region(end, tangent, n, dz, limits))
    k = shapely.intersection_all(discs)
    yield "range", k
    k = shapely.intersection_all([k, *wedges]) if not k.is_empty else k
    yield "incidence", k
    if fans and not k.is_empty:
        k = shapely.intersection_all([k, *fans])
        yield "precision", k
    zi, inside = int(targets.zone[t]), int(targets.side[t]) == 0
    region = k.intersection((space.inside if inside else space.outside)[zi]) if not k.is_empty else k
    yield "stand", region
    if not region.is_empty:
        region = _unshadowed(region, _piece_shadows(targets, t, k, space, outer))
    yield "sight", region


def _unshadowed(region: shapely.Geometry, shadows: list[shapely.Geometry]) -> shapely.Geometry:
    """``region`` minus the union of ``shadows``. Only the shadows that meet ``region`` are unioned: the same point set
    (a shadow apart from the region takes nothing from it), at a fraction of the cost, as most shadows of the blockers
    near a piece reach far past its region and the union of them all is what costs."""
    if not shadows:
        return region
    polys = np.asarray(shadows, dtype=object)
    shapely.prepare(region)
    polys = polys[shapely.intersects(region, polys)]
    if not polys.size:
        return region
    try:
        return region.difference(shapely.union_all(polys))
    except shapely.errors.GEOSException:  # near-coincident sliver edges (doors, junction cuts): snap-round
        return shapely.difference(region, shapely.union_all(polys, grid_size=SNAP_GRID_M), grid_size=SNAP_GRID_M)


def _piece_shadows(
    targets: Targets, t: int, k: shapely.Geometry, space: FrameSpace, outer: bool
) -> list[shapely.Geometry]:
    """The shadows (and, unless ``outer``, the grazing slivers) of the blockers near piece ``t`` that meet ``k``."""
    bl = space.blockers
    tree = None if bl is None else bl._seg_tree  # type: ignore[attr-defined]
    if tree is None or bl is None:
        return []
    a, b = np.asarray(targets.a[t], float), np.asarray(targets.b[t], float)
    far = space.far_m
    ends = shapely.box(*np.minimum(a, b) - 1e-6, *np.maximum(a, b) + 1e-6)
    hit = np.union1d(tree.query(k, predicate="intersects"), tree.query(ends, predicate="intersects"))
    hit = hit[bl.key[hit] != wall_key(int(targets.zone[t]), int(targets.wall[t]))]
    if not hit.size:
        return []
    m = hit.size
    shadows = _shadows(np.tile(a, (m, 1)), np.tile(b, (m, 1)), bl.a[hit], bl.b[hit], 2.0 * far)
    if not outer:
        shadows += _grazing(a, b, bl.a[hit], bl.b[hit], 2.0 * far)
    return shadows


def why_empty(targets: Targets, t: int, limits: SightLimits, space: FrameSpace) -> str | None:
    """Why R_t is empty, in words (:data:`STAGE_REASON`), or None when it is not."""
    for stage, region in region_stages(targets, t, limits, space):
        if region.is_empty:
            return STAGE_REASON[stage]
    return None
