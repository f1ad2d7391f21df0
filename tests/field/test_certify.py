"""The certified visiting order: the CP-SAT model's bound in registration mode, against brute force."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.field.certify import BC_OPT, HK_EXACT, certify
from planner.field.order import order_length, registration_violations, solve_order
from tests.field.cpsat_model import cpsat_order


def brute_force(d, nbrs, parts, start_is_station, closed, registration):
    """The shortest order from node 0 over all permutations (keeping the rule in registration mode)."""
    n = len(d)
    best = math.inf
    for rest in itertools.permutations(range(1, n)):
        order = (0, *rest)
        if registration and registration_violations(order, nbrs, parts, start_is_station):
            continue
        best = min(best, order_length(d, order, closed))
    return best


def _line_case():
    # four nodes: 0 at (0, 0), 1 at (1, 0), 2 at (2, 0), 3 at (10, 0); the start is node 0.
    # relation: 0-2, 1-2, 0-3 (node 1 registers only on node 2)
    p = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [10.0, 0.0]])
    d = np.hypot(*(p[:, None] - p[None]).transpose(2, 0, 1))
    nbrs = [{2, 3}, {2}, {0, 1}, {0}]
    return d, nbrs, [0, 0, 0, 0]


def test_registration_forces_a_detour_and_the_bound_is_exact():
    d, nbrs, parts = _line_case()
    # shortest: 0 -> 1 -> 2 -> 3 = 1 + 1 + 8 = 10 m; it breaks the rule (1 before its only neighbour 2)
    assert registration_violations((0, 1, 2, 3), nbrs, parts, True) == [1]
    # orders keeping the rule: 0,2,1,3 = 2 + 1 + 9 = 12; 0,2,3,1 = 2 + 8 + 9 = 19; 0,3,2,1 = 10 + 8 + 1 = 19
    assert brute_force(d, nbrs, parts, True, False, True) == pytest.approx(12.0)
    r = solve_order(d, "registration", nbrs, parts, True, solution_limit=50)
    cert = certify(d, r, "registration", nbrs, parts, True, False)
    assert cert.result.order == (0, 2, 1, 3) and cert.result.length_m == pytest.approx(12.0)
    # the shortest route's bound (exact DP) is only 10 m; the branch-and-cut proves 12 m (12000 mm, integer here)
    assert dict(cert.bounds)[HK_EXACT] == pytest.approx(10.0)
    assert cert.method == BC_OPT and cert.bound_m == pytest.approx(12.0)
    assert cert.scope == "registration-order route"


def test_cpsat_improves_a_poor_hint():
    d, nbrs, parts = _line_case()
    # hint 0,3,2,1 (19 m, keeps the rule): CP-SAT still finds the 12 m order and proves it
    ex = cpsat_order(d, True, nbrs, parts, hint=(0, 3, 2, 1))
    assert ex.optimal and ex.order == (0, 2, 1, 3) and ex.length_m == pytest.approx(12.0)
    # shortest mode on the same nodes: 10 m, proven; closed tour 0,1,2,3,0 = 10 + 10 = 20 m
    assert cpsat_order(d, False, nbrs, parts).bound_m == pytest.approx(10.0)
    assert cpsat_order(d, False, nbrs, parts, closed=True).bound_m == pytest.approx(20.0)


@st.composite
def instances(draw):
    n = draw(st.integers(3, 7))
    pts = draw(st.lists(st.tuples(st.integers(0, 30), st.integers(0, 30)), min_size=n, max_size=n))
    p = np.array(pts, dtype=float)
    d = np.hypot(*(p[:, None] - p[None]).transpose(2, 0, 1))
    start_is_station = draw(st.booleans())
    # the relation: each station j >= 1 joined to one earlier station of its part (a spanning forest), plus extras;
    # a start that is no station (a point) stands in a part of its own and has no neighbours
    first = 0 if start_is_station else 1
    parts = [-1] * n
    nbrs: list[set[int]] = [set() for _ in range(n)]
    for j in range(first, n):
        if j == first or draw(st.integers(0, 4)) == 0:
            parts[j] = j  # opens a new part
            continue
        i = draw(st.integers(first, j - 1))
        parts[j] = parts[i]
        nbrs[i].add(j)
        nbrs[j].add(i)
    for i, j in itertools.combinations(range(first, n), 2):
        if parts[i] == parts[j] and draw(st.integers(0, 2)) == 0:
            nbrs[i].add(j)
            nbrs[j].add(i)
    closed = draw(st.booleans())
    return d, nbrs, parts, start_is_station, closed


@settings(max_examples=100, deadline=None, derandomize=True, database=None)
@given(instances(), st.sampled_from(["shortest", "registration"]))
def test_bound_below_brute_force_optimum_below_route(inst, mode):
    d, nbrs, parts, start_is_station, closed = inst
    reg = mode == "registration"
    opt = brute_force(d, nbrs, parts, start_is_station, closed, reg)
    r = solve_order(d, mode, nbrs, parts, start_is_station, closed, solution_limit=20)
    cert = certify(d, r, mode, nbrs, parts, start_is_station, closed)
    assert cert.bound_m <= opt + 1e-9 <= cert.result.length_m + 2e-9
    if reg:
        assert not registration_violations(cert.result.order, nbrs, parts, start_is_station)
    # on so few nodes the models are solved: the route and the bound are the optimum up to the cm rounding
    # of each of the at most n arcs (n <= 7: 7 cm)
    tol = len(d) * 0.01
    assert cert.result.length_m <= opt + tol and cert.bound_m >= opt - tol


@pytest.mark.slow
def test_branch_and_cut_closes_the_gap_on_a_random_plan():
    # 40 random points (the benchmark's kind: a square of side 10 sqrt(n) m, overlap within 16 m with
    # probability 1/2 plus the minimum spanning tree): the registration order is proven optimal, below
    # the routing answer, and the position model's bound (CP-SAT, a little work) stays below it
    from scipy.sparse.csgraph import minimum_spanning_tree

    from planner.field.scip_order import scip_order

    n = 40
    rng = np.random.default_rng(3)
    p = rng.uniform(0.0, 10.0 * math.sqrt(n), (n, 2))
    d = np.hypot(*(p[:, None] - p[None]).transpose(2, 0, 1))
    near = np.triu((d <= 16.0) & (rng.uniform(size=d.shape) < 0.5), 1) | (minimum_spanning_tree(d).toarray() > 0)
    nbrs = [set(np.flatnonzero(near[j] | near[:, j]).tolist()) - {j} for j in range(n)]
    parts = [0] * n
    r = solve_order(d, "registration", nbrs, parts, True, solution_limit=100)
    cert = certify(d, r, "registration", nbrs, parts, True, False)
    assert cert.method == BC_OPT and not registration_violations(cert.result.order, nbrs, parts, True)
    assert cert.result.length_m <= r.length_m + 1e-9
    assert cert.bound_m >= (1 - 1e-4) * cert.result.length_m  # mm rounding of 40 arcs at most
    ex = scip_order(d, True, nbrs, parts, hint=cert.result.order)
    assert ex.optimal and ex.length_m == pytest.approx(cert.result.length_m)
    weak = cpsat_order(d, True, nbrs, parts, hint=cert.result.order, work_limit=1.0)
    assert weak.bound_m <= cert.result.length_m + 1e-9
