"""A wall edge that ends at a piece's end, up to the last bit of a coordinate, shadows nothing of the room.

building27, room R16 (5.55 x 2.87 m): the piece of wall 3 at 4.62-5.55 m ends at x = 0.29999999999999982, the next wall
starts at x = 0.3; the 2e-16 m vector between them once gave a shadow over the whole room, so R_t was empty although the
room's centre (3.075, 10.155) sees the piece (and the whole room: incidence at most atan(2.775 / 1.435) = 62.7 deg < 68
deg)."""

from __future__ import annotations

import numpy as np
import shapely

from planner.candidates.from_regions import common_region
from planner.coverage.regions import coverage_regions
from planner.coverage.targets import make_targets
from planner.coverage.visibility import sight_limits
from planner.io import load_site
from planner.site.validate import validate_site
from tests.conftest import INSTANCES


def test_corner_piece_region_is_not_swallowed_by_a_rounding_shadow() -> None:
    site = load_site(INSTANCES / "building27.json")
    limits = sight_limits(validate_site(site), False, True)
    targets = make_targets(site, 1.0)
    zi = next(i for i, z in enumerate(site.zones) if z.id == "R16")
    pieces = np.flatnonzero((targets.zone == zi) & (targets.side == 0))
    regions = coverage_regions(site, targets, limits, pieces)
    centre = shapely.Point(3.075, 10.155)
    assert all(regions[int(p)].contains(centre) for p in pieces)
    assert common_region(site, targets, pieces, limits, {}, {}).contains(centre)
