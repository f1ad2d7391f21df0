"""The ring walk over short arcs without links (:func:`planner.bounds.arc_reach.short_arc_ring`) takes the same step
as the links :func:`planner.bounds.plane_patches.arc_links` forms (:func:`planner.solve.ring_unit.unit_ring`), reach by
reach, and so the same walk, on random rings: arcs of random spans and wall lengths near the seam, random lows (some 0),
pieces not required, shares 0 to 1. Arcs of half the ring or more are left to the links (None)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.bounds.arc_reach import short_arc_ring
from planner.bounds.plane_patches import arc_links
from planner.solve.ring_unit import unit_ring
from tests.bounds.test_plane_ring import QUICK


def _linked(start, span, low, lengths, required, share):  # type: ignore[no-untyped-def]
    n = lengths.size
    cum = np.concatenate([[0.0], np.cumsum(np.tile(lengths, 3))])
    one = arc_links(start, span, low, cum, n, share)
    adj = (one + one.T).astype(bool).tocsr()
    r = np.repeat(np.arange(start.size), span + 1)
    c = np.concatenate([np.arange(a, a + k + 1) for a, k in zip(start, span)]) % n
    cover = sp.csr_matrix((np.ones(r.size, dtype=bool), (r, c)), shape=(start.size, n))
    return unit_ring(cover, required, adj)


@settings(QUICK, max_examples=300)
@given(
    seed=st.integers(0, 100_000),
    n=st.integers(8, 40),
    m=st.integers(1, 30),
    share=st.sampled_from([0.0, 0.1, 0.3, 0.5, 1.0]),
)
def test_short_arcs_take_the_steps_of_their_links(seed: int, n: int, m: int, share: float) -> None:
    rng = np.random.default_rng(seed)
    longest = (n - 3) // 2  # 2 span + 2 < n
    start = rng.integers(0, n, m)
    span = rng.integers(0, longest + 1, m)
    lengths = rng.choice([0.5, 1.0, 2.5], n) * rng.uniform(0.5, 1.5, n)
    cum = np.concatenate([[0.0], np.cumsum(np.tile(lengths, 2))])
    whole = cum[start + span + 1] - cum[start]
    low = np.where(rng.random(m) < 0.2, 0.0, whole * rng.uniform(0.0, 1.0, m))  # what the patch surely sees
    required = rng.random(n) < 0.85
    required[int(rng.integers(n))] = True
    new = short_arc_ring(start, span, low, lengths, required, share)
    old = _linked(start, span, low, lengths, required, share)
    assert new is not None and old is not None
    reach = old.hi.copy()
    for _ in range(m + 1):  # each step from the same reach
        step = np.maximum(reach, old.linked(reach))
        assert np.array_equal(np.maximum(reach, new.linked(reach)), step)
        reach = step
    assert new.unit_walk() == old.unit_walk()
    for limit in (0.5, 2.5, 4.5):
        assert new.unit_walk(limit=limit) == old.unit_walk(limit=limit)


# the full-strength run is in the slow tier (see tests/bounds/test_plane_patches.py for why it is marked so)
test_short_arcs_take_the_steps_of_their_links = pytest.mark.slow(test_short_arcs_take_the_steps_of_their_links)


@settings(QUICK, max_examples=40)
@given(seed=st.integers(0, 100_000), n=st.integers(8, 40), m=st.integers(1, 30), share=st.sampled_from([0.0, 0.3, 1.0]))
def test_short_arcs_take_the_steps_of_their_links_on_fewer_cases(seed, n, m, share):  # type: ignore[no-untyped-def]
    test_short_arcs_take_the_steps_of_their_links.hypothesis.inner_test(seed=seed, n=n, m=m, share=share)


def test_arcs_of_half_the_ring_are_left_to_the_links() -> None:
    lengths, required = np.ones(10), np.ones(10, dtype=bool)
    start, low = np.array([0, 5]), np.zeros(2)
    assert short_arc_ring(start, np.array([3, 3]), low, lengths, required, 0.3) is not None  # 2 * 3 + 2 < 10
    assert short_arc_ring(start, np.array([4, 3]), low, lengths, required, 0.3) is None
    assert short_arc_ring(start, np.array([3, 3]), low, lengths, np.zeros(10, dtype=bool), 0.3) is None
