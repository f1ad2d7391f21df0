"""The MILP: hand-checkable covers, connectivity, k, combined precision, presolve, agreement of backends."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from planner.coverage.overlap import OverlapRule
from planner.solve.backends import BACKENDS
from planner.solve.instance import CoverInstance
from planner.solve.milp import MilpOptions, block_solvers, solve


def instance(cover: list[set[int]], n_targets: int, cost=None, groups=True, info=None) -> CoverInstance:
    rows = [i for i, c in enumerate(cover) for _ in c]
    cols = [t for c in cover for t in sorted(c)]
    a = sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(len(cover), n_targets))
    return CoverInstance(
        a,
        np.ones(len(cover)) if cost is None else np.asarray(cost, float),
        groups=tuple("g" for _ in cover) if groups else None,
        target_length_m=np.ones(n_targets),
        info=info,
    )


# targets 0..5 of unit length; c0 and c1 cover the halves and share nothing, so they cannot be
# registered; c2 = {2, 3} shares 1 m with each (>= 0.3 * min(3, 2) = 0.6 m): the bridge;
# c3 = {2} is dominated by c0 for the plain cover and is no bridge
BRIDGE = [{0, 1, 2}, {3, 4, 5}, {2, 3}, {2}]


@pytest.mark.parametrize("backend", BACKENDS)
def test_plain_cover_takes_two_connected_cover_needs_the_bridge(backend):
    plain = solve(instance(BRIDGE, 6), MilpOptions(backend=backend, overlap=None, time_limit_s=20))
    assert plain.status.value == "optimal" and plain.selected == (0, 1)
    conn = solve(instance(BRIDGE, 6), MilpOptions(backend=backend, overlap=OverlapRule(0.3), time_limit_s=20))
    assert conn.status.value == "optimal" and conn.selected == (0, 1, 2) and conn.bound == 3


def test_overlap_threshold_decides_the_link():
    # with 60 % required overlap, c2 shares 1 m of min(3, 2) = 2 m: 50 % < 60 %, no link at all:
    # no connected cover exists, and the solver must not claim one
    r = solve(instance(BRIDGE, 6), MilpOptions(overlap=OverlapRule(0.6), time_limit_s=10))
    assert r.status.value in ("infeasible", "no_solution")


@pytest.mark.parametrize("backend", BACKENDS)
def test_k_equals_two(backend):
    # four candidates each seeing the three targets: k = 2 takes exactly two
    cover = [{0, 1, 2}] * 4
    r = solve(instance(cover, 3, groups=False), MilpOptions(backend=backend, overlap=None, k=2, time_limit_s=20))
    assert r.status.value == "optimal" and len(r.selected) == 2


@pytest.mark.parametrize("backend", BACKENDS)
def test_combined_precision_adds_information(backend):
    # one target: c0, c1 each give (sigma_req/sigma)^2 = 0.5, c2 gives 1.0 but costs 3:
    # combined precision needs 0.5 + 0.5 >= 1 (cost 2); plain k = 1 would take c0 alone (cost 1)
    cover = [{0}, {0}, {0}]
    info = sp.csr_matrix(np.array([[0.5], [0.5], [1.0]]))
    inst = instance(cover, 1, cost=[1, 1, 3], groups=False, info=info)
    single = solve(inst, MilpOptions(backend=backend, overlap=None, time_limit_s=20))
    combined = solve(inst, MilpOptions(backend=backend, overlap=None, precision="combined", time_limit_s=20))
    assert single.objective == 1 and combined.objective == 2 and combined.selected == (0, 1)


def test_too_few_views_for_k_is_infeasible():
    r = solve(instance([{0}, {0, 1}], 2, groups=False), MilpOptions(overlap=None, k=2))
    assert r.status.value == "infeasible" and r.info["targets_seen_by_fewer_than_k"] == [1]


def test_presolve_keeps_the_connected_optimum():
    # a ring of 12 targets; candidates cover arcs of 3 (step 1) and singletons (dominated for the
    # plain cover); with and without presolve the connected optimum is the same
    arcs = [{(i + j) % 12 for j in range(3)} for i in range(12)]
    singles = [{i} for i in range(12)]
    inst = instance(arcs + singles, 12)
    with_p = solve(inst, MilpOptions(overlap=OverlapRule(0.3), time_limit_s=20))
    without = solve(inst, MilpOptions(overlap=OverlapRule(0.3), time_limit_s=20, presolve=False))
    assert with_p.status.value == without.status.value == "optimal"
    assert with_p.objective == without.objective
    assert with_p.info["presolve"]["dominated_removed"] >= 12


def test_solve_takes_keywords():
    r = solve(instance(BRIDGE, 6), backend="scip", time_limit_s=10, seed=1, threads=1)
    assert r.backend == "scip" and r.selected == (0, 1, 2)


def test_repeated_presolve_keeps_a_bridge_that_covers_only_implied_targets():
    # c0, c1, c3 are the only seers of pieces 0, 8, 9; c2 = {3, 4, 5} links all three (1 m shared each,
    # >= 0.3 * 2 m) and no two of them share wall. Once pieces 3, 4, 5 are implied by 0, 9, 8 (their
    # other seers see nothing else there), c2 covers no kept target but is still the only bridge
    cover = [{0, 1, 2, 3}, {5, 6, 7, 8}, {3, 4, 5}, {4, 9}]
    inst = instance(cover, 10)
    with_p = solve(inst, MilpOptions(overlap=OverlapRule(0.3), time_limit_s=20))
    without = solve(inst, MilpOptions(overlap=OverlapRule(0.3), time_limit_s=20, presolve=False))
    assert with_p.status.value == without.status.value == "optimal"
    assert with_p.selected == without.selected == (0, 1, 2, 3)
    assert with_p.info["presolve"]["targets_out"] <= 5  # 3, 4, 5 and more were implied away


def test_repeated_presolve_drops_what_the_first_pass_cannot():
    # the ring of test_presolve_keeps_the_connected_optimum: removing the singletons makes targets
    # implied; the connected optimum stays
    arcs = [{(i + j) % 12 for j in range(3)} for i in range(12)]
    inst = instance(arcs + [{i} for i in range(12)], 12)
    r = solve(inst, MilpOptions(overlap=OverlapRule(0.3), time_limit_s=20))
    full = solve(inst, MilpOptions(overlap=OverlapRule(0.3), time_limit_s=20, presolve=False))
    assert r.status.value == "optimal" and r.objective == full.objective


@pytest.mark.parametrize("backend", BACKENDS)
def test_presolve_forces_every_view_k_2_needs(backend):
    # k = 2: piece 0 is seen by c0 and c1 only, piece 1 by c0 and c2 only, so every candidate is needed
    r = solve(
        instance([{0, 1}, {0}, {1}], 2, groups=False), MilpOptions(backend=backend, overlap=None, k=2, time_limit_s=20)
    )
    assert r.status.value == "optimal" and r.selected == (0, 1, 2) and r.objective == 3


def test_independent_blocks_add_up():
    # the windows j..j+3 of 12 pieces (connected optimum 5: 0, 2, 4, 6, 8) twice, on pieces 0..11 in group g
    # and 12..23 in group h: two blocks that share no piece; objective and bound are 5 + 5, proven in both
    windows = [set(range(j, j + 4)) for j in range(9)]
    cover = windows + [{t + 12 for t in w} for w in windows]
    rows = [i for i, c in enumerate(cover) for _ in c]
    cols = [t for c in cover for t in sorted(c)]
    a = sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(18, 24))
    inst = CoverInstance(a, np.ones(18), groups=tuple("g" * 9 + "h" * 9), target_length_m=np.ones(24))
    r = solve(inst, MilpOptions(overlap=OverlapRule(0.3), time_limit_s=20))
    assert r.status.value == "optimal" and r.objective == r.bound == 10
    assert r.selected == (0, 2, 4, 6, 8, 9, 11, 13, 15, 17)
    _, blocks = block_solvers(inst, MilpOptions(overlap=OverlapRule(0.3)))
    assert len(blocks) == 2


def _blocks_by_products(a, keep_c, keep_t, groups):
    """The blocks as they were found before issue 32: candidates joined through shared targets and through the
    candidate x candidate "same group" product."""
    from scipy.sparse.csgraph import connected_components

    from planner.solve.presolve import group_ids

    sub = a[keep_c][:, keep_t]
    nc, nt = sub.shape
    links = [sp.bmat([[None, sub], [sub.T, None]]).tocsr()]
    if groups is not None:
        gid = group_ids([groups[i] for i in keep_c])
        g = sp.csr_matrix((np.ones(nc), (np.arange(nc), gid)), shape=(nc, int(gid.max(initial=-1)) + 1))
        links.append(sp.block_diag([(g @ g.T).astype(bool), sp.csr_matrix((nt, nt))]).tocsr())
    n, label = connected_components(sum(links), directed=False)
    out = []
    for b in range(n):
        members = np.flatnonzero(label == b)
        bc, bt = keep_c[members[members < nc]], keep_t[members[members >= nc] - nc]
        if bt.size:
            out.append((bc, bt))
    return sorted(out, key=lambda b: b[0].size * b[1].size)


@pytest.mark.parametrize("seed", range(20))
def test_blocks_through_group_nodes_are_the_product_blocks(seed):
    # issue 32: the blocks' "same group" links are group nodes now, not a kept x kept product; the blocks and
    # their order must be the old ones (random sparse covers of 6-40 candidates over 5-30 pieces, 1-4 groups,
    # random kept subsets; with and without groups)
    from planner.solve.decompose import _blocks

    rng = np.random.default_rng(seed)
    m, n = int(rng.integers(6, 41)), int(rng.integers(5, 31))
    a = sp.random(m, n, density=float(rng.uniform(0.03, 0.2)), random_state=seed, format="csr").astype(bool)
    keep_c = np.sort(rng.choice(m, size=int(rng.integers(1, m + 1)), replace=False))
    keep_t = np.sort(rng.choice(n, size=int(rng.integers(1, n + 1)), replace=False))
    for groups in (tuple(str(g) for g in rng.integers(0, int(rng.integers(1, 5)), size=m)), None):
        got, want = _blocks(a, keep_c, keep_t, groups), _blocks_by_products(a, keep_c, keep_t, groups)
        assert len(got) == len(want)
        for (gc, gt), (wc, wt) in zip(got, want):
            assert np.array_equal(gc, wc) and np.array_equal(gt, wt)


def test_a_relation_given_whole_replaces_the_rules():
    # BRIDGE under the 30 % rule links c2 with c0 and c1 (see above): given that relation whole, the connected
    # optimum is the rule's {0, 1, 2}; given no link at all, no connected cover of two or more stations exists;
    # given c0 - c1 linked directly, the plain cover {0, 1} is connected
    from dataclasses import replace

    from planner.coverage.overlap import overlap_adjacency

    base = instance(BRIDGE, 6)
    rule = OverlapRule(0.3)
    adj, _ = overlap_adjacency(base.by_candidate, np.ones(6), rule, base.groups)
    same = solve(replace(base, relation=adj), MilpOptions(overlap=rule, time_limit_s=10))
    assert same.status.value == "optimal" and same.selected == (0, 1, 2)
    none = solve(replace(base, relation=sp.csr_matrix((4, 4), dtype=bool)), MilpOptions(overlap=rule, time_limit_s=10))
    assert none.status.value in ("infeasible", "no_solution")
    direct = sp.csr_matrix((np.ones(2, dtype=bool), ([0, 1], [1, 0])), shape=(4, 4))
    pair = solve(replace(base, relation=direct), MilpOptions(overlap=rule, time_limit_s=10))
    assert pair.status.value == "optimal" and pair.selected == (0, 1)
    with pytest.raises(ValueError, match="relation"):
        replace(base, relation=sp.csr_matrix((3, 3), dtype=bool))
