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
from dataclasses import dataclass, field

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.coverage.matrix import ON_WALL_M, blockers_for, convex_alone
from planner.coverage.region_precision import PRECISION_CHORD_M, precision_region
from planner.coverage.shadows import sight_stage, unit
from planner.coverage.targets import Targets
from planner.coverage.threads import ordered_map, thread_count
from planner.coverage.visibility import EPS_FRONT_M, Blockers, SightLimits
from planner.site.model import SITE_FRAME, Site

#: vertices of the polygon inscribed in each range disc
DISC_SEGMENTS = 512
#: largest distance of a 3-D incidence boundary from its chords (m)
HYPERBOLA_SAGITTA_M = 1e-3
#: segments per quarter circle of the stand-off buffers
STANDOFF_QUAD_SEGS = 16
#: pieces whose stages before sight are drawn together (vectorised; memory in proportion)
CHUNK = 256
#: ... but a batch of pieces is split into as many chunks as there are threads, down to this many pieces a chunk
MIN_CHUNK = 16
#: range discs kept per frame for later chunks and calls (about 8 kB each)
DISC_CACHE = 4096


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
    #: range discs drawn in this frame, by (x, y, radius): a piece's end is shared with its neighbour, which another
    #: chunk or call may draw (the inside and outside pieces of a wall, the batches of a common region)
    discs: dict[tuple[float, float, float], shapely.Geometry] = field(default_factory=dict, repr=False)


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


def coverage_regions(
    site: Site,
    targets: Targets,
    limits: SightLimits,
    which: Sequence[int] | NDArray[np.integer] | None = None,
    spaces: dict[str, FrameSpace] | None = None,
    outer: bool = False,
) -> dict[int, shapely.Geometry]:
    """R_t for the pieces ``which`` (all by default), as shapely geometries (possibly empty). ``spaces`` caches
    :func:`frame_space` per frame between calls (one cache per ``outer``). ``outer``: the outer approximation O_t
    instead (:func:`piece_region`). The stages before sight are drawn :data:`CHUNK` pieces of a frame at a time
    (:func:`convex_stages`; fewer, down to :data:`MIN_CHUNK`, so that a small batch gives every thread a chunk), the
    chunks on a few threads (:func:`planner.coverage.threads.ordered_map`); each piece's region is the one
    :func:`piece_region` draws."""
    spaces = spaces if spaces is not None else {}
    idx = np.arange(len(targets)) if which is None else np.asarray(which, dtype=np.int64).reshape(-1)
    drawn: dict[int, shapely.Geometry] = {}
    frame_of = np.asarray(targets.frame)[idx]
    chunks: list[tuple[NDArray[np.int64], FrameSpace]] = []
    workers = thread_count()
    for f in dict.fromkeys(frame_of.tolist()):  # frames in order of first use
        frame = targets.frames[int(f)]
        if frame not in spaces:
            spaces[frame] = frame_space(site, frame, limits, outer)
        mine = idx[frame_of == f]
        size = min(CHUNK, max(MIN_CHUNK, -(-len(mine) // workers)))  # a small batch still keeps the threads busy
        chunks += [(mine[start : start + size], spaces[frame]) for start in range(0, len(mine), size)]
    # the chunks side by side (each region is drawn from its own piece alone, so the same in any chunk)
    for part in ordered_map(lambda c: _sighted(targets, c[0], limits, c[1], outer), chunks):
        drawn.update(part)
    return {int(t): drawn[int(t)] for t in idx}


def _sighted(
    targets: Targets, idx: NDArray[np.int64], limits: SightLimits, space: FrameSpace, outer: bool
) -> dict[int, shapely.Geometry]:
    """R_t of the pieces ``idx`` of one frame: :func:`convex_stages`, then the sight stage. A region empty at an earlier
    stage is that stage's (each stage leaves an empty region as it is)."""
    stages = convex_stages(targets, idx, limits, space, outer)
    k = stages["precision" if "precision" in stages else "incidence"]
    out = sight_stage(targets, idx, k, stages["stand"], space.blockers, space.far_m, outer)
    return dict(zip(idx.tolist(), out))


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
    :data:`STAGE_REASON` in order, up to the first empty one (which says why R_t is empty); the last is R_t."""
    stages = convex_stages(targets, np.array([t], dtype=np.int64), limits, space, outer)
    for stage, regions in stages.items():
        yield stage, regions[0]
        if regions[0].is_empty:
            return
    k = stages["precision" if "precision" in stages else "incidence"]
    yield "sight", sight_stage(targets, np.array([t]), k, stages["stand"], space.blockers, space.far_m, outer)[0]


def convex_stages(
    targets: Targets, idx: NDArray[np.int64], limits: SightLimits, space: FrameSpace, outer: bool = False
) -> dict[str, NDArray[np.object_]]:
    """The regions of the pieces ``idx`` (one frame) after each stage before sight, drawn for all of them at once
    (vectorised shapely calls; the disc about an end that two pieces share drawn once): stage -> object array, for
    ``range``, ``incidence``, ``precision`` (with a per-view precision test) and ``stand``. A region empty after a stage
    stays as it is. Each stage intersects in the order one piece at a time would, so each region is the same."""
    m = len(idx)
    a, b = np.asarray(targets.a[idx], float).reshape(m, 2), np.asarray(targets.b[idx], float).reshape(m, 2)
    n = np.asarray(targets.normal[idx], float).reshape(m, 2)
    tangent = unit(b - a)
    ih, far, s = limits.instrument_height_m, space.far_m, limits.effective_range_m
    corners = [a + EPS_FRONT_M * n - far * tangent, b + EPS_FRONT_M * n + far * tangent]
    k = shapely.polygons(np.stack([*corners, b + far * n + far * tangent, a + far * n - far * tangent], axis=1))
    limited = math.isfinite(s) and s < far
    ends = [(a, np.asarray(targets.ha_m[idx], float)), (b, np.asarray(targets.hb_m[idx], float))]
    dz = [np.maximum(np.abs(h - ih), ih) for _, h in ends]
    gone = (s <= dz[0]) | (s <= dz[1]) if limited else np.zeros(m, bool)
    reach = [np.sqrt(np.maximum(s * s - d * d, 0.0)) if limited else np.full(m, far) for d in dz]
    live = ~gone
    if limited:  # the range discs, inscribed (circumscribed with ``outer``)
        cos = math.cos(math.pi / DISC_SEGMENTS)
        radii = [r[live] / cos if outer else r[live] for r in reach]
        for disc in _discs([e[live] for e, _ in ends], radii, space.discs):
            k[live] = shapely.intersection(k[live], disc)
    k[gone] = shapely.Polygon()
    out = {"range": k.copy()}
    live = ~shapely.is_empty(k)
    for (end, _), d, r in zip(ends, dz, reach):
        k[live] = shapely.intersection(
            k[live], _wedges(end[live], tangent[live], n[live], d[live], 1.01 * r[live], limits)
        )
    out["incidence"] = k.copy()
    if limits.per_pair_precision:
        live = ~shapely.is_empty(k)
        for (end, _), d in zip(ends, dz):
            rows = np.flatnonzero(live)
            fans = [precision_region(end[i], tangent[i], n[i], float(d[i]), limits) for i in rows]
            k[live] = shapely.intersection(k[live], np.asarray(fans + [None], dtype=object)[:-1])
        out["precision"] = k.copy()
    live = ~shapely.is_empty(k)
    zone, side = np.asarray(targets.zone[idx]), np.asarray(targets.side[idx])
    area = [(space.inside if int(sd) == 0 else space.outside)[int(zi)] for zi, sd in zip(zone[live], side[live])]
    k[live] = shapely.intersection(k[live], np.asarray(area + [None], dtype=object)[:-1])
    out["stand"] = k
    return out


def _discs(
    centres: list[NDArray[np.float64]],
    radii: list[NDArray[np.float64]],
    cache: dict[tuple[float, float, float], shapely.Geometry],
) -> list[NDArray[np.object_]]:
    """The range discs about ``centres`` (one array per end), each distinct (centre, radius) drawn once: taken from
    ``cache`` where drawn before (the same disc: one buffer of one point), else drawn here and kept there (up to
    :data:`DISC_CACHE` discs)."""
    key = np.column_stack([np.concatenate(centres), np.concatenate(radii)])
    if not len(key):
        return [np.zeros(0, dtype=object) for _ in centres]
    rows, inverse = np.unique(key, axis=0, return_inverse=True)
    keys = [(x, y, r) for x, y, r in rows.tolist()]
    drawn = np.array([cache.get(k) for k in keys] + [None], dtype=object)[:-1]
    new = np.flatnonzero(drawn == None)  # noqa: E711 (elementwise: the discs not drawn yet)
    if new.size:
        drawn[new] = shapely.buffer(shapely.points(rows[new, :2]), rows[new, 2], quad_segs=DISC_SEGMENTS // 4)
        room = max(0, DISC_CACHE - len(cache))
        cache.update((keys[i], drawn[i]) for i in new[:room].tolist())
    drawn = drawn[inverse.reshape(-1)]
    return list(np.split(drawn, np.cumsum([len(c) for c in centres])[:-1]))


def _wedges(
    end: NDArray, tangent: NDArray, normal: NDArray, dz: NDArray, far: NDArray, limits: SightLimits
) -> NDArray[np.object_]:
    """:func:`_incidence_region` of each row: the horizontal wedges drawn at once, the 3-D ones one by one."""
    if not len(end):
        return np.zeros(0, dtype=object)
    theta = limits.theta_max_deg
    tan = math.tan(math.radians(theta))
    f = far[:, None]
    out = shapely.polygons(
        np.stack([end, end + f * (normal + tan * tangent), end + f * (normal - tan * tangent)], axis=1)
    )
    for i in np.flatnonzero(dz > 0) if limits.incidence_3d else ():
        out[i] = _incidence_region(end[i], tangent[i], normal[i], theta, float(dz[i]), True, float(far[i]))
    return out


def why_empty(targets: Targets, t: int, limits: SightLimits, space: FrameSpace) -> str | None:
    """Why R_t is empty, in words (:data:`STAGE_REASON`), or None when it is not."""
    for stage, region in region_stages(targets, t, limits, space):
        if region.is_empty:
            return STAGE_REASON[stage]
    return None
