"""The vectorised presolve against straightforward references on small random inputs (issue 56: cheaper, the same
results).

:func:`planner.solve.lazy_links.linked_dominated` takes the shared wall and the count of shared pieces from one complex
product and tests a candidate's replacers on all its hard links at once; the reference forms both real products whole
and walks the kept candidates one at a time with Python sets. :func:`planner.solve.presolve.dominated` without a
relation tests every candidate at once (:func:`planner.solve.presolve._dominated_plain`); the reference is the walk
over the pieces' lists of kept seers. Both must give exactly the same masks (and the same relation among the kept),
float ties, identical rows, stored False entries and small blocks included.
"""

from __future__ import annotations

from unittest.mock import patch

import numpy as np
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.coverage.overlap import OverlapRule, group_ids, link_filter
from planner.solve import lazy_links, presolve
from planner.solve.lazy_links import OverlapLinks, length_order, linked_dominated, representatives
from planner.solve.presolve import dominated, presolve_order


def reference_linked(
    a: sp.csr_matrix, cost: np.ndarray, lengths: np.ndarray, rule: OverlapRule, gid: np.ndarray
) -> tuple[np.ndarray, set[tuple[int, int]]]:
    """The rule of :func:`linked_dominated` spelled out: the real products formed whole (the same sums in the same
    order as a block of them), candidates longest first, i dropped for a kept superset j of its group, no dearer,
    linked to every kept neighbour k of i with s(i, k) + slack < rho min(L_j, L_k), j itself aside."""
    a = a.astype(bool).tocsr()
    a.sort_indices()
    n = a.shape[0]
    covered = np.asarray(a @ lengths, dtype=np.float64).ravel()
    _, keep = link_filter(rule, covered, gid)
    right = (a.astype(np.float64) @ sp.diags(lengths)).T.tocsr()
    ones = sp.csr_matrix((np.ones(right.nnz), right.indices, right.indptr), shape=right.shape)
    shared = (a.astype(np.float64) @ right).toarray()
    count = (a.astype(np.float64) @ ones).toarray()
    size = np.diff(a.indptr)
    reps = representatives(a, cost, gid)
    order = reps[length_order(a[reps], cost[reps], covered[reps])]
    removed = np.ones(n, dtype=bool)
    kept: list[int] = []
    nbrs: dict[int, set[int]] = {}
    for i in order.tolist():
        if size[i] == 0:
            continue
        near = [k for k in kept if shared[i, k] != 0]
        links = [k for k in near if keep(np.array([i]), np.array([k]), np.array([shared[i, k]]))[0]]
        sups = [j for j in near if count[i, j] == size[i] and cost[j] <= cost[i] and gid[j] == gid[i]]
        longer = [k for k in links if covered[k] > covered[i] and rule.overlap * covered[k] > shared[i, k] + 1e-9]
        if any(
            all(k == j or k in nbrs[j] for k in longer if shared[i, k] + 1e-9 < rule.overlap * covered[j]) for j in sups
        ):
            continue
        removed[i] = False
        kept.append(i)
        nbrs[i] = set(links)
        for k in links:
            nbrs[k].add(i)
    return removed, {(i, k) for i, ks in nbrs.items() for k in ks}


def random_rows(rng: np.random.Generator, n: int, m: int, density: float, falses: bool) -> sp.csr_matrix:
    """Rows of pieces, a third of them repeated; with ``falses`` some entries stored as False."""
    a = sp.csr_matrix(rng.random((n, m)) < density)
    if n > 2:
        a = sp.vstack([a, a[: n // 3]]).tocsr()
    if falses and a.nnz:
        a = a.copy()
        a.data = a.data.copy()
        a.data[rng.random(a.nnz) < 0.1] = False
    return a


@settings(max_examples=200, deadline=None, derandomize=True, database=None)
@given(
    n=st.integers(1, 30),
    m=st.integers(1, 10),
    seed=st.integers(0, 2**31 - 1),
    share=st.sampled_from([0.0, 0.3, 0.5, 0.9]),
    unit=st.booleans(),
    falses=st.booleans(),
    block=st.sampled_from([1, 3, 512]),
    pairs=st.sampled_from([1, 4096]),
)
def test_linked_dominated_as_the_reference(
    n: int, m: int, seed: int, share: float, unit: bool, falses: bool, block: int, pairs: int
) -> None:
    # unit lengths: covered lengths and shared walls tie; blocks of 1 and 3 rows; replacers a row at a time
    rng = np.random.default_rng(seed)
    a = random_rows(rng, n, m, 0.4, falses)
    cost = rng.integers(1, 3, a.shape[0]).astype(float)
    lengths = np.ones(m) if unit else rng.uniform(0.1, 2.0, m)
    gid = group_ids(rng.integers(0, 2, a.shape[0]).tolist())
    rule = OverlapRule(share)
    want_drop, want_links = reference_linked(a, cost, lengths, rule, gid)
    with patch.object(lazy_links, "BLOCK_ROWS", block), patch.object(lazy_links, "_PAIRS", pairs):
        drop, among = linked_dominated(a, cost, OverlapLinks(lengths, rule, gid))
    assert drop.tolist() == want_drop.tolist()
    got = among.tocoo()
    assert set(zip(got.row.tolist(), got.col.tolist())) == want_links


def reference_plain(a: sp.csr_matrix, cost: np.ndarray, groups: list[int] | None) -> np.ndarray:
    """Plain dominance by the walk over the pieces' lists of kept seers."""
    a = a.astype(bool).tocsr()
    a.sort_indices()
    cost = np.asarray(cost, float)
    gid = np.zeros(a.shape[0], dtype=np.int64) if groups is None else group_ids(groups)
    return presolve._dominated_by_pieces(a, np.diff(a.indptr), cost, presolve_order(a, cost), gid, None)


@settings(max_examples=300, deadline=None, derandomize=True, database=None)
@given(
    n=st.integers(0, 40),
    m=st.integers(1, 12),
    seed=st.integers(0, 2**31 - 1),
    density=st.floats(0.05, 0.9),
    grouped=st.booleans(),
    falses=st.booleans(),
    chunk=st.sampled_from([1, 7, 1_000_000]),
)
def test_plain_dominance_as_the_walk(
    n: int, m: int, seed: int, density: float, grouped: bool, falses: bool, chunk: int
) -> None:
    # every candidate at once (pairs a few rows at a time), and the bits refused (the walk itself)
    rng = np.random.default_rng(seed)
    a = random_rows(rng, n, m, density, falses)
    cost = rng.integers(0, 3, a.shape[0]).astype(float)
    groups = rng.integers(0, 2, a.shape[0]).tolist() if grouped else None
    want = reference_plain(a, cost, groups).tolist()
    with patch.object(presolve, "_PLAIN_PAIRS", chunk):
        assert dominated(a, cost, None, groups).tolist() == want
    with patch.object(presolve, "PLAIN_BITS", 0):
        assert dominated(a, cost, None, groups).tolist() == want
