"""The sight stage of a coverage region takes away only the shadows that meet the region, unioned: the same point set as
taking away the union of every shadow of the blockers near the piece (the way it was drawn before), up to rounding.

Random small rooms (rectangle, L, T, U, some with a block, random range and theta_max, anywhere in the plane), every
piece: the region as drawn now against the stand-stage region minus the union of all the piece's shadows. Derandomised.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from planner.coverage.regions import coverage_regions, frame_space, region_stages
from planner.coverage.shadows import SNAP_GRID_M, piece_shadows, unshadowed
from planner.coverage.targets import make_targets
from planner.coverage.visibility import SightLimits
from planner.site.model import Site
from tests.bounds.plane_cases import rooms

QUICK = settings(
    deadline=None,
    derandomize=True,
    database=None,
    max_examples=25,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


def all_shadows_away(region: shapely.Geometry, shadows: list[shapely.Geometry]) -> shapely.Geometry:
    """The former sight stage: ``region`` minus the union of every shadow (snap-rounded where GEOS fails)."""
    if not shadows:
        return region
    try:
        return region.difference(shapely.union_all(shadows))
    except shapely.errors.GEOSException:
        union = shapely.union_all(shadows, grid_size=SNAP_GRID_M)
        return shapely.difference(region, union, grid_size=SNAP_GRID_M)


def assert_same_set(a: shapely.Geometry, b: shapely.Geometry, what: str) -> None:
    """``a`` and ``b`` agree as point sets up to rounding (a snap-rounded side: the grid along the boundary)."""
    tol = 1e-9 + 2.0 * SNAP_GRID_M * (a.length + b.length)
    sym = float(shapely.symmetric_difference(a, b).area)
    assert sym <= tol, f"{what}: symmetric difference {sym:.3g} m2 > {tol:.3g}"


@pytest.mark.slow
@QUICK
@given(site=rooms(max_size_m=15.0), incidence_3d=st.booleans())
def test_region_equals_the_region_minus_every_shadow(site: Site, incidence_3d: bool) -> None:
    p = site.parameters
    limits = SightLimits(p.max_slant_range_m, p.theta_max_deg, 1.5, incidence_3d=incidence_3d)
    targets = make_targets(site, 1.0)
    space = frame_space(site, site.zones[0].frame, limits)
    regions = coverage_regions(site, targets, limits, None, {site.zones[0].frame: space})
    for t in range(len(targets)):
        stages = dict(region_stages(targets, t, limits, space))
        if "stand" not in stages or stages["stand"].is_empty:
            assert regions[t].is_empty
            continue
        k = stages.get("precision", stages["incidence"])
        before = all_shadows_away(stages["stand"], piece_shadows(targets, t, k, space.blockers, space.far_m, False))
        assert_same_set(regions[t], before, targets.label(t))


@QUICK
@given(
    seed=st.integers(0, 2**31 - 1),
    n=st.integers(0, 40),
    spread=st.floats(1.0, 1e3),
)
def test_unshadowed_equals_the_difference_with_the_whole_union(seed: int, n: int, spread: float) -> None:
    rng = np.random.default_rng(seed)
    region = shapely.Polygon(rng.uniform(0, 10, (12, 2))).convex_hull
    if n:  # triangles near and far, some crossing the region
        tri = rng.uniform(-spread, spread, (n, 3, 2)) + rng.uniform(0, 10, (n, 1, 2))
        shadows = [g for g in shapely.polygons(tri) if g.is_valid and g.area > 0]
    else:
        shadows = []
    assert_same_set(unshadowed(region, shadows), all_shadows_away(region, shadows), f"seed {seed}")
