"""The plain cover by CFT through pycft: a cover, no smaller than the optimum, a bound below it (planner.solve.cft)."""

from __future__ import annotations

from itertools import combinations

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.core.errors import InfeasibleError
from planner.solve.cft import cft_cover

# c0 sees targets {0, 1}, c1 {2, 3}, c2 {0, 2}, c3 {1, 3}: each candidate sees 2 of the 4 targets, so no single one
# covers them and the optimum is at least 2; c0 + c1 (and c2 + c3) cover all 4: the optimum is 2. Each target is
# seen by exactly two candidates, so x = 1/2 everywhere is an LP solution of value 4 * 1/2 = 2 = the LP optimum, and
# a Lagrangian bound is at most that: lower_bound <= 2.
TINY = sp.csr_matrix(np.array([[1, 1, 0, 0], [0, 0, 1, 1], [1, 0, 1, 0], [0, 1, 0, 1]], dtype=bool))


def is_cover(a: sp.csr_matrix, selected: tuple[int, ...]) -> bool:
    return bool((np.bincount(a[list(selected)].indices, minlength=a.shape[1]) > 0).all())


def random_cover_matrix(seed: int, n: int, m: int, density: float) -> sp.csr_matrix:
    """n candidates x m targets, each target seen by at least one candidate."""
    rng = np.random.default_rng(seed)
    a = rng.random((n, m)) < density
    for j in np.flatnonzero(~a.any(axis=0)):
        a[rng.integers(n), j] = True
    return sp.csr_matrix(a)


def brute_force(a: sp.csr_matrix, cost: np.ndarray) -> float:
    """The least cost of a cover of every target, over all subsets of the candidates."""
    n = a.shape[0]
    return min(float(cost[list(s)].sum()) for r in range(n + 1) for s in combinations(range(n), r) if is_cover(a, s))


def test_tiny_optimum_two():
    got = cft_cover(TINY)
    assert got.selected in ((0, 1), (2, 3))
    assert 0 < got.lower_bound <= 2 + 1e-9
    assert not got.capped


def test_tiny_costs_turn_the_choice():
    # c0 and c1 cost 2 each (c0 + c1: 4), c2 and c3 cost 1 each (c2 + c3: 2); any cover holds c0 or c2 for
    # target 0 and c1 or c3 for target 3, so 2 is the least cost, by c2 + c3 alone
    got = cft_cover(TINY, np.array([2.0, 2.0, 1.0, 1.0]))
    assert got.selected == (2, 3) and got.lower_bound <= 2 + 1e-9


@settings(max_examples=150, deadline=None, derandomize=True, database=None)
@given(
    n=st.integers(1, 8),
    m=st.integers(1, 8),
    seed=st.integers(0, 2**31 - 1),
    density=st.floats(0.1, 0.7),
    weighted=st.booleans(),
)
def test_matches_brute_force(n: int, m: int, seed: int, density: float, weighted: bool) -> None:
    a = random_cover_matrix(seed, n, m, density)
    cost = np.random.default_rng(seed + 1).integers(1, 4, n).astype(float) if weighted else np.ones(n)
    got = cft_cover(a, cost if weighted else None)
    best = brute_force(a, cost)
    assert is_cover(a, got.selected)
    assert list(got.selected) == sorted(set(got.selected))
    assert float(cost[list(got.selected)].sum()) >= best - 1e-9
    assert got.lower_bound <= best + 1e-6


@settings(max_examples=40, deadline=None, derandomize=True, database=None)
@given(n=st.integers(1, 8), m=st.integers(2, 8), seed=st.integers(0, 2**31 - 1))
def test_a_target_nobody_sees_is_infeasible(n: int, m: int, seed: int) -> None:
    a = random_cover_matrix(seed, n, m, 0.5).toarray()
    a[:, seed % m] = False  # target seed % m: seen by no candidate
    with pytest.raises(InfeasibleError):
        cft_cover(sp.csr_matrix(a))


def test_nothing_to_cover():
    got = cft_cover(sp.csr_matrix((3, 0), dtype=bool))
    assert got.selected == () and got.lower_bound == 0.0


def test_empty_candidates_are_never_chosen():
    # rows 0 and 2 see nothing; CFT is given rows 1 and 3 only, and its answer maps back to them
    a = sp.csr_matrix(np.array([[0, 0], [1, 0], [0, 0], [0, 1]], dtype=bool))
    assert cft_cover(a).selected == (1, 3)


def test_same_seed_same_result():
    a = random_cover_matrix(5, 200, 120, 0.04)
    first, again = cft_cover(a, seed=3), cft_cover(a, seed=3)
    assert first.selected == again.selected and first.lower_bound == again.lower_bound
    assert is_cover(a, first.selected)


def test_start_is_used():
    # 60 candidates x 40 targets: with its full 250 heuristic iterations CFT finds 11 stations; with 1 it stops at
    # 12. Given the 11-cover as its start, the 1-iteration run keeps it (the start is its first upper bound)
    a = random_cover_matrix(0, 60, 40, 0.08)
    full, short = cft_cover(a), cft_cover(a, heur_iters=1)
    assert (len(full.selected), len(short.selected)) == (11, 12)
    started = cft_cover(a, heur_iters=1, start=full.selected)
    assert is_cover(a, started.selected) and len(started.selected) == 11


def test_start_every_candidate():
    # the trivial cover (every candidate, empty ones included, one repeated) as the start: a cover no larger
    a = random_cover_matrix(2, 30, 20, 0.1).toarray()
    a[4] = False
    a = sp.csr_matrix(a)
    start = (*range(30), 7)
    got = cft_cover(a, start=start)
    assert is_cover(a, got.selected) and len(got.selected) <= 30


def test_start_that_is_no_cover():
    with pytest.raises(ValueError, match="not a cover"):
        cft_cover(TINY, start=(0, 2))
