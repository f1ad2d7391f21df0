"""The candidate pool: closed-form candidates, samples in their movement fields, corner rays and a grid."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely

from planner.candidates.closed_form import (
    Limits,
    plan_zone_side,
    pole_in_frame,
    rotate,
    scan_side_angles,
    side_candidate,
    side_sign,
)
from planner.candidates.formulas import horizontal_reach_m
from planner.core.checks import argument, count, real
from planner.core.settings import DEFAULTS
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Site, Zone

#: vertices within this of 180 deg (a curve drawn finely) get no corner rays or bisector points
NEARLY_STRAIGHT_DEG = 5.0
#: the candidate grid where none is given and no strategy chose one (one model, studies, tests), m
GRID_SPACING_M = 10.0


@dataclass(frozen=True, kw_only=True)
class PoolOptions:
    """How dense the pool is. ``grid_spacing_m``: grid over the accessible area (a zone-side region too small for
    ``min_grid_points`` at that spacing gets a finer grid); None: the run's strategy chooses it
    (:func:`planner.plan.problem.resolve`), :data:`GRID_SPACING_M` where nothing chooses; ``field_samples``: random
    points (seeded) per movement field; ``min_standoff_m``: grid and field points closer to a wall are dropped."""

    grid_spacing_m: float | None = DEFAULTS["pool.grid_spacing_m"]
    field_samples: int = 6
    min_grid_points: int = 12
    min_standoff_m: float = 0.5
    seed: int = DEFAULTS["pool.seed"]

    def __post_init__(self) -> None:
        if self.grid_spacing_m is not None:
            real(self.grid_spacing_m, "grid_spacing_m", above=0.0)
        real(self.min_standoff_m, "min_standoff_m", at_least=0.0)
        count(self.field_samples, "field_samples", 0)
        count(self.min_grid_points, "min_grid_points", 1)
        count(self.seed, "seed", 0)

    @property
    def grid_m(self) -> float:
        """The grid spacing this pool is built with, m: the one given or chosen, else :data:`GRID_SPACING_M`."""
        return GRID_SPACING_M if self.grid_spacing_m is None else self.grid_spacing_m


def closed_form_candidates(site: Site, limits: Limits) -> list[Candidate]:
    """Every zone-side's vertex, wall and circle candidates, in zone order."""
    return [c for z in site.zones for side in z.scan_side.sides for c in plan_zone_side(z, side, limits).candidates]


def _region(zone: Zone, side: ScanSide, reach_m: float) -> shapely.Geometry:
    """Where a station for this zone-side can usefully stand (before obstacles and boundary)."""
    if side is ScanSide.INSIDE:
        return zone.polygon
    return zone.polygon.buffer(reach_m, quad_segs=16).difference(zone.polygon)


def _frame_axes(site: Site, frame: str) -> tuple[np.ndarray, np.ndarray]:
    """Origin and unit x-axis of the grid of a frame: first vertex and first wall of its first zone, so that rotating or
    translating a site moves the grid with it."""
    zone = next(z for z in site.zones if z.frame == frame)
    xy = np.asarray(zone.xy)
    d = xy[1] - xy[0]
    return xy[0], d / np.hypot(*d)


def _grid_points(region: shapely.Geometry, origin: np.ndarray, ux: np.ndarray, spacing: float) -> np.ndarray:
    uy = np.array([-ux[1], ux[0]])
    corners = np.asarray(shapely.get_coordinates(shapely.envelope(region))) - origin
    u, v = corners @ ux, corners @ uy
    iu = np.arange(math.floor(u.min() / spacing), math.ceil(u.max() / spacing) + 1)
    iv = np.arange(math.floor(v.min() / spacing), math.ceil(v.max() / spacing) + 1)
    gu, gv = np.meshgrid(iu * spacing, iv * spacing, indexing="xy")
    pts = origin + np.outer(gu.ravel(), ux) + np.outer(gv.ravel(), uy)
    return pts[shapely.contains_xy(region, pts[:, 0], pts[:, 1])]


def _sample_polygon(
    poly: shapely.Geometry, k: int, rng: np.random.Generator, origin: np.ndarray, ux: np.ndarray
) -> np.ndarray:
    """Up to ``k`` uniform points of ``poly``, drawn in the box of its coordinates along the frame's axes (origin, ux):
    the same draws land on the same points of a rotated or translated site."""
    if k <= 0 or poly.is_empty or poly.area <= 0:
        return np.zeros((0, 2))
    uy = np.array([-ux[1], ux[0]])
    local = (np.asarray(poly.exterior.coords) - origin) @ np.column_stack([ux, uy])
    lo, hi = local.min(axis=0), local.max(axis=0)
    out = np.zeros((0, 2))
    for _ in range(20):
        uv = rng.uniform(lo, hi, size=(4 * k, 2))
        pts = origin + np.outer(uv[:, 0], ux) + np.outer(uv[:, 1], uy)
        out = np.vstack([out, pts[shapely.contains_xy(poly, pts[:, 0], pts[:, 1])]])
        if len(out) >= k:
            break
    return out[:k]


def _corner_rays(zone: Zone, side: ScanSide, limits: Limits) -> Iterable[tuple[str, np.ndarray]]:
    """Points near each wall of a corner from which the corner point itself is seen within theta_max. From a corner, the
    corner point is seen at incidence <= theta_max only from bearings >= 90 - theta_max off the wall; in a sharp corner
    that is a thin sliver along the other wall, which no grid hits. Rays at the middle of each sliver, at 1/5 .. 4/5 of
    the reach."""
    xy = np.asarray(zone.xy)
    n = len(xy)
    angles = scan_side_angles(zone, side)
    lo = 90.0 - limits.theta_max_deg
    for i in range(n):
        a = float(angles[i])
        if a <= lo or a >= 180.0 - NEARLY_STRAIGHT_DEG:
            continue
        reach = horizontal_reach_m(limits.max_slant_range_m, zone.vertex_heights_m[i], limits.instrument_height_m)
        out = (xy[(i + 1) % n] - xy[i]) / np.hypot(*(xy[(i + 1) % n] - xy[i]))
        for tag, bearing in (("a", (lo + min(a, 90.0)) / 2.0), ("b", a - (lo + min(a, 90.0)) / 2.0)):
            d = rotate(out, side_sign(side) * bearing)
            for k, f in enumerate((0.2, 0.4, 0.6, 0.8), 1):
                yield f"V{i + 1}{tag}{k}", xy[i] + f * reach * d


def _bisector_points(zone: Zone, region: shapely.Geometry, standoff_m: float) -> Iterable[tuple[str, np.ndarray]]:
    """At every vertex of the outline and the holes, points on the bisector (scanning side): the one ``standoff_m`` off
    both walls and one three times as far, where the bisector stays in ``region`` that long; in a sliver narrower than
    that, the middle of the bisector's first stretch in the region (closer to the walls than the stand-off: the only
    place that sees the sliver's tip). These are the corner stations an art-gallery vertex guard would take, moved off
    the walls."""
    lo, hi = np.asarray(region.bounds[:2]), np.asarray(region.bounds[2:])
    far = 2.0 * float(np.hypot(*(hi - lo))) + 1.0
    for r, ring in enumerate(zone.rings):
        prev, nxt = np.roll(ring, 1, axis=0), np.roll(ring, -1, axis=0)
        for i, p in enumerate(ring):
            u = (prev[i] - p) / np.hypot(*(prev[i] - p))
            w = (nxt[i] - p) / np.hypot(*(nxt[i] - p))
            if abs(math.degrees(math.acos(max(-1.0, min(1.0, float(u @ w))))) - 180.0) < NEARLY_STRAIGHT_DEG:
                continue  # a nearly straight vertex (a finely drawn curve) is no corner
            b = (u + w) / np.hypot(*(u + w))
            for direction in (b, -b):
                step = p + 1e-6 * direction
                if not shapely.contains_xy(region, step[0], step[1]):
                    continue
                stretch = _first_stretch(region, p, p + far * direction)
                half = math.acos(max(-1.0, min(1.0, float(direction @ w))))
                d = standoff_m / max(math.sin(half), 1e-9)
                if d < stretch:
                    yield f"B{r}.{i + 1}", p + d * direction
                    if 3 * d < stretch:
                        yield f"B{r}.{i + 1}x3", p + 3 * d * direction
                else:
                    yield f"B{r}.{i + 1}m", p + 0.5 * stretch * direction
                break


def _first_stretch(region: shapely.Geometry, p: np.ndarray, q: np.ndarray) -> float:
    """Length of the part of segment p-q inside ``region`` that starts at p."""
    parts = shapely.get_parts(shapely.intersection(region, shapely.LineString([p, q])))
    return max((g.length for g in parts if g.length > 0 and shapely.distance(g, shapely.Point(p)) < 1e-6), default=0.0)


def candidate_pool(site: Site, limits: Limits, options: PoolOptions) -> list[Candidate]:
    """Closed-form candidates, then field samples, and per zone-side the corner rays, the centre (inside), the
    corner-bisector points and the grid; duplicates removed. Order matters: it is the tie-breaking order of the greedy,
    closed form first."""
    argument(site, Site, "site")
    rng = np.random.default_rng(options.seed)
    closed = closed_form_candidates(site, limits)
    pool: list[Candidate] = list(closed)
    for c in closed:
        if c.field:
            origin, ux = _frame_axes(site, c.frame)
            for k, (x, y) in enumerate(
                _sample_polygon(shapely.Polygon(c.field), options.field_samples, rng, origin, ux), 1
            ):
                pool.append(Candidate(f"{c.id}.f{k}", c.zone, c.side, c.frame, float(x), float(y), CandidateKind.FIELD))
    walls = {
        f: shapely.MultiLineString(
            [r for z in site.zones if z.frame == f for r in (z.polygon.exterior, *z.polygon.interiors)]
        )
        for f in dict.fromkeys(z.frame for z in site.zones)
    }
    for zone in site.zones:
        for side in zone.scan_side.sides:
            pool += _zone_side_points(site, zone, side, limits, options, walls[zone.frame])
    return dedupe(pool)


def _zone_side_points(
    site: Site, zone: Zone, side: ScanSide, limits: Limits, options: PoolOptions, walls: shapely.Geometry
) -> list[Candidate]:
    """The corner rays, the centre (inside), the corner-bisector points and the grid of one zone-side."""

    def point(name: str, x: float, y: float, kind: CandidateKind = CandidateKind.FIELD) -> Candidate:
        return side_candidate(zone.id, side, zone.frame, name, float(x), float(y), kind)

    out = [point(name, *p) for name, p in _corner_rays(zone, side, limits)]
    reach = max(
        horizontal_reach_m(limits.max_slant_range_m, h, limits.instrument_height_m) for h in zone.vertex_heights_m
    )
    region = _region(zone, side, reach)
    if region.is_empty:  # no wall top within reach from outside: no point stands usefully (coverage says
        return out  # which pieces nothing sees, exit 4)
    origin, ux = _frame_axes(site, zone.frame)
    if side is ScanSide.INSIDE:  # the point farthest from every wall: a room's natural centre station
        centre = pole_in_frame(region, origin, ux)
        out.append(point("P", centre.x, centre.y, CandidateKind.GRID))
    out += [point(name, *p) for name, p in _bisector_points(zone, region, options.min_standoff_m)]
    spacing = options.grid_m
    if region.area / spacing**2 < options.min_grid_points:
        spacing = max(math.sqrt(region.area / options.min_grid_points), 0.25)
    pts = _grid_points(region, origin, ux, spacing)
    far = shapely.distance(walls, shapely.points(pts)) >= options.min_standoff_m if len(pts) else []
    kept = pts[np.asarray(far, dtype=bool)] if len(pts) else []
    return out + [point(f"G{k}", x, y, CandidateKind.GRID) for k, (x, y) in enumerate(kept, 1)]


def dedupe(cands: Sequence[Candidate], tol_m: float = 1e-6) -> list[Candidate]:
    """Drop candidates standing where an earlier one of the same frame stands (within tol_m)."""
    seen: set[tuple[str, int, int]] = set()
    out = []
    for c in cands:
        key = (c.frame, round(c.x / tol_m), round(c.y / tol_m))
        if key not in seen:
            seen.add(key)
            out.append(c)
    return out
