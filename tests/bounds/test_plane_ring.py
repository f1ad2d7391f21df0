"""The connected plane bound (planner.bounds.plane_ring): its parts against brute force, and the issue's case.

- ``ring.cyclic_arcs`` (vectorised) agrees with the widest-gap rule written as a loop, on random rows.
- ``undominated`` (a table of the ring's arcs, O(n^2)) keeps exactly the triples no other holds (pairwise).
- The bound never passes the connected optimum over a 0.5-m grid of positions (the brute-force oracle: the exact
  connected MILP on that pool), on random blocks scanned from outside and rooms from inside, any overlap share: the
  bound claims every connected plan, stations anywhere, so also those on the grid.
- Polygon B: 6 stations, proven over the plane (the plain cover's plane bound is 5; the outside ring walk 5).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import planner
from planner.bounds.connected_result import ConnectedPlaneBound
from planner.bounds.plane_patches import undominated
from planner.bounds.plane_ring import connected_plane_bound
from planner.coverage.matrix import build_coverage
from planner.coverage.targets import make_targets
from planner.engine import plan_site
from planner.plan import PlanOptions, coverage_problem, plan_limits, resolve
from planner.site.model import ScanSide, Site, Zone
from planner.site.params import Parameters
from planner.site.validate import validate_site
from planner.solve.instance import cover_instance
from planner.solve.milp import MilpOptions, solve
from planner.solve.ring import cyclic_arcs
from tests.bounds.plane_cases import _place, as_candidates, outline, positions
from tests.conftest import INSTANCES

QUICK = settings(
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large],
)


def _loop_arc(cols: list[int], n: int) -> tuple[int, int]:
    """The smallest cyclic arc of ``cols`` written plainly: leave out the first widest gap between neighbours."""
    cols = sorted(cols)
    gaps = [(cols[(k + 1) % len(cols)] - cols[k]) % n or n for k in range(len(cols))]
    k = gaps.index(max(gaps))
    start = cols[(k + 1) % len(cols)]
    return start, cols[k] + (n if cols[k] < start else 0)


@settings(QUICK, max_examples=200)
@given(n=st.integers(1, 30), rows=st.lists(st.sets(st.integers(0, 29), min_size=1), min_size=1, max_size=20))
def test_cyclic_arcs_agree_with_the_loop(n: int, rows: list[set[int]]) -> None:
    rows = [{c % n for c in r} for r in rows]
    m = sp.csr_matrix(
        (
            np.ones(sum(map(len, rows)), dtype=bool),
            (np.repeat(np.arange(len(rows)), [len(r) for r in rows]), [c for r in rows for c in sorted(r)]),
        ),
        shape=(len(rows), n),
    )
    start, end = cyclic_arcs(m)
    assert list(zip(start.tolist(), end.tolist())) == [_loop_arc(list(r), n) for r in rows]


# the full-strength run is in the slow tier, marked here rather than by a decorator: hypothesis derandomises
# a property by its source, decorators included, so a marker line would change the cases it has always run
test_cyclic_arcs_agree_with_the_loop = pytest.mark.slow(test_cyclic_arcs_agree_with_the_loop)


@settings(QUICK, max_examples=50)
@given(n=st.integers(1, 30), rows=st.lists(st.sets(st.integers(0, 29), min_size=1), min_size=1, max_size=20))
def test_cyclic_arcs_agree_with_the_loop_on_fewer_cases(n, rows):
    # the quick twin: the body of the test above on 50 cases (the test above runs 200, in the slow tier)
    test_cyclic_arcs_agree_with_the_loop.hypothesis.inner_test(n=n, rows=rows)


def _holds(s1: int, e1: int, s2: int, e2: int, n: int) -> bool:
    """Arc [s1, e1] holds arc [s2, e2] as sets of pieces of the ring of n (ends inclusive, e may pass n)."""
    a = {k % n for k in range(s1, e1 + 1)}
    return {k % n for k in range(s2, e2 + 1)} <= a


@settings(QUICK, max_examples=300)
@given(
    n=st.integers(2, 12),
    items=st.lists(st.tuples(st.integers(0, 11), st.integers(0, 11), st.integers(0, 4)), min_size=1, max_size=25),
)
def test_undominated_is_the_pairwise_definition(n: int, items: list[tuple[int, int, int]]) -> None:
    start = np.array([s % n for s, _, _ in items])
    span = np.array([k % n for _, k, _ in items])
    low = np.array([float(w) for _, _, w in items])
    kept = set(undominated(start, span, low, n).tolist())
    for p in range(len(items)):
        held = [
            m
            for m in range(len(items))
            if m != p and _holds(start[m], start[m] + span[m], start[p], start[p] + span[p], n) and low[m] <= low[p]
        ]
        # p goes when another holds it, except the first of equal sets with equal low (one of them stays)
        same = [
            m
            for m in held
            if _holds(start[p], start[p] + span[p], start[m], start[m] + span[m], n) and low[m] == low[p]
        ]
        strict = [m for m in held if m not in same]
        expect = not strict and all(m > p for m in same)
        assert (p in kept) == expect, (p, held, kept)


# the full-strength run is in the slow tier, marked here rather than by a decorator: hypothesis derandomises
# a property by its source, decorators included, so a marker line would change the cases it has always run
test_undominated_is_the_pairwise_definition = pytest.mark.slow(test_undominated_is_the_pairwise_definition)


@settings(QUICK, max_examples=75)
@given(
    n=st.integers(2, 12),
    items=st.lists(st.tuples(st.integers(0, 11), st.integers(0, 11), st.integers(0, 4)), min_size=1, max_size=25),
)
def test_undominated_is_the_pairwise_definition_on_fewer_cases(n, items):
    # the quick twin: the body of the test above on 75 cases (the test above runs 300, in the slow tier)
    test_undominated_is_the_pairwise_definition.hypothesis.inner_test(n=n, items=items)


def block_site(
    kind: str,
    w: float,
    h: float,
    a: float,
    b: float,
    theta: float,
    reach: float,
    share: float,
    inside: bool,
    angle: float,
    shift: tuple[float, float],
) -> Site:
    xy = outline(kind, w, h, a, b)
    zone = Zone("B", ScanSide.INSIDE if inside else ScanSide.OUTSIDE, _place(xy, angle, shift), (3.0,) * len(xy))
    return Site(
        f"{kind} {w:.1f} x {h:.1f}",
        (zone,),
        parameters=Parameters(theta_max_deg=theta, max_slant_range_m=reach, overlap=share),
    )


def _ring_positions(site: Site, step: float, reach: float) -> np.ndarray:
    """A grid of step ``step`` over the block's box grown by the horizontal reach, outside the block."""
    import shapely

    v = np.asarray(site.zones[0].vertices)
    lo, hi = v.min(axis=0) - reach, v.max(axis=0) + reach
    gx, gy = np.meshgrid(np.arange(lo[0], hi[0], step), np.arange(lo[1], hi[1], step))
    pts = np.column_stack([gx.ravel(), gy.ravel()])
    return pts[~shapely.contains_xy(shapely.Polygon(v), pts[:, 0], pts[:, 1])]


def connected_optimum(site: Site, options: PlanOptions, share: float) -> tuple[float, object]:
    """The exact connected optimum over a 0.5-m grid (brute force), and the problem it was solved on."""
    limits = plan_limits(validate_site(site), options)
    targets = make_targets(site, options.target_spacing_m)
    zone = site.zones[0]
    grid = (
        positions(zone, 0.5)
        if zone.scan_side is ScanSide.INSIDE
        else as_candidates(zone, _ring_positions(site, 0.5, math.sqrt(max(limits.effective_range_m**2 - 9.0, 1.0))))
    )
    problem = build_coverage(site, grid, targets, limits)
    if np.any(problem.by_target.getnnz(axis=1) == 0):
        return math.inf, problem
    result = solve(cover_instance(problem), MilpOptions(overlap=planner.OverlapRule(share), time_limit_s=60.0))
    return (float(result.objective) if result.status.value == "optimal" else -math.inf), problem


@pytest.mark.slow
@settings(QUICK, max_examples=60)
@given(
    kind=st.sampled_from(["rect", "rect", "L", "U"]),
    w=st.floats(1.5, 5.0),
    h=st.floats(1.5, 5.0),
    a=st.floats(0.3, 0.7),
    b=st.floats(0.3, 0.7),
    theta=st.floats(40.0, 80.0),
    reach=st.floats(6.0, 12.0),
    share=st.floats(0.1, 0.6),
    inside=st.sampled_from([False, False, True]),
    angle=st.floats(0, 360),
    shift=st.tuples(st.floats(-1e3, 1e3), st.floats(-1e3, 1e3)),
)
def test_bound_at_most_the_connected_optimum_over_a_grid(kind, w, h, a, b, theta, reach, share, inside, angle, shift):
    if kind != "rect":
        w, h = max(w, 5.0), max(h, 5.0)
    site = block_site(kind, w, h, a, b, theta, reach, share, inside, angle, shift)
    checked = bound_against_grid(site, share, work_patches=10**9)
    if checked is not None:
        cb, optimum = checked
        assert cb.bound is not None and cb.bound <= optimum, (cb.summary(), optimum)


def bound_against_grid(site: Site, share: float, **kwargs: int) -> tuple[ConnectedPlaneBound, float] | None:
    """The connected plane bound of ``site`` (``kwargs`` to :func:`connected_plane_bound`), asked for one more station
    than the exact connected optimum over a 0.5-m grid (a sound bound never gets there), and that optimum; None when
    some piece is seen from no grid position (nothing to compare)."""
    options = PlanOptions(method="milp", precision=False, milp=MilpOptions(overlap=planner.OverlapRule(share)))
    optimum, _ = connected_optimum(site, options, share)
    if not math.isfinite(optimum):
        return None
    problem, _unseen, _ = coverage_problem(resolve(site, options))
    limits = plan_limits(validate_site(site), options)
    t = problem.targets
    counts = {int(k): int(optimum) + 1 for k in np.unique(t.zone.astype(np.int64) * 2 + t.side)}
    return connected_plane_bound(site, problem, limits, share, np.zeros(len(t)), counts, **kwargs), optimum


@pytest.mark.slow
def test_polygon_b_is_proven_over_the_plane():
    # plain cover: 1 inside + 4 outside (plane bound 5); connected: the outside ring walk needs 5, so 1 + 5 = 6
    plan = plan_site(planner.load_site(INSTANCES / "polygon_b.json"), PlanOptions(method="milp"))
    info = plan.result.info
    assert len(plan.stations) == 6 and info["plane_bound"] == 5
    assert info["connected_plane_bound"] == 6 and info["bound_scope"] == "plane"
    sides = {s["zone_side"]: s for s in info["connected_plane"]["zone_sides"]}
    assert sides["B/outside"]["ring"] == 5 and sides["B/inside"]["farley"] == 1.0
