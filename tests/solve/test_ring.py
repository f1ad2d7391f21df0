"""The ring bound: the cheapest walk over arcs equals the connected optimum when every station sees one run
of the ring (checked against enumeration and by hand), and stays below it when runs have holes."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.sparse as sp

from planner.coverage.overlap import OverlapRule, overlap_adjacency
from planner.solve.connectivity import disconnected_groups
from planner.solve.instance import CoverInstance
from planner.solve.milp import MilpOptions, solve
from planner.solve.ring import arcs, lagrangian_bound, ring_bound, ring_graph

RULE = OverlapRule(0.3)


def matrix(cover: list[set[int]], n: int) -> sp.csr_matrix:
    rows = [i for i, c in enumerate(cover) for _ in c]
    cols = [t for c in cover for t in sorted(c)]
    return sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(len(cover), n))


def adjacency(a: sp.csr_matrix) -> sp.csr_matrix:
    return overlap_adjacency(a, np.ones(a.shape[1]), RULE, ["g"] * a.shape[0])[0]


def enumerate_optimum(a: sp.csr_matrix, cost: np.ndarray) -> float:
    """Cheapest connected cover of every column, trying every subset (inf when there is none)."""
    adj, n = adjacency(a), a.shape[0]
    best = np.inf
    for size in range(1, n + 1):
        for subset in itertools.combinations(range(n), size):
            if (
                cost[list(subset)].sum() < best
                and a[list(subset)].getnnz(axis=0).all()
                and not disconnected_groups(adj, ["g"] * n, subset)
            ):
                best = float(cost[list(subset)].sum())
    return best


def ring_arcs(rng: np.random.Generator, n: int, m: int, holes: bool = False) -> list[set[int]]:
    """m arcs of 3..6 of n ring pieces (a hole punched inside some when ``holes``), drawn until all are seen."""
    while True:
        cover = []
        for _ in range(m):
            s, k = int(rng.integers(n)), int(rng.integers(3, 7))
            arc = {(s + j) % n for j in range(k)}
            if holes and k >= 5 and rng.random() < 0.5:
                arc.discard((s + 2) % n)
            cover.append(arc)
        if set().union(*cover) == set(range(n)):
            return cover


def test_hand_ring_needs_three_where_the_plain_cover_takes_two():
    # 12 unit pieces on a ring, arcs of 6 starting at 0, 3, 6, 9. Arcs 0 and 6 cover the ring (plain cover: 2)
    # but share nothing; neighbours share 3 m >= 0.3 * 6 = 1.8 m, so they are linked. A chain of arcs from
    # start 0 must reach piece 11: 0 -> 3 -> 6 covers 0..11, three stations.
    a = matrix([{(s + j) % 12 for j in range(6)} for s in (0, 3, 6, 9)], 12)
    r = ring_bound(a, np.ones(12, dtype=bool), adjacency(a), np.ones(4))
    assert r is not None and r.bound == 3 and len(r.walk) == 3 and r.exact_arcs == 4
    assert a[list(r.walk)].getnnz(axis=0).all()


def test_windows_on_a_line_are_a_chain_of_five():
    # 12 pieces on a line, windows j..j+3 (j = 0..8): linked when starts differ by <= 2 (share >= 2 of 4,
    # 0.3 * 4 = 1.2); read as a ring, windows 8 and 0 touch but share nothing, so the walk still runs
    # 0, 2, 4, 6, 8: 5 stations, the connected optimum of tests/solve/test_connectivity_methods.py
    a = matrix([set(range(j, j + 4)) for j in range(9)], 12)
    r = ring_bound(a, np.ones(12, dtype=bool), adjacency(a), np.ones(9))
    assert r is not None and r.bound == 5 and r.walk == (0, 2, 4, 6, 8)


def test_arcs_leave_out_the_widest_gap():
    # pieces {10, 11, 0, 1} of 12 wrap: arc 10..13; {2, 4, 5}: arc 2..5 with a hole at 3
    start, end, exact = arcs(matrix([{10, 11, 0, 1}, {2, 4, 5}], 12))
    assert start.tolist() == [10, 2] and end.tolist() == [13, 5] and exact.tolist() == [True, False]


@pytest.mark.parametrize("seed", range(8))
def test_walk_is_the_connected_optimum_of_whole_arcs(seed):
    rng = np.random.default_rng(seed)
    a = matrix(ring_arcs(rng, 14, 9), 14)
    cost = rng.integers(1, 4, size=9).astype(float)
    best = enumerate_optimum(a, cost)
    r = ring_bound(a, np.ones(14, dtype=bool), adjacency(a), cost)
    if not np.isfinite(best):
        assert r is None
        return
    assert r is not None and r.bound == pytest.approx(best)
    walk = list(r.walk)  # every arc whole: the walk is a plan of that cost
    assert a[walk].getnnz(axis=0).all() and not disconnected_groups(adjacency(a), ["g"] * 9, walk)
    assert cost[walk].sum() == pytest.approx(best)
    # turning the ring (starting the piece order elsewhere) changes nothing
    turned = a[:, np.roll(np.arange(14), 5)].tocsr()
    assert ring_bound(turned, np.ones(14, dtype=bool), adjacency(turned), cost).bound == pytest.approx(best)


@pytest.mark.parametrize("seed", range(8))
def test_bound_stays_below_the_optimum_with_holes(seed):
    rng = np.random.default_rng(100 + seed)
    a = matrix(ring_arcs(rng, 14, 10, holes=True), 14)
    best = enumerate_optimum(a, np.ones(10))
    r = ring_bound(a, np.ones(14, dtype=bool), adjacency(a), np.ones(10))
    if r is not None:
        assert r.bound <= best + 1e-9


def test_not_applicable_when_a_link_jumps_across_the_ring():
    # arcs 0..3 and 6..9 of 12 are linked by hand (an opening, say): their arcs neither overlap nor touch
    a = matrix([set(range(4)), set(range(6, 10)), set(range(3, 7)), {9, 10, 11, 0}], 12)
    adj = adjacency(a).tolil()
    adj[0, 1] = adj[1, 0] = True
    assert ring_bound(a, np.ones(12, dtype=bool), adj.tocsr(), np.ones(4)) is None


def test_solve_closes_a_ring_block_before_any_search():
    # the hand ring above as a site's block: the greedy or the walk gives 3, the walk bounds it by 3
    a = matrix([{(s + j) % 12 for j in range(6)} for s in (0, 3, 6, 9)], 12)
    inst = CoverInstance(a, np.ones(4), groups=("g",) * 4, target_length_m=np.ones(12))
    r = solve(inst, MilpOptions())
    off = solve(inst, MilpOptions(ring_bound=False))
    assert solve(inst, MilpOptions(overlap=None)).objective == 2
    assert r.status.value == "optimal" and r.objective == 3 and r.info["rounds"] == 0
    assert r.info["ring_bound"] == {
        "blocks": 1,
        "closed_before_search": 1,
        "lagrange_steps": 0,
        "work_capped_blocks": 0,
    }
    assert off.status.value == "optimal" and off.objective == 3 and off.info["ring_bound"]["blocks"] == 0


def test_lagrangian_bound_stays_below_the_optimum_and_can_pass_the_ring():
    # arcs with holes: L(lambda) = sum lambda + walk(max(rc, 0)) + sum min(rc, 0) is a lower bound for every
    # lambda >= 0 (planner.solve.ring.lagrangian_bound), from zero multipliers (L = the ring bound) upward
    passed = 0
    for seed in range(8):
        rng = np.random.default_rng(100 + seed)
        a = matrix(ring_arcs(rng, 14, 10, holes=True), 14)
        best = enumerate_optimum(a, np.ones(10))
        graph = ring_graph(a, np.ones(14, dtype=bool), adjacency(a))
        if graph is None or not np.isfinite(best):
            continue
        ring = graph.walk(np.ones(10)).bound
        value, steps = lagrangian_bound(graph, a.astype(float).tocsr(), np.ones(10), np.zeros(14), best, np.inf, 100)
        assert steps <= 100 and ring - 1e-6 <= value <= best + 1e-6
        for lam in rng.uniform(0, 0.6, size=(5, 14)):  # any multipliers, even ones with negative reduced costs
            rc = 1.0 - a.astype(float) @ lam
            w = graph.walk(np.maximum(rc, 0))
            assert lam.sum() + w.bound + np.minimum(rc, 0).sum() <= best + 1e-6
        passed += value > ring + 1e-6
    assert passed >= 1


def test_lagrangian_ascent_gives_up_when_no_step_raises_the_bound():
    # a ring of 5 pieces, arcs {0,1,2}, {2,3,4}, {4,0,1}: any two cover it and overlap in one of three pieces
    # (>= 30 %), so the connected optimum is 2. lambda = (0, 1, 0, 1, 0) is dual feasible (each arc sums to 1)
    # with sum 2, so L starts at 2 and, being a lower bound, never rises; toward the optimum itself, with no
    # stop level, the ascent stops after give_up steps (20 by default, 7 when asked) instead of all 200
    a = matrix([{0, 1, 2}, {2, 3, 4}, {4, 0, 1}], 5)
    graph = ring_graph(a, np.ones(5, dtype=bool), adjacency(a))
    assert graph is not None and enumerate_optimum(a, np.ones(3)) == 2
    sub, lam = a.astype(float).tocsr(), np.array([0.0, 1.0, 0.0, 1.0, 0.0])
    assert lagrangian_bound(graph, sub, np.ones(3), lam, 2.0, np.inf, 200) == (2.0, 20)
    assert lagrangian_bound(graph, sub, np.ones(3), lam, 2.0, np.inf, 200, give_up=7) == (2.0, 7)
    assert lagrangian_bound(graph, sub, np.ones(3), lam, 2.0, np.inf, 200, give_up=1000) == (2.0, 200)


@pytest.mark.parametrize("seed", range(4))
def test_solve_with_and_without_the_ring_bound_agree_with_enumeration(seed):
    # one zone-side, arcs with holes: the ring stage (walk, local search, Lagrangian ascent) and the cut loop
    # alone both end at the enumerated connected optimum
    rng = np.random.default_rng(200 + seed)
    a = matrix(ring_arcs(rng, 14, 10, holes=True), 14)
    best = enumerate_optimum(a, np.ones(10))
    inst = CoverInstance(a, np.ones(10), groups=("g",) * 10, target_length_m=np.ones(14))
    for ring in (True, False):
        r = solve(inst, MilpOptions(ring_bound=ring))
        if np.isfinite(best):
            assert r.status.value == "optimal" and r.objective == best, ring
        else:
            assert r.status.value in ("infeasible", "no_solution"), ring


@pytest.mark.parametrize("seed", range(4))
def test_a_work_budget_caps_the_ascent_and_the_answer_stays_right(seed, monkeypatch):
    # issue 32: the ascent's walks are counted (links of the lifted graph x sources, per step) against
    # block.RING_WORK. With no budget at all the ascent takes no step and says so for each block that wanted
    # some (as many as took steps without the cap); the solve still ends at the enumerated connected optimum
    # (the cut loop proves what the ring stage left open)
    import importlib

    block = importlib.import_module("planner.solve.block")
    rng = np.random.default_rng(200 + seed)
    a = matrix(ring_arcs(rng, 14, 10, holes=True), 14)
    best = enumerate_optimum(a, np.ones(10))
    inst = CoverInstance(a, np.ones(10), groups=("g",) * 10, target_length_m=np.ones(14))
    free = solve(inst, MilpOptions())
    monkeypatch.setattr(block, "RING_WORK", 0.0)
    capped = solve(inst, MilpOptions())
    assert free.info["ring_bound"]["work_capped_blocks"] == 0
    assert capped.info["ring_bound"]["lagrange_steps"] == 0
    assert capped.info["ring_bound"]["work_capped_blocks"] == int(free.info["ring_bound"]["lagrange_steps"] > 0)
    if np.isfinite(best):
        assert capped.status.value == "optimal" and capped.objective == free.objective == best


def _pairwise_lift(cover: sp.csr_matrix, adj: sp.csr_matrix) -> sp.csr_matrix | None:
    """The lifted link graph by its definition, as it was built before issue 32 (int64 lists, both directions
    per lift pair): copies i at lift ki and j at lift kj are linked when the lifted arcs overlap or touch."""
    from planner.solve.ring import _LIFTS

    m, n = cover.shape
    start, end, _ = arcs(cover)
    pairs = sp.triu(adj, k=1).tocoo()
    rows, cols = [], []
    for i, j in zip(pairs.row.tolist(), pairs.col.tolist()):
        if start[i] < 0 or start[j] < 0:
            return None
        for li, ki in enumerate(_LIFTS.tolist()):
            for lj, kj in enumerate(_LIFTS.tolist()):
                if start[j] + kj * n <= end[i] + ki * n + 1 and start[i] + ki * n <= end[j] + kj * n + 1:
                    rows += [li * m + i, lj * m + j]
                    cols += [lj * m + j, li * m + i]
    size = _LIFTS.size * m
    return sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(size, size))


@pytest.mark.parametrize("seed", range(12))
def test_ring_graph_is_the_pairwise_lift(seed):
    # issue 32: the lifted graph is built in 32-bit halves and mirrored once; its pattern must be the
    # definition's, pair by pair (random arcs of 3-9 pieces on a ring of 24, a ring of windows when even)
    rng = np.random.default_rng(seed)
    n = 24
    cover = [
        {(s + d) % n for d in range(int(rng.integers(3, 10)))}
        for s in rng.integers(0, n, size=int(rng.integers(5, 14)))
    ]
    cover += [set(range(j, j + 5)) for j in range(0, n - 4, 4)] + [{20, 21, 22, 23, 0}] if seed % 2 == 0 else []
    a = matrix(cover, n)
    required = np.ones(n, dtype=bool)
    g, want = ring_graph(a, required, adjacency(a)), _pairwise_lift(a, adjacency(a))
    assert g is not None and want is not None and want.nnz > 0  # every seed here has linked arcs
    assert g.graph.shape == want.shape
    assert (g.graph != want).nnz == 0 and g.graph.has_sorted_indices
