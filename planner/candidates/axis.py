"""Candidates along each room's medial axis, one in every cell of the coverage arrangement on it.

A grid anchored anywhere misses a room narrower than its step (a corridor 8 m wide between two rows of a 10-m grid gets
no candidate at all). The medial axis of a room's stand area (the points with two or more nearest boundary points: a
corridor's centre line, a room's skeleton) runs through every part of it, however narrow and however turned. It is
approximated by the Voronoi edges of the boundary sampled finely (edges strictly inside the area).

Along the axis the set of pieces a station covers changes only where the axis crosses the boundary of a coverage region
R_t: each region holds closed stretches of the axis. A candidate is put in every maximal cell of those stretches (where
a stretch ends right after the last one began: the classic maximal cliques of intervals), so the pool holds, for every
position on the axis, a candidate that sees all it sees (up to the regions' tolerance). Any plan whose stations stand on
the axis (a corridor's centre-line construction: stations ``w/2 tan(theta_max)`` either side of each other) is matched
or beaten by the plain cover over the pool.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.candidates.closed_form import side_candidate
from planner.candidates.from_regions import largest_part_pole
from planner.coverage.regions import FrameSpace, coverage_regions, frame_space
from planner.coverage.targets import SIDE_CODE, Targets
from planner.coverage.threads import Background, ordered_map
from planner.coverage.visibility import SightLimits
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Site

#: boundary points of the stand area per narrowest half-width (so the Voronoi edges follow the axis)
SAMPLES_PER_WIDTH = 8
#: boundary samples at most this far apart
MAX_SAMPLE_STEP_M = 0.5
#: no more boundary samples than this per zone (a huge zone keeps a coarser axis)
MAX_BOUNDARY_SAMPLES = 20_000
#: axis candidates per zone-side times its pieces at most (the cells are thinned evenly beyond it): a round room drawn
#: with 5,000 walls has a spoke per vertex, and every candidate on them sees the room
MAX_AXIS_PAIRS = 2_000_000
#: ... but never fewer candidates than this
MIN_AXIS_CANDIDATES = 100
#: distances of the rings around an outside zone along which its candidates are put, as shares of the horizontal reach
#: (stations for an outside face stand far off)
OUTSIDE_RINGS = (0.3, 0.45)
#: pieces x vertices of the stand area above which the lines are sampled every ``step_m`` instead of cut by the regions
#: (a many-vertex apse passes it; an ordinary zone-side stays well under it)
MAX_CELL_WORK = 4_000_000
#: axis lines shorter than this get one candidate at their middle instead of their cells (m)
MIN_CELL_LINE_M = 0.5
#: at most this many axis lines per zone-side are cut by the regions (the longest); the rest get their middle
MAX_CELL_LINES = 200
#: stretch ends closer than this along the axis are one
CUT_TOL_M = 1e-6


def medial_axis(area: shapely.Geometry) -> list[shapely.LineString]:
    """The medial axis of ``area`` (a polygon or multipolygon) as merged lines, approximated by the Voronoi edges of its
    boundary sampled at an eighth of its narrowest half-width (at most 0.5 m, at least 1 mm)."""
    out: list[shapely.LineString] = []
    for part in shapely.get_parts(area):
        if part.is_empty or part.area <= 0:
            continue
        half = float(shapely.distance(largest_part_pole(part), part.boundary))
        seg = min(max(half / SAMPLES_PER_WIDTH, 1e-3), MAX_SAMPLE_STEP_M)
        seg = max(seg, part.boundary.length / MAX_BOUNDARY_SAMPLES)
        pts = shapely.get_coordinates(shapely.segmentize(part.boundary, seg))
        if len(pts) < 3:
            continue
        edges = voronoi_edges(pts)
        edges = edges[shapely.contains_properly(part, edges)]
        if len(edges) == 0:
            continue
        merged = shapely.get_parts(shapely.line_merge(shapely.union_all(edges)))
        out += [g for g in shapely.simplify(merged, 1e-9) if g.length > 0]  # collinear vertices dropped
    return out


def voronoi_edges(points: NDArray[np.float64]) -> NDArray[np.object_]:
    """The edges of the Voronoi diagram of ``points`` as two-point lines, each once (in a canonical order), from the
    rings of its cells: the same segments, coordinate for coordinate, as GEOS's ``only_edges`` output inside the
    diagram's envelope (plus the envelope's own, which no caller keeps), without the clipping of each edge to the
    envelope one by one that makes that output cost 0.8 s for 3,000 points against 0.06 s for the cells."""
    cells = shapely.get_parts(shapely.voronoi_polygons(shapely.multipoints(points)))
    xy, ring = shapely.get_coordinates(shapely.get_exterior_ring(cells), return_index=True)
    same = ring[:-1] == ring[1:]
    a, b = xy[:-1][same], xy[1:][same]
    first = ((a[:, 0] < b[:, 0]) | ((a[:, 0] == b[:, 0]) & (a[:, 1] <= b[:, 1])))[:, None]
    seg = np.unique(np.hstack([np.where(first, a, b), np.where(first, b, a)]), axis=0)  # each shared edge once
    seg = seg[(seg[:, 0] != seg[:, 2]) | (seg[:, 1] != seg[:, 3])]
    return shapely.linestrings(seg.reshape(-1, 2, 2))


def intervals(
    line: shapely.LineString, regions: Sequence[shapely.Geometry], tree: shapely.STRtree | None = None
) -> tuple[NDArray, NDArray]:
    """The stretches of ``line`` inside each of ``regions`` (closed sets), as distances along it: (lo, hi) per stretch;
    a region that only touches the line gives a stretch of length 0. ``tree``: an STR-tree of ``regions`` (built here
    when not given; one tree serves every line cut by the same regions)."""
    tree = shapely.STRtree(list(regions)) if tree is None else tree
    hit = tree.query(line, predicate="intersects")
    if hit.size == 0:
        return np.zeros(0), np.zeros(0)
    parts = shapely.get_parts(shapely.intersection(line, np.asarray(regions, dtype=object)[hit]))
    kind = shapely.get_type_id(parts)
    dots = shapely.get_coordinates(parts[kind == 0])
    runs = parts[kind == 1]
    ends = [shapely.get_coordinates(shapely.get_point(runs, i)) for i in (0, -1)] if len(runs) else []
    xy = np.vstack([*ends, dots]) if len(runs) or len(dots) else np.zeros((0, 2))
    along = locate(line, xy) if len(xy) else np.zeros(0)  # the first and last point of each run, then the dots
    first, last, at = np.split(along, [len(runs), 2 * len(runs)])
    return np.concatenate([np.minimum(first, last), at]), np.concatenate([np.maximum(first, last), at])


def maximal_cells(lo: NDArray[np.float64], hi: NDArray[np.float64]) -> NDArray[np.float64]:
    """A point of every maximal cell of closed intervals [lo, hi] on a line: where a stretch ends right after the last
    one began, the middle of the two (the set of stretches holding it is then not contained in any other point's). Every
    position on the line sees a subset of the pieces seen from one of these points."""
    if lo.size == 0:
        return np.zeros(0)
    lo = np.round(lo / CUT_TOL_M) * CUT_TOL_M
    hi = np.round(hi / CUT_TOL_M) * CUT_TOL_M
    # events: starts before ends at one coordinate (closed intervals touching at a point share it)
    pos = np.concatenate([lo, hi])
    kind = np.concatenate([np.zeros(lo.size, int), np.ones(hi.size, int)])
    order = np.lexsort((kind, pos))
    pos, kind = pos[order], kind[order]
    turn = np.flatnonzero((kind[:-1] == 0) & (kind[1:] == 1))  # a start followed by an end
    return (pos[turn] + pos[turn + 1]) / 2.0


def locate(line: shapely.LineString, xy: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distance along ``line`` of each point of ``xy`` (points on or next to it): its nearest segment found with a tree,
    then the projection onto it (``line_locate_point`` walks every vertex for every point)."""
    v = shapely.get_coordinates(line)
    a, b = v[:-1], v[1:]
    seg = np.hypot(*(b - a).T)
    start = np.concatenate([[0.0], np.cumsum(seg)[:-1]])
    tree = shapely.STRtree(shapely.linestrings(np.stack([a, b], axis=1)))
    _, k = tree.query_nearest(shapely.points(xy), all_matches=False)
    u = (b[k] - a[k]) / np.where(seg[k] > 0, seg[k], 1.0)[:, None]
    along = np.clip(np.einsum("ij,ij->i", xy - a[k], u), 0.0, seg[k])
    return start[k] + along


def offset_rings(
    zone_polygon: shapely.Geometry, area: shapely.Geometry, distances_m: Sequence[float]
) -> list[shapely.LineString]:
    """The rings at ``distances_m`` outside a zone's outline, clipped to the stand ``area``: where stations for an
    outside face stand (the outside has no medial axis to follow)."""
    out: list[shapely.LineString] = []
    for d in distances_m:
        ring = shapely.boundary(zone_polygon.buffer(d, quad_segs=8, join_style="mitre", mitre_limit=2.0))
        part = shapely.intersection(ring, area)
        out += [g for g in shapely.get_parts(shapely.line_merge(part)) if shapely.get_type_id(g) == 1 and g.length > 0]
    return out


def axis_candidates(
    site: Site,
    targets: Targets,
    limits: SightLimits,
    spaces: dict[str, FrameSpace] | None = None,
    cache: dict[int, shapely.Geometry] | None = None,
    cells: bool = True,
    step_m: float = 1.0,
) -> list[Candidate]:
    """One candidate in every maximal cell of the coverage arrangement along the medial axis of each inside zone's stand
    area, and along rings at :data:`OUTSIDE_RINGS` around each outside zone (the cells of the zone-side's own pieces'
    regions); ``cache`` keeps the regions drawn. Without ``cells`` (where regions do not model the coverage test), or
    past :data:`MAX_CELL_WORK`, points every ``step_m`` along the lines."""
    spaces = {} if spaces is None else spaces
    cache = {} if cache is None else cache
    out: list[Candidate] = []
    reach = limits.effective_range_m if math.isfinite(limits.effective_range_m) else 100.0
    sides = []  # (zone index, side, stand area, pieces) of each zone-side with pieces and room to stand
    for zi, zone in enumerate(site.zones):
        if zone.frame not in spaces:
            spaces[zone.frame] = frame_space(site, zone.frame, limits)
        for side in zone.scan_side.sides:
            inside = side is ScanSide.INSIDE
            area = (spaces[zone.frame].inside if inside else spaces[zone.frame].outside)[zi]
            pieces = np.flatnonzero((targets.zone == zi) & (targets.side == SIDE_CODE[side]))
            if not (area.is_empty or pieces.size == 0):
                sides.append((zi, side, area, pieces))
    with Background() as later:  # each zone-side's lines drawn beside the regions (they need none of them)
        lines_of = [
            later.start(medial_axis, area)
            if side is ScanSide.INSIDE
            else later.start(offset_rings, site.zones[zi].polygon, area, [f * reach for f in OUTSIDE_RINGS])
            for zi, side, area, _ in sides
        ]
        for (zi, side, area, pieces), lines_later in zip(sides, lines_of):
            zone = site.zones[zi]
            if cells and pieces.size * shapely.get_num_coordinates(area) <= MAX_CELL_WORK:
                missing = [int(t) for t in pieces if int(t) not in cache]
                cache.update(coverage_regions(site, targets, limits, missing, spaces))
                regions = [cache[int(t)] for t in pieces if not cache[int(t)].is_empty]
                pts = _zone_points(lines_later.result(), regions)
            else:
                pts = _zone_points(lines_later.result(), [], step_m)
            cap = max(MIN_AXIS_CANDIDATES, MAX_AXIS_PAIRS // max(int(pieces.size), 1))
            if len(pts) > cap:  # evenly thinned: a huge or round room keeps a sample of its axis cells
                pts = pts[np.linspace(0, len(pts) - 1, cap).round().astype(int)]
            out += [
                side_candidate(zone.id, side, zone.frame, f"A{k}", float(x), float(y), CandidateKind.AXIS)
                for k, (x, y) in enumerate(pts, 1)
            ]
    return out


def _zone_points(
    lines: Sequence[shapely.LineString], regions: Sequence[shapely.Geometry], step_m: float = 1.0
) -> NDArray[np.float64]:
    """The maximal-cell points of ``lines`` under ``regions``; with no regions, points every ``step_m``."""
    if not lines:
        return np.zeros((0, 2))

    # the longest lines first; a stub (the spokes of a round room's axis) stands for itself by its middle
    lines = sorted(lines, key=lambda g: -g.length)
    cut = [g for g in lines if g.length >= MIN_CELL_LINE_M][:MAX_CELL_LINES] if regions else list(lines)

    tree = shapely.STRtree(list(regions)) if regions else None

    def along(line: shapely.LineString) -> NDArray[np.float64]:
        if regions:
            return maximal_cells(*intervals(line, regions, tree))
        return np.linspace(0.0, line.length, max(1, math.ceil(line.length / step_m)) + 1)

    def cells(line: shapely.LineString) -> NDArray[np.float64]:
        return shapely.get_coordinates(shapely.line_interpolate_point(line, along(line)))

    parts = ordered_map(cells, cut)  # each line cut alone (GEOS works without Python's lock): on a few threads
    parts += [
        shapely.get_coordinates(shapely.line_interpolate_point(line, 0.5, normalized=True))
        for line in lines[len(cut) :]
    ]
    return np.unique(np.round(np.vstack(parts), 9), axis=0)
