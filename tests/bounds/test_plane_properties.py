"""Claims that hold for every input, checked against brute force on random small sites.

(a) "Unseeable" is never said of a piece that some position sees: when pieces are refused, a dense
    grid of positions (0.25 m) covers none of them.
(b) The plane bound is sound: the cover LP over the pool grown by pricing *and* a few hundred more
    positions (random, and the vertices and edge midpoints of the regions) stays at or above the plane
    LP bound, and no sampled position weighs more than the heaviest outer-region weight w*.
(c) On tiny rooms, the plane bound is at most the optimum of a brute-force cover over a 0.1-m grid plus
    every point of the closed arrangement of all the regions (faces, edges, vertices).
(d) A corridor gets at most as many stations as the centre-line construction: stations on the centre
    line, w/2 tan(theta_max) of wall seen either side, spaced by 2 w/2 tan(theta_max) - 1 m (so that every
    1-m piece lies whole in one window), the first and last one far enough in to see the end walls.

Derandomised (the same examples every run). ``scripts/checks/check_plane_properties.py`` runs more of them, with
corridors up to 300 m.
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
import scipy.sparse as sp
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from planner.bounds.plane import price_plane
from planner.core.errors import InfeasibleError
from planner.coverage.arrangement import heaviest_points
from planner.coverage.matrix import build_coverage
from planner.coverage.regions import coverage_regions
from planner.coverage.targets import Targets, make_targets
from planner.engine import plan_site
from planner.plan import PlanOptions, coverage_problem, plan_limits, resolve
from planner.site.model import ScanSide, Site, Zone
from planner.site.params import Parameters
from planner.site.validate import validate_site
from planner.solve.milp import MilpOptions
from planner.solve.pricing import cover_lp
from tests.bounds.plane_cases import as_candidates, min_cover, positions, rooms

QUICK = settings(
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large],
)
PLAIN = PlanOptions(method="milp", milp=MilpOptions(overlap=None, time_limit_s=30.0))
#: examples per property in CI (2,000 in all); ``scripts/checks/check_plane_properties.py`` scales them up
SCALE = float(os.environ.get("PLANNER_PROPERTY_SCALE", "1"))
EXAMPLES = {k: max(1, int(n * SCALE)) for k, n in {"a": 1100, "b": 300, "c": 300, "d": 300}.items()}
#: corridors up to this long (m); the script's long run goes to 300 m
CORRIDOR_M = float(os.environ.get("PLANNER_PROPERTY_CORRIDOR_M", "60"))


@pytest.mark.slow
@settings(QUICK, max_examples=EXAMPLES["a"])
@given(site=rooms(), precision=st.booleans())
def test_a_no_piece_refused_that_a_position_sees(site: Site, precision: bool) -> None:
    options = PlanOptions(method="milp", precision=precision, milp=MilpOptions(overlap=None))
    problem, unseen, reasons = coverage_problem(resolve(site, options))
    if unseen.size == 0:
        return
    assert set(map(int, unseen)) <= set(reasons), "every refused piece has a reason"
    dense = build_coverage(site, positions(site.zones[0], 0.25), problem.targets, problem.limits)
    seen = np.asarray(dense.by_target[unseen].sum(axis=1)).ravel()
    assert not seen.any(), f"refused pieces seen from the dense grid: {unseen[seen > 0].tolist()}"


@pytest.mark.slow
@settings(QUICK, max_examples=EXAMPLES["b"])
@given(site=rooms(max_size_m=12.0), seed=st.integers(0, 2**31 - 1))
def test_b_no_sampled_position_beats_the_plane_bound(site: Site, seed: int) -> None:
    options = PlanOptions(method="milp", precision=False, milp=MilpOptions(overlap=None))
    problem, unseen, _ = coverage_problem(resolve(site, options))
    if unseen.size:
        return
    limits = problem.limits
    grown, report = price_plane(site, problem, limits, time_limit_s=30.0)
    y = np.asarray(report.duals)
    rng = np.random.default_rng(seed)
    zone = site.zones[0]
    lo, hi = np.min(zone.vertices, axis=0), np.max(zone.vertices, axis=0)
    pts = [lo + rng.random((150, 2)) * (hi - lo)]
    regions = coverage_regions(site, problem.targets, limits, [int(t) for t in np.flatnonzero(y > 1e-9)])
    for g in regions.values():  # the corners and edge midpoints of the regions that carry weight
        ring = shapely.get_coordinates(shapely.boundary(g))
        if len(ring) > 1:
            step = max(1, len(ring) // 8)
            pts += [ring[::step], ((ring[:-1] + ring[1:]) / 2)[::step]]
    sample = build_coverage(site, as_candidates(zone, np.vstack(pts)), problem.targets, limits)
    weight = np.asarray(sample.by_candidate.astype(float) @ y).ravel()
    assert weight.max(initial=0.0) <= max(1.0, report.heaviest_weight) + 1e-7
    both = sample.by_candidate.shape[0] and cover_lp(sp.vstack([grown.by_candidate, sample.by_candidate]).T.tocsr())
    if both:
        assert both.value >= report.plane_lp_bound - 1e-6  # the plane bound holds for the pool + the samples


@pytest.mark.slow
@settings(QUICK, max_examples=EXAMPLES["c"])
@given(site=rooms(max_size_m=6.0, blocks=False))
def test_c_plane_bound_at_most_brute_force_optimum(site: Site) -> None:
    options = PlanOptions(method="milp", precision=False, milp=MilpOptions(overlap=None, time_limit_s=30.0))
    try:
        plan = plan_site(site, options)
    except InfeasibleError:
        return
    limits = plan_limits(validate_site(site), options)
    t = plan.problem_size["targets"]
    zone = site.zones[0]
    targets = make_targets(site, options.target_spacing_m)
    assert len(targets) == t
    regions = coverage_regions(site, targets, limits)
    cells = heaviest_points(list(regions.values()), np.ones(len(regions)), -1.0, 10**6)
    pts = np.array([(c.x, c.y) for c in cells]).reshape(-1, 2)
    grid = positions(zone, 0.1)
    brute = build_coverage(site, grid + as_candidates(zone, pts, "V"), targets, limits)
    optimum = min_cover(brute.by_candidate)
    assert plan.result.info["plane_bound"] <= optimum
    assert len(plan.stations) >= plan.result.info["plane_bound"]


def corridor(width: float, length: float, theta: float, angle: float, shift: tuple[float, float]) -> Site:
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    xy = np.round(
        np.array([(0, 0), (length, 0), (length, width), (0, width)], float) @ np.array([[c, s], [-s, c]]) + shift, 9
    )
    zone = Zone("K", ScanSide.INSIDE, tuple(map(tuple, xy)), (3.0,) * 4)
    return Site("corridor", (zone,), parameters=Parameters(theta_max_deg=theta, max_slant_range_m=200.0, overlap=0.0))


def centre_line_plan(width: float, length: float, theta: float) -> np.ndarray:
    """x of the construction's stations along the centre line (see the module docstring)."""
    r = width / 2 * math.tan(math.radians(theta))  # wall seen either side of a centre-line station
    x0 = r - 0.01  # the first sees wall from 0 ...
    assert x0 >= width / 2 / math.tan(math.radians(theta)) + 0.01  # ... and its end wall's corners within theta
    if length - 2 * x0 <= 0:
        return np.array([length / 2])
    n = math.ceil((length - 2 * x0) / (2 * r - 1.02)) + 1
    return np.linspace(x0, length - x0, n)


@pytest.mark.slow
@settings(QUICK, max_examples=EXAMPLES["d"])
@given(
    width=st.floats(1.5, 15.0),
    length=st.floats(20.0, CORRIDOR_M),
    theta=st.floats(50.0, 85.0),
    angle=st.floats(0.0, 360.0),
    shift=st.tuples(st.floats(-1e3, 1e3), st.floats(-1e3, 1e3)),
)
def test_d_corridor_within_the_centre_line_construction(
    width: float, length: float, theta: float, angle: float, shift: tuple[float, float]
) -> None:
    check_corridor(width, length, theta, angle, shift)


def check_corridor(width: float, length: float, theta: float, angle: float, shift: tuple[float, float]) -> None:
    site = corridor(width, length, theta, angle, shift)
    options = PlanOptions(method="milp", precision=False, milp=MilpOptions(overlap=None, time_limit_s=60.0))
    xs = centre_line_plan(width, length, theta)
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    pts = np.column_stack([xs, np.full(len(xs), width / 2)]) @ np.array([[c, s], [-s, c]]) + shift
    plan = plan_site(site, options)
    built = build_coverage(
        site,
        as_candidates(site.zones[0], pts, "C"),
        plan_problem_targets(site, options),
        plan_limits(validate_site(site), options),
    )
    assert built.uncoverable().size == 0, "the construction covers every piece"
    assert len(plan.stations) <= len(xs)
    assert plan.result.status.value == "optimal"


def plan_problem_targets(site: Site, options: PlanOptions) -> Targets:
    return make_targets(site, options.target_spacing_m)


@pytest.mark.parametrize(
    ("width", "length", "theta"),
    [
        pytest.param(8.0, 200.0, 68.0, marks=pytest.mark.slow),
        pytest.param(1.5, 60.0, 50.0, marks=pytest.mark.slow),
        (15.0, 60.0, 85.0),
    ],
)
def test_d_cases_that_mattered(width: float, length: float, theta: float) -> None:
    # the corridor (refused before), the narrowest and the widest at the extremes of theta
    check_corridor(width, length, theta, 17.0, (3.0, -5.0))
