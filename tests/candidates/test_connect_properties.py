"""Outside zones against brute force (slow, hypothesis, few examples): small random blocks (rectangles and L shapes,
turned) scanned from outside within a boundary 3-5 m around, theta_max 46-80 deg (about the outside corner's 45 deg),
the default overlap rule. The oracle is the exact connected optimum over a 0.5-m grid of positions between the block
and the boundary (CP-SAT with the registration cuts, over the grid alone), its stations verified by the planner's own
verify. Then:

- where the grid has a connected plan, the planner never refuses over the plane (a refusal over the plane claims that no
  positions at all can be linked, the grid's included), its bounds over the plane are never above the grid optimum, and
  its plan has no more stations or says its scope is the pool;
- where the planner refuses over the plane, the grid has no connected plan either.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from planner.core.errors import InfeasibleError
from planner.coverage.matrix import build_coverage
from planner.coverage.overlap import OverlapRule
from planner.coverage.sight import Sight
from planner.coverage.targets import make_targets
from planner.engine import plan_site
from planner.plan import PlanOptions, plan_limits
from planner.plan.verify import verify_stations
from planner.site.model import ScanSide, Site, Zone
from planner.site.params import Parameters
from planner.site.validate import validate_site
from planner.solve.instance import cover_instance
from planner.solve.milp import MilpOptions, solve
from planner.solve.result import Status
from tests.bounds.plane_cases import _place, as_candidates, outline

FEW = settings(
    deadline=None,
    derandomize=True,
    database=None,
    max_examples=8,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)
SHARE = 0.3
STEP_M = 0.5


def block(kind: str, w: float, h: float, margin: float, theta: float, angle: float) -> Site:
    xy = _place(outline(kind, w, h, 0.5, 0.5), angle, (0.0, 0.0))
    zone = Zone("B", ScanSide.OUTSIDE, xy, (3.0,) * len(xy))
    box = shapely.Polygon(xy).buffer(margin, join_style="mitre")
    boundary = tuple((float(x), float(y)) for x, y in list(box.exterior.coords)[:-1])
    params = Parameters(theta_max_deg=theta, overlap=SHARE)
    return Site(f"{kind} {w:.1f} x {h:.1f}", (zone,), parameters=params, boundary=boundary)


def grid_connected_optimum(site: Site, options: PlanOptions) -> float:
    """The exact connected optimum over a 0.5-m grid between the block and its boundary (a station's stand-off kept by
    the coverage test), its stations verified; inf where some piece is seen from no grid position, -inf where the
    grid has no connected plan."""
    validation = validate_site(site)
    limits = plan_limits(validation, options)
    inner = shapely.Polygon(site.zones[0].vertices)
    outer = shapely.Polygon(site.boundary)
    lo, hi = np.asarray(outer.bounds[:2]), np.asarray(outer.bounds[2:])
    gx, gy = np.meshgrid(np.arange(lo[0], hi[0], STEP_M), np.arange(lo[1], hi[1], STEP_M))
    pts = np.column_stack([gx.ravel(), gy.ravel()])
    keep = shapely.contains_xy(outer, pts[:, 0], pts[:, 1]) & ~shapely.contains_xy(inner, pts[:, 0], pts[:, 1])
    grid = as_candidates(site.zones[0], pts[keep])
    problem = build_coverage(site, grid, make_targets(site, options.target_spacing_m), limits)
    if np.any(problem.by_target.getnnz(axis=1) == 0):
        return math.inf
    result = solve(cover_instance(problem), MilpOptions(overlap=OverlapRule(SHARE), time_limit_s=120.0))
    if result.status is Status.INFEASIBLE:
        return -math.inf
    assert result.status is Status.OPTIMAL, result.status
    sight = Sight(site=site, limits=limits, scanner=validation.scanner)
    report = verify_stations(sight, [grid[i] for i in result.selected], options.verify_spacing_m)
    assert report.complete, report.summary()
    return float(result.objective)


@pytest.mark.slow
@settings(FEW)
@given(
    kind=st.sampled_from(["rect", "rect", "L"]),
    w=st.floats(3.0, 9.0),
    h=st.floats(3.0, 6.0),
    margin=st.floats(3.0, 5.0),
    theta=st.floats(46.0, 80.0),
    angle=st.floats(0.0, 90.0),
)
def test_outside_blocks_against_the_grid_optimum(kind, w, h, margin, theta, angle):
    if kind != "rect":
        w, h = max(w, 5.0), max(h, 5.0)
    site = block(kind, w, h, margin, theta, angle)
    options = PlanOptions(precision=False)
    optimum = grid_connected_optimum(site, options)
    if optimum == math.inf:
        return  # a piece no grid position sees: nothing to compare
    try:
        plan = plan_site(site, options)
    except InfeasibleError as err:
        over_plane = "over the plane" in err.message
        assert not (over_plane and math.isfinite(optimum)), (err.message, optimum)
        return
    info = plan.result.info
    assert plan.verification.complete and plan.connected
    if math.isfinite(optimum):
        assert info["plane_bound"] <= optimum
        conn = info.get("connected_plane_bound")
        assert conn is None or conn <= optimum, (conn, optimum)
        assert len(plan.stations) <= optimum or info["bound_scope"] == "pool", (len(plan.stations), optimum)
