"""Dominance without the candidate x candidate product (issue 32), against its definition written plainly.

The oracle: candidates in order of (largest coverage, cheapest, lowest index); i is dropped when some
candidate j kept before it, no dearer, of its group, sees every piece i sees and (under ``adj``) is
linked to every other neighbour of i; a candidate seeing nothing is dropped unless it may bridge. Both
must drop exactly the same candidates on random small matrices, with and without an overlap graph.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.solve.presolve import _no_bridge, dominated


def oracle(a: sp.csr_matrix, cost: np.ndarray, adj: sp.csr_matrix | None, groups: list[int] | None) -> np.ndarray:
    sets = [set(a.indices[a.indptr[i]:a.indptr[i + 1]].tolist()) for i in range(a.shape[0])]
    nb = None if adj is None else [set(adj.indices[adj.indptr[i]:adj.indptr[i + 1]].tolist()) for i in range(a.shape[0])]
    order = sorted(range(a.shape[0]), key=lambda i: (-len(sets[i]), cost[i], i))
    removed = np.zeros(a.shape[0], dtype=bool)
    kept: dict[int, int] = {}
    for rank, i in enumerate(order):
        if not sets[i]:
            if adj is None or _no_bridge(adj, i, removed, kept, cost, groups):
                removed[i] = True
                continue
        elif any(sets[i] <= sets[j] and cost[j] <= cost[i] and (groups is None or groups[j] == groups[i])
                 and (nb is None or nb[i] - {j} <= nb[j]) for j in kept):
            removed[i] = True
            continue
        kept[i] = rank
    return removed


@settings(max_examples=300, deadline=None, derandomize=True, database=None)
@given(n=st.integers(1, 14), m=st.integers(1, 8), seed=st.integers(0, 2**31 - 1), links=st.booleans(),
       grouped=st.booleans())
def test_dominated_matches_its_definition(n: int, m: int, seed: int, links: bool, grouped: bool) -> None:
    rng = np.random.default_rng(seed)
    a = sp.csr_matrix(rng.random((n, m)) < 0.35)
    cost = rng.integers(1, 3, n).astype(float)
    adj = None
    if links:
        upper = np.triu(rng.random((n, n)) < 0.3, 1)
        adj = sp.csr_matrix(upper | upper.T)
    groups = rng.integers(0, 2, n).tolist() if grouped else None
    assert dominated(a, cost, adj, groups).tolist() == oracle(a, cost, adj, groups).tolist()


def test_a_subset_goes_and_equal_rows_keep_the_first() -> None:
    # rows: {0,1,2}, {0,1}, {0,1,2}, {3}: row 1 is inside row 0; row 2 repeats row 0 (the first stays);
    # row 3 is alone: kept
    a = sp.csr_matrix(np.array([[1, 1, 1, 0], [1, 1, 0, 0], [1, 1, 1, 0], [0, 0, 0, 1]], dtype=bool))
    assert dominated(a, np.ones(4)).tolist() == [False, True, True, False]


@settings(max_examples=60, deadline=None, derandomize=True, database=None)
@given(seed=st.integers(0, 2**31 - 1), copies=st.integers(1, 4))
def test_overlap_links_among_distinct_rows_keep_the_connected_optimum(seed: int, copies: int) -> None:
    # a ring of 10 pieces, arcs of 2-4 pieces at random starts, each drawn up to 4 times (identical rows, as a
    # fine grid gives): the links are formed among one row per set of copies, and the connected optimum must
    # equal the one with every link formed and no presolve
    from planner.coverage.overlap import OverlapRule
    from planner.solve.milp import MilpOptions, solve
    from tests.solve.test_milp import instance

    rng = np.random.default_rng(seed)
    arcs = [{(s + j) % 10 for j in range(int(rng.integers(2, 5)))} for s in rng.integers(0, 10, 8)]
    arcs += [{s, (s + 1) % 10} for s in range(10)]  # every piece coverable
    cover = [c for c in arcs for _ in range(int(rng.integers(1, copies + 1)))]
    inst = instance(cover, 10)
    rule = OverlapRule(0.3)
    fast = solve(inst, MilpOptions(overlap=rule, time_limit_s=20))
    full = solve(inst, MilpOptions(overlap=rule, time_limit_s=20, presolve=False))
    assert fast.status.value == full.status.value == "optimal"
    assert fast.objective == full.objective


def test_representatives_one_per_group_and_row() -> None:
    from planner.solve.milp import representatives

    # rows 0 and 2 equal (group 0): 0 stays; row 3 equals row 0 but in group 1: stays; row 1 alone
    a = sp.csr_matrix(np.array([[1, 1, 0], [0, 1, 1], [1, 1, 0], [1, 1, 0]], dtype=bool))
    assert representatives(a, np.ones(4), np.array([0, 0, 0, 1])).tolist() == [0, 1, 3]
    # a cheaper copy is the representative
    assert representatives(a, np.array([2.0, 1.0, 1.0, 1.0]), np.array([0, 0, 0, 1])).tolist() == [1, 2, 3]


@settings(max_examples=300, deadline=None, derandomize=True, database=None)
@given(n=st.integers(1, 30), m=st.integers(1, 10), seed=st.integers(0, 2**31 - 1), share=st.floats(0.0, 0.9),
       grouped=st.booleans(), reps_only=st.booleans())
def test_lazy_rows_drop_what_the_whole_relation_drops(n: int, m: int, seed: int, share: float, grouped: bool,
                                                        reps_only: bool) -> None:
    # the relation formed row by row as the presolve asks (planner.solve.lazy_links) against the same relation
    # formed whole (overlap_adjacency among the same candidates): the same candidates dropped, and the relation
    # handed on among the kept is the whole one's restricted to them
    from planner.coverage.overlap import OverlapRule, group_ids, overlap_adjacency
    from planner.solve.lazy_links import LazyLinks
    from planner.solve.milp import representatives
    from planner.solve.presolve import presolve_order

    rng = np.random.default_rng(seed)
    a = sp.csr_matrix(rng.random((n, m)) < 0.4)
    if n > 2:
        a = sp.vstack([a, a[: n // 3]]).tocsr()  # copies, as a fine grid gives
    cost = rng.integers(1, 3, a.shape[0]).astype(float)
    lengths = rng.uniform(0.5, 2.0, m)
    groups = rng.integers(0, 2, a.shape[0]).tolist() if grouped else [0] * a.shape[0]
    gid = group_ids(groups)
    rule = OverlapRule(share)
    reps = representatives(a, cost, gid) if reps_only else np.arange(a.shape[0])
    sub, _ = overlap_adjacency(a[reps], lengths, rule, [groups[i] for i in reps])
    coo = sub.tocoo()
    whole = sp.csr_matrix((coo.data, (reps[coo.row], reps[coo.col])), shape=(a.shape[0],) * 2)
    lazy = LazyLinks(a, lengths, rule, gid, reps, presolve_order(a, cost))
    d_lazy, d_whole = dominated(a, cost, lazy, groups), dominated(a, cost, whole, groups)
    assert d_lazy.tolist() == d_whole.tolist()
    kept = np.flatnonzero(~d_lazy)
    among = lazy.among(kept)
    part = whole[kept][:, kept].tocoo()  # the whole relation among the kept, in the instance's indices
    expect = sp.csr_matrix((np.ones(part.nnz, dtype=bool), (kept[part.row], kept[part.col])), shape=whole.shape)
    assert (among != expect).nnz == 0
