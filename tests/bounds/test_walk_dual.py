"""The ring walk's Lagrangian dual by column generation (planner.bounds.walk_dual) and the zone-sides whose patches see
only arcs (planner.bounds.ring_walks.arcs_only).

- On random small rings whose candidates see runs with holes, linked only where they share a piece, with unit or
  small integral costs: the bound never passes the cheapest connected cover (brute force over every subset), and
  never falls below the plain walk it starts from.
- Where every candidate sees an arc, the cheapest connected cover is the walk (the ring theorem), so the dual adds
  nothing: the premise of not running the quick cover over patches whose every set is an arc.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse.csgraph import connected_components

from planner.bounds.walk_dual import walk_dual_bound
from planner.solve.ring import ring_graph
from tests.bounds.test_plane_ring import QUICK


def cheapest_connected(a: np.ndarray, adj: np.ndarray, cost: np.ndarray) -> float:
    """The least cost of a set of rows of ``a`` (rows x targets, bool) covering every target, connected under
    ``adj``; inf where none."""
    n, best = a.shape[0], float("inf")
    for k in range(1, n + 1):
        for rows in itertools.combinations(range(n), k):
            r = list(rows)
            if cost[r].sum() >= best or not a[r].any(axis=0).all():
                continue
            if k == 1 or connected_components(sp.csr_matrix(adj[np.ix_(r, r)]), directed=False)[0] == 1:
                best = float(cost[r].sum())
    return best


@st.composite
def rings(draw, arcs_only: bool = False):
    """(cover: candidates x pieces in cyclic order, links, costs): each candidate sees a run of the ring, with holes
    unless ``arcs_only``; links drawn among pairs that share a piece; the pieces no candidate sees left out (the runs
    stay runs of the ring that is left)."""
    n, m = draw(st.integers(4, 10)), draw(st.integers(2, 8))
    a = np.zeros((m, n), dtype=bool)
    for j in range(m):
        start, length = draw(st.integers(0, n - 1)), draw(st.integers(1, n - 1))
        run = [(start + i) % n for i in range(length)]
        keep = [True] * length if arcs_only else draw(st.lists(st.booleans(), min_size=length, max_size=length))
        keep[0] = keep[-1] = True  # the run's ends seen: its arc is the run
        a[j, [p for p, k in zip(run, keep) if k]] = True
    a = a[:, a.any(axis=0)]
    share = (a.astype(int) @ a.T.astype(int)) > 0
    pick = np.array(draw(st.lists(st.booleans(), min_size=m * m, max_size=m * m))).reshape(m, m)
    adj = np.triu(share & pick, 1)
    cost = np.array(draw(st.lists(st.sampled_from([1.0, 1.0, 2.0, 3.0]), min_size=m, max_size=m)))
    return a, adj | adj.T, cost


def _bound(a: np.ndarray, adj: np.ndarray, cost: np.ndarray, goal: int) -> tuple[float, float] | None:
    """(the dual's bound, the plain walk) on ``a``, or None where the ring graph is not formed."""
    graph = ring_graph(sp.csr_matrix(a), np.ones(a.shape[1], dtype=bool), sp.csr_matrix(adj))
    if graph is None:
        return None
    walk = graph.walk(cost)
    value, _ = walk_dual_bound(graph, sp.csr_matrix(a.astype(np.float64)), cost, goal, 30)
    return value, (np.inf if walk is None else walk.bound)


@pytest.mark.slow
@settings(QUICK, max_examples=300)
@given(inst=rings())
def test_the_dual_bound_stays_below_the_connected_optimum(inst):
    a, adj, cost = inst
    best = cheapest_connected(a, adj, cost)
    got = _bound(a, adj, cost, int(min(best, 99)) + 1)
    if got is None:
        return
    value, walk = got
    assert value <= best + 1e-6, (value, best)
    if np.isfinite(walk):
        assert value >= walk - 1e-6


@settings(QUICK, max_examples=25)
@given(inst=rings())
def test_the_dual_bound_on_fewer_cases(inst):
    # the quick twin of the test above: its body on 25 cases
    test_the_dual_bound_stays_below_the_connected_optimum.hypothesis.inner_test(inst=inst)


@pytest.mark.slow
@settings(QUICK, max_examples=150)
@given(inst=rings(arcs_only=True))
def test_where_every_set_is_an_arc_the_cover_is_the_walk(inst):
    a, adj, cost = inst
    best = cheapest_connected(a, adj, cost)
    got = _bound(a, adj, cost, int(min(best, 99)) + 1)
    if got is None or not np.isfinite(best):
        return
    value, walk = got
    assert walk == pytest.approx(best)
    assert value <= best + 1e-6
