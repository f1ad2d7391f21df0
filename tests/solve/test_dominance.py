"""Offline dominance maxima (:mod:`planner.solve.dominance`) equal the brute-force maximum over every point with
x <= X and y >= Y, on random points and queries with ties, empty answers and weights changed between calls."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.solve.dominance import DominanceMax
from tests.bounds.test_plane_ring import QUICK

EMPTY = -(10**6)


def _brute(x, y, qx, qy, w):  # type: ignore[no-untyped-def]
    return np.array(
        [max([int(w[i]) for i in range(x.size) if x[i] <= a and y[i] >= b] + [EMPTY]) for a, b in zip(qx, qy)]
    )


@settings(QUICK, max_examples=200)
@given(seed=st.integers(0, 100_000), m=st.integers(0, 70), q=st.integers(0, 40), grid=st.sampled_from([3, 8, 1000]))
def test_dominance_maxima_are_the_brute_force_maxima(seed: int, m: int, q: int, grid: int) -> None:
    rng = np.random.default_rng(seed)
    x, y = (rng.integers(0, grid, m) / 7.0 for _ in range(2))  # small grids: many ties
    qx, qy = (rng.integers(-1, grid + 1, q) / 7.0 for _ in range(2))
    tree = DominanceMax(x, y, qx, qy)
    for _ in range(3):  # the same points and queries, new weights
        w = rng.integers(-1000, 1000, m)
        assert np.array_equal(tree(w, EMPTY), _brute(x, y, qx, qy, w))


def test_a_point_counts_on_the_boundary_and_not_past_it() -> None:
    tree = DominanceMax(
        np.array([1.0, 2.0]), np.array([5.0, 3.0]), np.array([1.0, 2.0, 0.5]), np.array([5.0, 3.0, 0.0])
    )
    assert tree(np.array([10, 20]), -1).tolist() == [10, 20, -1]
    assert tree(np.array([30, 20]), -1).tolist() == [30, 30, -1]  # (1, 5) dominates (2, 3)'s query too
