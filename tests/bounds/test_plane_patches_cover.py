"""The quick connected bound over patches (planner.bounds.patch_cover, planner.bounds.plane_refine.quick_bound): its
reductions against brute force, and the bound against the exact connected optimum over a grid.

- The reduction (near replacements, then dominance under the links and implied targets, alternated) keeps the
  connected optimum of random small instances, found by brute force over every subset; the ring walk with its
  Lagrangian ascent over the reduced instance never passes it.
- The near prefilter of the (U, low) dominance changes nothing: the undominated patches are the same with it.
- The quick bound never passes the exact connected optimum over a 0.5-m grid of positions (the oracle of
  ``test_plane_ring``), at the default patch count and at a coarse one.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse.csgraph import connected_components

import planner
from planner.bounds.patch_cover import near_linked_dominated, reduced, ring_lagrange_bound
from planner.bounds.plane_refine import quick_bound, undominated_rows
from planner.plan import PlanOptions
from planner.solve.milp import MilpOptions
from tests.bounds.test_plane_properties import SCALE
from tests.bounds.test_plane_refine import _levels
from tests.bounds.test_plane_ring import QUICK, block_site, connected_optimum


def brute_optimum(a: np.ndarray, adj: np.ndarray) -> float:
    """The least connected set of rows of ``a`` (rows x targets, bool) covering every target, under ``adj``."""
    n = a.shape[0]
    for k in range(1, n + 1):
        for rows in itertools.combinations(range(n), k):
            r = list(rows)
            if not a[r].any(axis=0).all():
                continue
            if k == 1 or connected_components(sp.csr_matrix(adj[np.ix_(r, r)]), directed=False)[0] == 1:
                return float(k)
    return float("inf")


@st.composite
def instances(draw):
    n, m = draw(st.integers(2, 9)), draw(st.integers(1, 7))
    a = np.array(draw(st.lists(st.lists(st.booleans(), min_size=m, max_size=m), min_size=n, max_size=n)), dtype=bool)
    for t in range(m):  # every target seen by some row
        if not a[:, t].any():
            a[draw(st.integers(0, n - 1)), t] = True
    # links only between rows that share a target (as relaxed links do), each such pair drawn
    share = (a.astype(int) @ a.T.astype(int)) > 0
    pick = np.array(draw(st.lists(st.booleans(), min_size=n * n, max_size=n * n))).reshape(n, n)
    adj = np.triu(share & pick, 1)
    adj = adj | adj.T
    cells = np.array(draw(st.permutations(list(itertools.product(range(4), range(4))))))[:n]
    return a, adj, cells


@pytest.mark.slow
@settings(QUICK, max_examples=300)
@given(inst=instances())
def test_the_reduction_keeps_the_connected_optimum_and_the_bound_stays_below(inst):
    a, adj, cells = inst
    best = brute_optimum(a, adj)
    kc, kt = reduced(sp.csr_matrix(a), sp.csr_matrix(adj), cells)
    assert brute_optimum(a[np.ix_(kc, kt)], adj[np.ix_(kc, kc)]) == best
    gone = near_linked_dominated(sp.csr_matrix(a), sp.csr_matrix(adj), cells)
    keep = np.flatnonzero(~gone)
    assert brute_optimum(a[keep], adj[np.ix_(keep, keep)]) == best
    if np.isfinite(best):
        sub = sp.csr_matrix(a[kc])
        assert ring_lagrange_bound(sub, kt, sp.csr_matrix(adj[np.ix_(kc, kc)]), int(best) + 1) <= best


@pytest.mark.slow
@settings(QUICK, max_examples=200)
@given(
    rows=st.lists(st.sets(st.integers(0, 9), min_size=1), min_size=1, max_size=25),
    lows=st.lists(st.sampled_from([0.0, 0.5, 1.0, 2.0]), min_size=25, max_size=25),
    order=st.permutations(list(range(25))),
)
def test_the_near_prefilter_changes_no_undominated_patch(rows, lows, order):
    n = len(rows)
    u = sp.csr_matrix(
        (
            np.ones(sum(map(len, rows)), dtype=bool),
            (np.repeat(np.arange(n), [len(r) for r in rows]), [c for r in rows for c in sorted(r)]),
        ),
        shape=(n, 10),
    )
    low = np.asarray(lows[:n])
    cell = np.asarray(order[:n])
    h = 1.5
    cx, cy = (cell % 5) * h + 3.0, (cell // 5) * h - 7.0
    plain = undominated_rows(u, low)[0]
    near = undominated_rows(u, low, (cx, cy, h))[0]
    key = [(frozenset(rows[i]), low[i]) for i in range(n)]
    assert {key[i] for i in plain.tolist()} == {key[i] for i in near.tolist()}


@settings(QUICK, max_examples=20)
@given(inst=instances())
def test_the_reduction_on_fewer_cases(inst):
    # the quick twin of the test above: its body on 20 cases
    test_the_reduction_keeps_the_connected_optimum_and_the_bound_stays_below.hypothesis.inner_test(inst=inst)


@pytest.mark.slow
@settings(QUICK, max_examples=max(1, int(12 * SCALE)))
@given(
    kind=st.sampled_from(["rect", "rect", "L", "U"]),
    w=st.floats(1.5, 5.0),
    h=st.floats(1.5, 5.0),
    theta=st.floats(40.0, 80.0),
    reach=st.floats(6.0, 12.0),
    share=st.floats(0.1, 0.6),
    inside=st.sampled_from([False, False, True]),
    angle=st.floats(0, 360),
    coarse=st.booleans(),
)
def test_the_quick_bound_at_most_the_connected_optimum_over_a_grid(
    kind, w, h, theta, reach, share, inside, angle, coarse
):
    if kind != "rect":
        w, h = max(w, 5.0), max(h, 5.0)
    site = block_site(kind, w, h, 0.5, 0.5, theta, reach, share, inside, angle, (10.0, -20.0))
    options = PlanOptions(method="milp", precision=False, milp=MilpOptions(overlap=planner.OverlapRule(share)))
    optimum, _ = connected_optimum(site, options, share)
    if not np.isfinite(optimum):
        return
    lv, _seen = _levels(site, options)
    got = quick_bound(lv.pieces, share, int(optimum) + 1, *((2_000,) if coarse else ()))
    assert got.bound <= optimum, (got, optimum)


@pytest.mark.slow
def test_the_grid_centres_are_those_of_its_rows():
    # SidePieces.grid's centres (the quick bound's near cells, the refinement's first patches) carry the sets the
    # STR-trees give at them: the scan line's U and low, row for row
    site = block_site("U", 5.0, 5.0, 0.5, 0.5, 75.0, 10.0, 0.25, False, 30.0, (3.0, -4.0))
    options = PlanOptions(method="milp", precision=False, milp=MilpOptions(overlap=planner.OverlapRule(0.25)))
    lv, _seen = _levels(site, options)
    got = lv.pieces.grid(lv.h0)
    assert got is not None and lv.pieces.grid(lv.h0) is got  # formed once
    u, low, cx, cy = got
    want_u, want_low = lv.sets(cx, cy, 0)
    assert (u != want_u).nnz == 0 and np.allclose(low, want_low)
