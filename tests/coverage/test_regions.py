"""Coverage regions R_t against the coverage test itself.

Property: for thousands of random positions, inside R_t => the coverage test accepts the pair, and an accepted pair
farther than ``region_tolerance_m`` from R_t's boundary => inside R_t. Sites: a convex room, an L (non-convex), a room
with a free-standing block (a hole), and an outside zone with an obstacle; horizontal and 3-D incidence.
"""

from __future__ import annotations

import numpy as np
import pytest

from planner.coverage.matrix import ZoneSideBlockers, build_coverage
from planner.coverage.regions import coverage_regions, region_tolerance_m
from planner.coverage.targets import make_targets
from planner.coverage.visibility import SightLimits
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import Obstacle, ScanSide, Site, Zone
from tests.coverage.region_property import assert_regions_match

L_SHAPE = ((0, 0), (12, 0), (12, 5), (5, 5), (5, 10), (0, 10))
SITES = {
    "convex": Site("convex", (Zone("R", ScanSide.INSIDE, ((0, 0), (10, 0), (10, 4), (0, 4)), (3,) * 4),)),
    "L": Site("L", (Zone("L", ScanSide.INSIDE, L_SHAPE, (3,) * 6),)),
    "holed": Site(
        "holed",
        (
            Zone(
                "H",
                ScanSide.INSIDE,
                ((0, 0), (20, 0), (20, 12), (0, 12)),
                (4,) * 4,
                holes=(((8, 5), (8, 7), (11, 7), (11, 5)),),
                hole_heights_m=((3,) * 4,),
            ),
        ),
    ),
    "outside+obstacle": Site(
        "out",
        (Zone("O", ScanSide.OUTSIDE, L_SHAPE, (3,) * 6),),
        obstacles=(Obstacle("column", ((15, 2), (16, 2), (16, 3), (15, 3)), 2.0),),
    ),
}


@pytest.mark.parametrize("incidence_3d", [False, pytest.param(True, marks=pytest.mark.slow)])
@pytest.mark.parametrize("name", list(SITES))
def test_region_agrees_with_the_coverage_test(name: str, incidence_3d: bool) -> None:
    site = SITES[name]
    limits = SightLimits(30.0, 68.0, 1.5, incidence_3d=incidence_3d)
    targets = make_targets(site, 1.0)
    regions = coverage_regions(site, targets, limits)
    rng = np.random.default_rng(7)
    lo = np.min([z.polygon.bounds[:2] for z in site.zones], axis=0) - 5
    hi = np.max([z.polygon.bounds[2:] for z in site.zones], axis=0) + 5
    pts = rng.uniform(lo, hi, size=(1500, 2))
    seen_inside, _ = assert_regions_match(
        site, targets, limits, regions, pts, region_tolerance_m(limits, site.parameters.min_standoff_m)
    )
    assert seen_inside > 1000  # the property was exercised, not vacuous


def test_zone_side_blockers_change_no_pair(monkeypatch: pytest.MonkeyPatch) -> None:
    """Testing views against only the blockers of the piece's zone-side gives the same matrix as against all."""
    rooms = [
        Zone(f"R{k}", ScanSide.INSIDE, ((6 * k, 0), (6 * k + 5, 0), (6 * k + 5, 4), (6 * k, 4)), (3,) * 4)
        for k in range(3)
    ]
    outline = Zone("out", ScanSide.OUTSIDE, ((-0.5, -0.5), (17.5, -0.5), (17.5, 4.5), (-0.5, 4.5)), (3,) * 4)
    site = Site("row", (*rooms, outline), obstacles=(Obstacle("c", ((2, 1.5), (2.5, 1.5), (2.5, 2), (2, 2)), 2.0),))
    targets = make_targets(site, 1.0)
    limits = SightLimits(40.0, 75.0, 1.5)
    rng = np.random.default_rng(3)
    pts = rng.uniform((-10, -10), (28, 15), size=(800, 2))
    cands = [
        Candidate(f"p{i}", "R0", ScanSide.INSIDE, "site", float(x), float(y), CandidateKind.GRID)
        for i, (x, y) in enumerate(pts)
    ]
    fast = build_coverage(site, cands, targets, limits).by_candidate
    monkeypatch.setattr(ZoneSideBlockers, "of", lambda self, zone_index, inside: self.all)
    full = build_coverage(site, cands, targets, limits).by_candidate
    assert fast.nnz > 0 and (fast != full).nnz == 0
