"""Dominance without the candidate x candidate product (issue 32), against its definition written plainly.

The oracle: candidates in a given order (largest coverage, cheapest, lowest index; under the overlap rule
longest covered length first); i is dropped when some candidate j kept before it, no dearer, of its group,
sees every piece i sees and (under ``adj``) is linked to every neighbour of i not dropped before i, j itself
aside; a candidate seeing nothing is dropped when no neighbour of it is left or such a j is linked to all
that are. The presolve must drop exactly those, and (checked by brute force over every subset of small
random instances) an optimal connected plan must survive it.
"""

from __future__ import annotations

from itertools import combinations
from unittest.mock import patch

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse.csgraph import connected_components

from planner.coverage.overlap import OverlapRule, group_ids, overlap_adjacency
from planner.solve import presolve
from planner.solve.lazy_links import OverlapLinks, length_order, linked_dominated, representatives
from planner.solve.presolve import dominated, presolve_order


def oracle(
    a: sp.csr_matrix,
    cost: np.ndarray,
    adj: sp.csr_matrix | None,
    groups: list[int] | None,
    order: np.ndarray | None = None,
) -> np.ndarray:
    sets = [set(a.indices[a.indptr[i] : a.indptr[i + 1]].tolist()) for i in range(a.shape[0])]
    nb = (
        None
        if adj is None
        else [set(adj.indices[adj.indptr[i] : adj.indptr[i + 1]].tolist()) for i in range(a.shape[0])]
    )
    order = presolve_order(a, cost) if order is None else order
    removed: set[int] = set()
    kept: list[int] = []
    for i in order.tolist():
        left = set() if nb is None else nb[i] - removed
        fits = [
            j
            for j in kept
            if cost[j] <= cost[i] and (groups is None or groups[j] == groups[i]) and (nb is None or left - {j} <= nb[j])
        ]
        if (not sets[i] and (nb is None or not left or fits)) or any(sets[i] <= sets[j] for j in fits):
            removed.add(i)
        else:
            kept.append(i)
    return np.isin(np.arange(a.shape[0]), sorted(removed))


def connected_optimum(
    a: sp.csr_matrix, cost: np.ndarray, adj: sp.csr_matrix, groups: list[int], among: np.ndarray
) -> float:
    """The cheapest plan of candidates ``among`` that covers every piece, each group's stations connected."""
    need = np.flatnonzero(np.diff(a.tocsc().indptr) > 0)
    best = np.inf
    for r in range(among.size + 1):
        for plan in combinations(among.tolist(), r):
            p = np.asarray(plan, dtype=np.int64)
            if cost[p].sum() >= best or not np.isin(need, a[p].indices).all():
                continue
            if all(
                connected_components(adj[q][:, q], directed=False)[0] <= 1
                for g in set(groups)
                if (q := p[np.asarray(groups)[p] == g]).size
            ):
                best = float(cost[p].sum())
    return best


@settings(max_examples=300, deadline=None, derandomize=True, database=None)
@given(
    n=st.integers(1, 24),
    m=st.integers(1, 8),
    seed=st.integers(0, 2**31 - 1),
    density=st.one_of(st.none(), st.floats(0.1, 0.95)),
    grouped=st.booleans(),
    bits=st.booleans(),
)
def test_dominated_matches_its_definition(
    n: int, m: int, seed: int, density: float | None, grouped: bool, bits: bool
) -> None:
    # with the relation held as bits (replacers tried on 2, then 5 neighbours, then all) and as CSR rows only
    rng = np.random.default_rng(seed)
    a = sp.csr_matrix(rng.random((n, m)) < 0.35)
    cost = rng.integers(1, 3, n).astype(float)
    adj = None
    if density is not None:
        upper = np.triu(rng.random((n, n)) < density, 1)
        adj = sp.csr_matrix(upper | upper.T)
    groups = rng.integers(0, 2, n).tolist() if grouped else None
    want = oracle(a, cost, adj, groups).tolist()
    with patch.object(presolve, "_BITS_MAX", 16_384 if bits else 0), patch.object(presolve, "_PROBES", (2, 5)):
        for one_shot in (0, presolve._ONE_SHOT):  # the probes first, then all neighbours at once
            with patch.object(presolve, "_ONE_SHOT", one_shot):
                assert dominated(a, cost, adj, groups).tolist() == want


@pytest.mark.parametrize("flip", [0.0, 0.01])
def test_bits_and_rows_drop_what_the_definition_drops(flip: float) -> None:
    # 600 intervals on a line (pieces: 40 points), linked where they meet: a wider one holds a narrower one's
    # pieces and links. Some links flipped. Neighbourhoods of ~180, so the default probes (16, 256) come into
    # play; 519 and 23 of the 600 go.
    rng = np.random.default_rng(7)
    n = 600
    x, r = rng.uniform(0, 10, n), rng.uniform(0.2, 1.5, n)
    a = sp.csr_matrix(np.abs(np.linspace(0, 10, 40)[None, :] - x[:, None]) <= r[:, None])
    cost = rng.integers(1, 3, n).astype(float)
    upper = np.triu((np.abs(x[:, None] - x[None, :]) <= r[:, None] + r[None, :]) ^ (rng.random((n, n)) < flip), 1)
    adj = sp.csr_matrix(upper | upper.T)
    groups = rng.integers(0, 2, n).tolist()
    want = oracle(a, cost, adj, groups).tolist()
    for bits_max in (16_384, 0):  # bits, then the CSR rows only
        with patch.object(presolve, "_BITS_MAX", bits_max):
            assert dominated(a, cost, adj, groups).tolist() == want


def test_a_subset_goes_and_equal_rows_keep_the_first() -> None:
    # rows: {0,1,2}, {0,1}, {0,1,2}, {3}: row 1 is inside row 0; row 2 repeats row 0 (the first stays);
    # row 3 is alone: kept
    a = sp.csr_matrix(np.array([[1, 1, 1, 0], [1, 1, 0, 0], [1, 1, 1, 0], [0, 0, 0, 1]], dtype=bool))
    assert dominated(a, np.ones(4)).tolist() == [False, True, True, False]


@pytest.mark.slow
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
    fast = solve(inst, MilpOptions(overlap=rule))
    full = solve(inst, MilpOptions(overlap=rule, presolve=False))
    assert fast.status.value == full.status.value == "optimal"
    assert fast.objective == full.objective


def test_representatives_one_per_group_and_row() -> None:
    # rows 0 and 2 equal (group 0): 0 stays; row 3 equals row 0 but in group 1: stays; row 1 alone
    a = sp.csr_matrix(np.array([[1, 1, 0], [0, 1, 1], [1, 1, 0], [1, 1, 0]], dtype=bool))
    assert representatives(a, np.ones(4), np.array([0, 0, 0, 1])).tolist() == [0, 1, 3]
    # a cheaper copy is the representative
    assert representatives(a, np.array([2.0, 1.0, 1.0, 1.0]), np.array([0, 0, 0, 1])).tolist() == [1, 2, 3]


def random_pool(
    n: int, m: int, seed: int, grouped: bool, density: float = 0.4
) -> tuple[sp.csr_matrix, np.ndarray, np.ndarray, list[int]]:
    """Coverage rows (a third of them repeated, as a fine grid gives), costs 1-2, piece lengths, groups."""
    rng = np.random.default_rng(seed)
    a = sp.csr_matrix(rng.random((n, m)) < density)
    if n > 2:
        a = sp.vstack([a, a[: n // 3]]).tocsr()
    cost = rng.integers(1, 3, a.shape[0]).astype(float)
    lengths = rng.uniform(0.5, 2.0, m)
    groups = rng.integers(0, 2, a.shape[0]).tolist() if grouped else [0] * a.shape[0]
    return a, cost, lengths, groups


@settings(max_examples=300, deadline=None, derandomize=True, database=None)
@given(
    n=st.integers(1, 30),
    m=st.integers(1, 10),
    seed=st.integers(0, 2**31 - 1),
    share=st.floats(0.0, 0.9),
    grouped=st.booleans(),
)
def test_linked_dominance_drops_what_the_whole_relation_drops(
    n: int, m: int, seed: int, share: float, grouped: bool
) -> None:
    # the relation formed among the kept only, neighbours no longer than i left unchecked
    # (planner.solve.lazy_links) against the definition over the relation formed whole, in the same order
    # (longest covered length first): the same candidates dropped, and the relation handed on among the
    # kept is the whole one's restricted to them
    a, cost, lengths, groups = random_pool(n, m, seed, grouped)
    rule = OverlapRule(share)
    whole, _ = overlap_adjacency(a, lengths, rule, groups)
    covered = np.asarray(a.astype(float) @ lengths).ravel()
    drop, among = linked_dominated(a, cost, OverlapLinks(lengths, rule, group_ids(groups)))
    assert drop.tolist() == oracle(a, cost, whole, groups, length_order(a, cost, covered)).tolist()
    kept = np.flatnonzero(~drop)
    part = whole[kept][:, kept].tocoo()
    expect = sp.csr_matrix((np.ones(part.nnz, dtype=bool), (kept[part.row], kept[part.col])), shape=whole.shape)
    assert (among != expect).nnz == 0


@pytest.mark.slow
@settings(max_examples=150, deadline=None, derandomize=True, database=None)
@given(
    n=st.integers(1, 9),
    m=st.integers(1, 6),
    seed=st.integers(0, 2**31 - 1),
    grouped=st.booleans(),
    density=st.floats(0.1, 0.5),
)
def test_an_optimal_connected_plan_survives_dominance(n: int, m: int, seed: int, grouped: bool, density: float) -> None:
    # brute force over every subset: the cheapest connected cover over the kept candidates costs what the
    # cheapest over all of them costs, for a random relation (the rule of presolve.dominated) and for the
    # overlap relation (lazy_links.linked_dominated)
    a, cost, lengths, groups = random_pool(n, m, seed, grouped)
    rng = np.random.default_rng(seed + 1)
    c = a.shape[0]
    upper = np.triu(rng.random((c, c)) < density, 1)
    relations = [(sp.csr_matrix(upper | upper.T), None)]
    rule = OverlapRule(float(rng.uniform(0.0, 0.8)))
    relations.append((overlap_adjacency(a, lengths, rule, groups)[0], rule))
    for adj, rule_or_none in relations:
        every = connected_optimum(a, cost, adj, groups, np.arange(c))
        if rule_or_none is None:
            drop = dominated(a, cost, adj, groups)
        else:
            drop = linked_dominated(a, cost, OverlapLinks(lengths, rule_or_none, group_ids(groups)))[0]
        assert connected_optimum(a, cost, adj, groups, np.flatnonzero(~drop)) == every


@settings(max_examples=60, deadline=None, derandomize=True, database=None)
@given(n=st.integers(1, 9), m=st.integers(1, 6), seed=st.integers(0, 2**31 - 1), share=st.floats(0.0, 0.8))
def test_an_optimal_connected_plan_survives_the_passes(n: int, m: int, seed: int, share: float) -> None:
    # decompose._reduce alternates dominance (the first pass under the overlap rule, the others over the relation
    # among the kept) with implied targets: a cover of the kept targets by the kept candidates covers all,
    # and the cheapest connected one costs what the cheapest over everything costs
    from planner.solve.decompose import _reduce

    a, cost, lengths, groups = random_pool(n, m, seed, True)
    rule = OverlapRule(share)
    whole, _ = overlap_adjacency(a, lengths, rule, groups)
    drop, _, _ = _reduce(a, cost, OverlapLinks(lengths, rule, group_ids(groups)), groups)
    kept = np.flatnonzero(~drop)
    assert connected_optimum(a, cost, whole, groups, kept) == connected_optimum(
        a, cost, whole, groups, np.arange(a.shape[0])
    )


@settings(max_examples=150, deadline=None, derandomize=True, database=None)
@given(
    n=st.integers(1, 24),
    m=st.integers(1, 8),
    seed=st.integers(0, 2**31 - 1),
    density=st.one_of(st.none(), st.floats(0.1, 0.95)),
    grouped=st.booleans(),
)
def test_the_product_and_the_pieces_drop_the_same(
    n: int, m: int, seed: int, density: float | None, grouped: bool
) -> None:
    # the supersets from the candidate x candidate product (in blocks of a few rows, and in one), and the walk over
    # the pieces' lists of kept seers (the product refused), against the definition
    rng = np.random.default_rng(seed)
    a = sp.csr_matrix(rng.random((n, m)) < 0.35)
    cost = rng.integers(1, 3, n).astype(float)
    adj = None
    if density is not None:
        upper = np.triu(rng.random((n, n)) < density, 1)
        adj = sp.csr_matrix(upper | upper.T)
    groups = rng.integers(0, 2, n).tolist() if grouped else None
    want = oracle(a, cost, adj, groups).tolist()
    for work, block in ((0, 8_000_000), (presolve.PRODUCT_WORK, 8_000_000), (presolve.PRODUCT_WORK, 3)):
        with patch.object(presolve, "PRODUCT_WORK", work), patch.object(presolve, "_BLOCK_WORK", block):
            assert dominated(a, cost, adj, groups).tolist() == want


def implied_one_by_one(by_target: sp.csr_matrix) -> list[bool]:
    """Implied targets taken one at a time: t goes for a t' whose candidate set lies inside t's, smaller, or equal and
    earlier and not gone itself."""
    sets = [
        set(by_target.indices[by_target.indptr[t] : by_target.indptr[t + 1]].tolist())
        for t in range(by_target.shape[0])
    ]
    out = [False] * len(sets)
    for t, s in enumerate(sets):
        out[t] = any(
            r != t and q and q <= s and (len(q) < len(s) or (r < t and not out[r])) for r, q in enumerate(sets)
        )
    return out


@settings(max_examples=150, deadline=None, derandomize=True, database=None)
@given(n=st.integers(1, 8), m=st.integers(1, 20), seed=st.integers(0, 2**31 - 1), share=st.floats(0.05, 0.9))
def test_implied_targets_as_taken_one_at_a_time(n: int, m: int, seed: int, share: float) -> None:
    # equal candidate sets (the first stays), sets inside others, and targets no candidate sees
    rng = np.random.default_rng(seed)
    by_target = sp.csr_matrix(rng.random((m, n)) < share)
    assert presolve.implied_targets(by_target).tolist() == implied_one_by_one(by_target)
