"""Candidates from coverage regions: one station for a whole zone-side wherever one exists.

For every zone-side, the intersection of the coverage regions of all its pieces is the set of positions from which one
station covers the whole zone-side. It is computed exactly (up to the regions' inner approximation of range discs) and,
when not empty, its pole of inaccessibility (the point farthest from its boundary, so that the coverage test is not
decided by rounding) is a candidate. Found by geometry, never by sampling.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.ops import polylabel

from planner.candidates.closed_form import side_candidate
from planner.coverage.regions import FrameSpace, coverage_regions
from planner.coverage.targets import SIDE_CODE, Targets
from planner.coverage.visibility import SightLimits
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import Site

#: the polylabel tolerance, as a share of the common part's size
POLE_TOLERANCE = 1e-3
#: regions drawn ahead at the first piece not drawn yet (a side whose common part is empty shows it after a few)
FIRST_BATCH = 8


def spread_order(n: int) -> np.ndarray:
    """0..n-1 in an order that jumps around the zone (golden-ratio stride), so that opposite walls meet early and an
    empty intersection shows after a few pieces."""
    return np.argsort((np.arange(n) * 0.6180339887498949) % 1.0, kind="stable")


def common_region(
    site: Site,
    targets: Targets,
    pieces: Sequence[int] | NDArray[np.integer],
    limits: SightLimits,
    spaces: dict[str, FrameSpace],
    cache: dict[int, shapely.Geometry],
) -> shapely.Geometry:
    """Intersection of the coverage regions of ``pieces`` (stops as soon as it is empty). Regions not in ``cache`` are
    drawn ahead in batches (:data:`FIRST_BATCH` pieces, then twice as many each time), which :func:`coverage_regions`
    draws together; the intersection still takes them one at a time in the spread order."""
    common: shapely.Geometry | None = None
    order = [int(t) for t in np.asarray(pieces)[spread_order(len(pieces))]]
    batch = FIRST_BATCH
    for i, t in enumerate(order):
        if t not in cache:
            cache.update(
                coverage_regions(site, targets, limits, [u for u in order[i : i + batch] if u not in cache], spaces)
            )
            batch *= 2
        common = cache[t] if common is None else common.intersection(cache[t])
        if common.is_empty:
            break
    return common if common is not None else shapely.Polygon()


def largest_part_pole(region: shapely.Geometry, min_tolerance_m: float = 1e-6) -> shapely.Point:
    """The pole of inaccessibility (the point farthest from the boundary) of the largest part of ``region``, found to
    ``POLE_TOLERANCE`` of its size (at least ``min_tolerance_m``)."""
    part = max(shapely.get_parts(region), key=lambda g: g.area)
    return polylabel(part, tolerance=max(POLE_TOLERANCE * float(np.sqrt(part.area)), min_tolerance_m))


def whole_side_candidates(
    site: Site,
    targets: Targets,
    limits: SightLimits,
    spaces: dict[str, FrameSpace] | None = None,
    cache: dict[int, shapely.Geometry] | None = None,
) -> list[Candidate]:
    """One candidate per zone-side that a single station can cover, at the pole of the common region."""
    spaces = {} if spaces is None else spaces
    cache = {} if cache is None else cache
    out = []
    for zi, zone in enumerate(site.zones):
        for side in zone.scan_side.sides:
            pieces = np.flatnonzero((targets.zone == zi) & (targets.side == SIDE_CODE[side]))
            if pieces.size == 0:
                continue
            common = common_region(site, targets, pieces, limits, spaces, cache)
            if common.is_empty or common.area <= 0:
                continue
            p = largest_part_pole(common)
            out.append(side_candidate(zone.id, side, zone.frame, "R", float(p.x), float(p.y), CandidateKind.REGION))
    return out
