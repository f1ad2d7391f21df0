"""Coverage regions follow the rules: the stand-off from walls and obstacles and the incidence-dependent view error e(S,
theta) (single precision, table 2.3 / Soudarissanane models) are in R_t as in the coverage test.

Property as in test_regions.py: inside R_t => the coverage test accepts the pair; an accepted pair farther than
``region_tolerance_m`` from R_t's boundary => inside R_t.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import shapely

from planner.coverage.matrix import build_coverage
from planner.coverage.regions import coverage_regions, region_tolerance_m, regions_apply
from planner.coverage.targets import make_targets
from planner.coverage.visibility import PrecisionRule, SightLimits
from planner.instrument.accuracy import ErrorBudget, RangeAngleSigma, max_slant_range_m, sigma_instr_m
from planner.site.model import Obstacle, ScanSide, Site, Zone
from tests.coverage.region_property import assert_regions_match, probe_candidates

P30 = RangeAngleSigma(range_sigma_const_m=0.0012, range_sigma_ppm=10.0, angle_sigma_arcsec=8.0)
BUDGET = ErrorBudget(0.0005, 0.0005, 0.0005)
SIGMA_REQ_M = 0.003  # 3 mm: (3.1) gives about 60 m at normal incidence, the table model about 40 m at 60 deg
L_SHAPE = ((0, 0), (60, 0), (60, 25), (25, 25), (25, 50), (0, 50))


def _site(name: str, standoff: float) -> Site:
    if name == "convex":
        site = Site("convex", (Zone("R", ScanSide.INSIDE, ((0, 0), (70, 0), (70, 45), (0, 45)), (6,) * 4),))
    else:
        site = Site(
            "L",
            (Zone("L", ScanSide.OUTSIDE, L_SHAPE, (6,) * 6),),
            obstacles=(Obstacle("column", ((70, 10), (72, 10), (72, 12), (70, 12)), 3.0),),
        )
    return replace(site, parameters=replace(site.parameters, min_standoff_m=standoff))


def _limits(model: str) -> SightLimits:
    s_prec = max_slant_range_m(P30, sigma_instr_m(SIGMA_REQ_M, BUDGET))
    return SightLimits(
        100.0, 79.0, 1.5, precision_range_m=s_prec, precision=PrecisionRule(P30, BUDGET, SIGMA_REQ_M, model)
    )


@pytest.mark.parametrize("model", [pytest.param("table", marks=pytest.mark.slow), "soudarissanane"])
@pytest.mark.parametrize("name,standoff", [("convex", 0.4), pytest.param("L", 1.5, marks=pytest.mark.slow)])
def test_region_with_view_error_and_standoff_agrees_with_the_coverage_test(
    name: str, standoff: float, model: str
) -> None:
    site, limits = _site(name, standoff), _limits(model)
    assert limits.per_pair_precision and regions_apply(limits)
    targets = make_targets(site, 2.0)
    regions = coverage_regions(site, targets, limits)
    rng = np.random.default_rng(11)
    lo = np.min([z.polygon.bounds[:2] for z in site.zones], axis=0) - 30
    hi = np.max([z.polygon.bounds[2:] for z in site.zones], axis=0) + 30
    pts = rng.uniform(lo, hi, size=(1500, 2))
    # and points just off the walls, where the stand-off decides
    edge = rng.uniform(0.0, 1.0, size=400)
    pts = np.vstack([pts, np.column_stack([edge * 60.0, rng.uniform(-2 * standoff, 2 * standoff, 400)])])
    seen_inside, covered = assert_regions_match(
        site, targets, limits, regions, pts, region_tolerance_m(limits, standoff)
    )
    plain = build_coverage(site, probe_candidates(site, pts), targets, replace(limits, precision=None)).by_target
    refused_by_error = plain.nnz - covered.nnz  # pairs the range rule allowed and the view error refused
    assert seen_inside > 1000
    assert refused_by_error > 100  # the incidence-dependent error did refuse views (range (3.1) alone allowed them)


def test_no_region_point_within_the_standoff() -> None:
    site = _site("L", 1.5)
    targets = make_targets(site, 2.0)
    regions = coverage_regions(site, targets, SightLimits(100.0, 70.0, 1.5))
    walls = shapely.union_all([site.zones[0].polygon.boundary, shapely.Polygon(site.obstacles[0].vertices).boundary])
    near = walls.buffer(1.5 - 1e-6)
    assert all(r.is_empty or r.intersection(near).area < 1e-9 for r in regions.values())


def test_3d_incidence_with_a_view_error_model_has_no_regions() -> None:
    assert not regions_apply(replace(_limits("table"), incidence_3d=True))
    assert regions_apply(replace(_limits("none"), incidence_3d=True))
