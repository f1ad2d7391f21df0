"""Floor and ceiling targets: each zone's floor and ceiling cut into patches of at most ``spacing_m`` a side.

A zone scanned from inside has a floor at ``floor_level_m`` and, where ``ceiling_height_m`` is given, a ceiling that
much above it; an ``outside`` zone has neither.

- **Floor**: the outline less the footprints of the blocks standing in it (its holes and, in the site frame, the
  obstacles that overlap it): no one scans the floor under a column. No-go areas stay floor.
- **Ceiling**: the outline less the footprints of the blocks that reach the ceiling.

Each area is cut by a square grid anchored at the outline's bounding box (width and depth split into equal cells no
wider than ``spacing_m``), the cells clipped to the area. A clipped cell in several parts gives one patch per part; a
part holding a hole is cut through each hole's centroid; parts smaller than ``SLIVER_SHARE`` of a full cell are slivers
and dropped.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.coverage.targets import PieceArrays
from planner.site.model import SITE_FRAME, ScanSide, Site

FLOOR = 0
CEILING = 1
KIND_CODE = {"floor": FLOOR, "ceiling": CEILING}
KIND_NAME = {FLOOR: "floor", CEILING: "ceiling"}
#: a clipped cell part smaller than this share of a full cell is a sliver and no target (1 cm2 at 1 m spacing)
SLIVER_SHARE = 1e-4
#: a block whose top is within this of the ceiling reaches it
REACH_TOL_M = 1e-9
#: cells clipped per call (bounds the memory of one shapely call on a large zone)
CELL_BATCH = 65_536


@dataclass(frozen=True, eq=False)
class SurfaceTargets(PieceArrays):
    """Floor and ceiling patches as parallel read-only arrays (one entry per patch). ``kind`` is ``FLOOR`` or
    ``CEILING``; ``frame`` indexes ``frames`` (as in :class:`planner.coverage.targets.Targets`); ``cell`` the grid
    column and row; ``polygon`` the patch (no holes); ``corners`` its vertices (P, K, 2), padded by repeating the last,
    ``n_corners`` how many are its own; ``height_m`` in the site's vertical datum; ``normal`` the unit normal towards
    the room."""

    kind: NDArray[np.int8]
    cell: NDArray[np.int32]
    polygon: NDArray[np.object_]
    corners: NDArray[np.float64]
    n_corners: NDArray[np.int32]
    centroid: NDArray[np.float64]
    area_m2: NDArray[np.float64]
    height_m: NDArray[np.float64]
    normal: NDArray[np.float64]
    spacing_m: float

    def label(self, t: int) -> str:
        """A readable id: zone/kind, the grid cell and the patch's centroid, e.g. ``Z1/floor cell 3,4 at 3.50, 4.50
        m``."""
        return (
            f"{self.zone_ids[self.zone[t]]}/{KIND_NAME[int(self.kind[t])]} cell {self.cell[t, 0]},{self.cell[t, 1]}"
            f" at {self.centroid[t, 0]:.2f}, {self.centroid[t, 1]:.2f} m"
        )

    def total_area_m2(self, zone: int | None = None, kind: int | None = None) -> float:
        """The patches' area, of one zone and/or kind where given."""
        keep = np.ones(len(self), dtype=bool)
        if zone is not None:
            keep &= self.zone == zone
        if kind is not None:
            keep &= self.kind == kind
        return float(self.area_m2[keep].sum())

    @cached_property
    def is_convex(self) -> NDArray[np.bool_]:
        """For each patch, whether it equals its convex hull (:func:`convex`): worked out once per set of patches, for
        every sight test that asks (a plan's tripod discs test hundreds of rims)."""
        return np.asarray(convex(self.polygon), dtype=bool) if len(self) else np.zeros(0, dtype=bool)


def convex(polys: NDArray[np.object_]) -> NDArray[np.bool_]:
    """For each polygon, True when it equals its convex hull (to a relative 1e-9 of its area)."""
    area = shapely.area(polys)
    return np.asarray(shapely.area(shapely.convex_hull(polys)) - area <= 1e-9 * area)


def zone_blocks(site: Site, zi: int) -> list[tuple[shapely.Polygon, float]]:
    """Footprints and heights (the top above the zone's floor) of the blocks standing in zone ``zi``: its holes (at
    their highest vertex) and, in the site frame, the obstacles overlapping its outline by some area."""
    zone = site.zones[zi]
    out = [(shapely.Polygon(ring), float(max(hs))) for ring, hs in zip(zone.holes, zone.hole_heights_m)]
    if zone.frame == SITE_FRAME and site.obstacles:
        outline = shapely.Polygon(zone.xy)
        for ob in site.obstacles:
            footprint = shapely.Polygon(ob.vertices)
            if outline.intersection(footprint).area > 0:
                out.append((footprint, ob.height_m))
    return out


def open_area(site: Site, zi: int, reaching_m: float = 0.0) -> shapely.Polygon | shapely.MultiPolygon:
    """Zone ``zi``'s outline less the footprints of its blocks whose top is at least ``reaching_m`` above the floor:
    with 0 the floor, with the ceiling height (less ``REACH_TOL_M``) the ceiling."""
    outline = shapely.Polygon(site.zones[zi].xy)
    cut = [poly for poly, h in zone_blocks(site, zi) if h >= reaching_m]
    return outline.difference(shapely.union_all(cut)) if cut else outline


def surface_areas(site: Site, zi: int) -> dict[int, shapely.Polygon | shapely.MultiPolygon]:
    """The floor and (where the zone has one) ceiling area of zone ``zi``; none for a zone scanned from outside."""
    zone = site.zones[zi]
    if ScanSide.INSIDE not in zone.scan_side.sides:
        return {}
    out = {FLOOR: open_area(site, zi)}
    if zone.ceiling_height_m is not None:
        out[CEILING] = open_area(site, zi, zone.ceiling_height_m - REACH_TOL_M)
    return out


#: the grid the floor and ceiling areas are snapped to before they are cut into patches (m)
GRID_NM = 1e-9


def _split_holes(poly: shapely.Polygon) -> list[shapely.Polygon]:
    """The polygon cut by vertical lines through each hole's centroid, so that no part holds a hole."""
    if not poly.interiors:
        return [poly]
    cuts = sorted({shapely.Polygon(ring).centroid.x for ring in poly.interiors})
    x0, y0, x1, y1 = poly.bounds
    edges = [x0, *cuts, x1]
    out = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        for part in shapely.get_parts(shapely.intersection(poly, shapely.box(lo, y0, hi, y1))):
            if isinstance(part, shapely.Polygon) and not part.is_empty:
                out.append(part)
    return out


def _cells(area: shapely.Geometry, bounds: tuple[float, ...], spacing_m: float) -> tuple[list, list]:
    """The parts of every grid cell within ``area``: (polygons, (column, row) of each)."""
    x0, y0, x1, y1 = bounds
    nx = max(1, math.ceil((x1 - x0) / spacing_m - 1e-9))
    ny = max(1, math.ceil((y1 - y0) / spacing_m - 1e-9))
    xs = x0 + (x1 - x0) * np.arange(nx + 1) / nx
    ys = y0 + (y1 - y0) * np.arange(ny + 1) / ny
    ii, jj = (g.ravel() for g in np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij"))
    full = (x1 - x0) / nx * (y1 - y0) / ny
    # on a 1-nm grid: a block within float noise of a wall (2e-16 m off it) is a notch of the floor, not a hole
    # beside a sliver, wherever the site stands (a hole would split its cell into two patches)
    area = shapely.set_precision(area, GRID_NM)
    shapely.prepare(area)
    polys: list[shapely.Polygon] = []
    cells: list[tuple[int, int]] = []
    for k0 in range(0, len(ii), CELL_BATCH):
        i, j = ii[k0 : k0 + CELL_BATCH], jj[k0 : k0 + CELL_BATCH]
        boxes = shapely.box(xs[i], ys[j], xs[i + 1], ys[j + 1])
        whole = shapely.contains_properly(area, boxes)
        cut = shapely.intersects(area, boxes) & ~whole
        clipped = boxes.copy()
        clipped[cut] = shapely.intersection(boxes[cut], area)
        keep = np.flatnonzero(whole | cut)
        parts, owner = shapely.get_parts(clipped[keep], return_index=True)
        for part, k in zip(parts, keep[owner]):
            if not isinstance(part, shapely.Polygon):
                continue  # a cell touching the area along an edge or at a point
            for piece in _split_holes(part):
                if piece.area >= SLIVER_SHARE * full:
                    polys.append(piece)
                    cells.append((int(i[k - k0]), int(j[k - k0])))
    return polys, cells


def _corners(polys: NDArray[np.object_]) -> tuple[NDArray[np.float64], NDArray[np.int32]]:
    """Each polygon's exterior vertices (closing point dropped), padded to the longest by its last vertex."""
    if len(polys) == 0:
        return np.zeros((0, 1, 2)), np.zeros(0, np.int32)
    rings = shapely.get_exterior_ring(polys)
    counts = shapely.get_num_coordinates(rings) - 1
    coords = shapely.get_coordinates(rings)
    starts = np.concatenate([[0], np.cumsum(counts + 1)[:-1]])
    m = np.arange(int(counts.max()))
    take = starts[:, None] + np.minimum(m[None, :], counts[:, None] - 1)
    return coords[take], counts.astype(np.int32)


def make_surface_targets(site: Site, spacing_m: float, kinds: Iterable[str] = ("floor", "ceiling")) -> SurfaceTargets:
    """Cut the floor and ceiling (``kinds``) of every zone into patches no wider than ``spacing_m`` (a ValueError for a
    spacing that is not a finite number > 0, or another kind)."""
    if not math.isfinite(spacing_m) or spacing_m <= 0:
        raise ValueError(f"surface target spacing must be > 0, got {spacing_m}")
    wanted = set(kinds)
    if not wanted <= set(KIND_CODE):
        raise ValueError(f"surface kinds are floor and ceiling, got {sorted(wanted - set(KIND_CODE))}")
    codes = {KIND_CODE[k] for k in wanted}
    frames = tuple(dict.fromkeys(z.frame for z in site.zones))
    polys: list[shapely.Polygon] = []
    cols: dict[str, list] = {k: [] for k in ("zone", "kind", "frame", "cell", "height")}
    for zi, zone in enumerate(site.zones):
        bounds = shapely.Polygon(zone.xy).bounds
        for kind, area in surface_areas(site, zi).items():
            if kind not in codes or area.is_empty:
                continue
            ps, cells = _cells(area, bounds, spacing_m)
            above = zone.ceiling_height_m if kind == CEILING and zone.ceiling_height_m is not None else 0.0
            height = zone.floor_level_m + above
            polys += ps
            cols["cell"] += cells
            for name, value in (("zone", zi), ("kind", kind), ("frame", frames.index(zone.frame)), ("height", height)):
                cols[name] += [value] * len(ps)
    poly_arr = np.empty(len(polys), dtype=object)
    poly_arr[:] = polys
    corners, counts = _corners(poly_arr)
    kind_arr = np.asarray(cols["kind"], dtype=np.int8)
    normal = np.zeros((len(polys), 3))
    normal[:, 2] = np.where(kind_arr == FLOOR, 1.0, -1.0)
    centroid = shapely.get_coordinates(shapely.centroid(poly_arr)) if polys else np.zeros((0, 2))
    return SurfaceTargets(
        zone=np.asarray(cols["zone"], dtype=np.int32),
        kind=kind_arr,
        frame=np.asarray(cols["frame"], dtype=np.int32),
        cell=np.asarray(cols["cell"], dtype=np.int32).reshape(-1, 2),
        polygon=poly_arr,
        corners=corners,
        n_corners=counts,
        centroid=centroid,
        area_m2=shapely.area(poly_arr).astype(np.float64),
        height_m=np.asarray(cols["height"], dtype=np.float64),
        normal=normal,
        frames=frames,
        zone_ids=tuple(z.id for z in site.zones),
        spacing_m=float(spacing_m),
    )
