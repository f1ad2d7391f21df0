"""The unit-cost ring walk by reach (:mod:`planner.solve.ring_unit`) equals the unrolled graph's cheapest walk at unit
costs (:meth:`planner.solve.ring.RingGraph.walk`, Dijkstra from every anchor) on random rings of arcs, with holes,
pieces not required and limits: the same cost wherever it is at most the limit + 1, and None where the unrolled graph
is None."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.solve.ring import ring_graph
from planner.solve.ring_unit import unit_ring
from tests.bounds.test_plane_ring import QUICK
from tests.solve.test_ring import adjacency, matrix, ring_arcs

LIMITS = (np.inf, 6.5, 4.5, 2.5, 1.5, 0.5)


def _same(a: sp.csr_matrix, required: np.ndarray, adj: sp.csr_matrix) -> None:
    old, new = ring_graph(a, required, adj), unit_ring(a, required, adj)
    assert (old is None) == (new is None)
    if old is None or new is None:
        return
    ones = np.ones(a.shape[0])
    full = old.walk(ones)
    walk = None if full is None else round(full.bound)
    assert new.unit_walk() == walk
    for limit in LIMITS:
        got = new.unit_walk(limit=limit)
        if walk is not None and (limit == np.inf or walk <= math.floor(limit) + 1):
            within = old.walk(ones, limit=limit)  # both branches from the anchor within the limit
            assert within is not None and got == walk == round(within.bound), limit
        else:
            assert got is None, limit


@settings(QUICK, max_examples=300)
@given(seed=st.integers(0, 100_000), n=st.integers(4, 16), m=st.integers(3, 18), holes=st.booleans())
def test_the_walk_by_reach_is_the_unrolled_walk(seed: int, n: int, m: int, holes: bool) -> None:
    rng = np.random.default_rng(seed)
    a = matrix(ring_arcs(rng, n, m, holes), n)
    required = rng.random(n) < 0.8
    required[int(rng.integers(n))] = True
    _same(a, required, adjacency(a))


# the full-strength run is in the slow tier (see tests/bounds/test_plane_patches.py for why it is marked so)
test_the_walk_by_reach_is_the_unrolled_walk = pytest.mark.slow(test_the_walk_by_reach_is_the_unrolled_walk)


@settings(QUICK, max_examples=40)
@given(seed=st.integers(0, 100_000), n=st.integers(4, 16), m=st.integers(3, 18), holes=st.booleans())
def test_the_walk_by_reach_is_the_unrolled_walk_on_fewer_cases(seed, n, m, holes):
    test_the_walk_by_reach_is_the_unrolled_walk.hypothesis.inner_test(seed=seed, n=n, m=m, holes=holes)


def test_long_arcs_that_meet_at_two_turns_and_a_link_across_the_seam():
    # arcs of 7 of 8 pieces meet both on this turn and the next: the walk takes the turn that reaches farther
    a = matrix([{(s + j) % 8 for j in range(7)} for s in (0, 4)], 8)
    _same(a, np.ones(8, dtype=bool), adjacency(a))
    # a chain round a ring of 12 whose links cross the seam (piece 11 to 0), every link by hand
    a = matrix([{(s + j) % 12 for j in range(5)} for s in (10, 2, 6)], 12)
    adj = sp.csr_matrix(np.array([[0, 1, 0], [1, 0, 1], [0, 1, 0]], dtype=bool))
    walk = unit_ring(a, np.ones(12, dtype=bool), adj)
    assert walk is not None and walk.unit_walk() == 3 and walk.unit_walk(limit=1.5) is None


def test_none_where_a_linked_pair_never_meets_or_nothing_is_required():
    a = matrix([{0, 1}, {4, 5}], 8)
    adj = sp.csr_matrix(np.array([[0, 1], [1, 0]], dtype=bool))
    assert unit_ring(a, np.ones(8, dtype=bool), adj) is None is ring_graph(a, np.ones(8, dtype=bool), adj)
    assert unit_ring(a, np.zeros(8, dtype=bool), adjacency(a)) is None
