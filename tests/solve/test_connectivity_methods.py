"""Registration connectivity by branch-and-cut, flow and the cut loop: every method finds the connected
optimum derived by hand or by enumerating every subset; the connected greedy is registrable."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.sparse as sp

from planner.core.errors import UsageError
from planner.coverage.overlap import OverlapRule, overlap_adjacency
from planner.solve.connectivity import disconnected_groups
from planner.solve.greedy import connected_greedy_plan
from planner.solve.instance import CoverInstance
from planner.solve.milp import MilpOptions, solve

RULE = OverlapRule(0.3)
#: (backend, connectivity) pairs measured side by side; bc needs SCIP's constraint handler (PySCIPOpt)
METHODS = [
    ("pyscipopt", "bc"),
    ("pyscipopt", "flow"),
    ("pyscipopt", "loop"),
    ("cpsat", "flow"),
    ("cpsat", "loop"),
    ("scip", "flow"),
    ("scip", "loop"),
    ("highs", "flow"),
    ("highs", "loop"),
]


def instance(cover: list[set[int]], n_targets: int, groups: list[str]) -> CoverInstance:
    rows = [i for i, c in enumerate(cover) for _ in c]
    cols = [t for c in cover for t in sorted(c)]
    a = sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(len(cover), n_targets))
    return CoverInstance(a, np.ones(len(cover)), groups=tuple(groups), target_length_m=np.ones(n_targets))


def brute_force(inst: CoverInstance) -> int | None:
    """Fewest stations of a cover whose every group is connected under RULE, by trying every subset
    (coverage as bit masks; the overlap relation from the planner's own adjacency)."""
    a = inst.by_candidate.tocsr()
    adj, _ = overlap_adjacency(a, inst.target_length_m, RULE, inst.groups)
    n, full = a.shape[0], (1 << a.shape[1]) - 1
    mask = [sum(1 << int(t) for t in a.indices[a.indptr[i] : a.indptr[i + 1]]) for i in range(n)]
    for size in range(1, n + 1):
        for subset in itertools.combinations(range(n), size):
            union = 0
            for i in subset:
                union |= mask[i]
            if union == full and not disconnected_groups(adj, inst.groups, subset):
                return size
    return None


# 12 unit pieces on a line; candidate j sees pieces j..j+3 (j = 0..8). The plain cover takes
# j = 0, 4, 8 (3 stations). Two windows are linked when they share >= 0.3 * 4 = 1.2 m, i.e. their
# starts differ by at most 2; a chain from j = 0 (the only seer of piece 0) to j = 8 (the only
# seer of piece 11) in steps of at most 2 needs 0, 2, 4, 6, 8: 5 stations.
WINDOWS = [set(range(j, j + 4)) for j in range(9)]


@pytest.mark.parametrize("backend,connectivity", METHODS)
def test_windows_on_a_line_need_a_chain_of_five(backend, connectivity):
    inst = instance(WINDOWS, 12, ["g"] * 9)
    plain = solve(inst, MilpOptions(backend=backend, overlap=None))
    # the ring bound (tests/solve/test_ring.py) would close this one-group block before the method runs
    r = solve(inst, MilpOptions(backend=backend, connectivity=connectivity, ring_bound=False))
    assert plain.objective == 3 and r.status.value == "optimal" and r.objective == 5 and r.bound == 5
    assert r.selected == (0, 2, 4, 6, 8) and r.info["connectivity"] == connectivity


def random_instance(seed: int) -> CoverInstance:
    """Two zone-sides: a ring of 12 pieces (8 arcs) and a line of 9 pieces (6 windows), arcs of 3..5
    pieces, drawn again until every piece is seen; the last ring candidate also sees the line's
    first piece, so the sides share a target (it is essential to neither)."""
    rng = np.random.default_rng(seed)
    while True:
        cover, groups = [], []
        for _ in range(8):
            s, k = int(rng.integers(12)), int(rng.integers(3, 6))
            cover.append({(s + j) % 12 for j in range(k)})
            groups.append("ring")
        for _ in range(6):
            s, k = int(rng.integers(9)), int(rng.integers(3, 6))
            cover.append({12 + min(s + j, 8) for j in range(k)})
            groups.append("line")
        cover[7].add(12)
        if set().union(*cover) == set(range(21)):
            return instance(cover, 21, groups)


#: the strengthening rows, tried on one method per connectivity model
EXTRAS = [("pyscipopt", "bc", True), ("cpsat", "loop", True), ("highs", "flow", True), ("scip", "loop", False)]


class _Enumerated(dict):
    """Enumerated optimum of each seed's instance, computed once."""

    def __missing__(self, seed: int) -> int | None:
        self[seed] = brute_force(random_instance(seed))
        return self[seed]


FOUND = _Enumerated()


@pytest.mark.parametrize("seed", [0, *(pytest.param(s, marks=pytest.mark.slow) for s in range(1, 6))])
def test_methods_agree_with_enumeration(seed):
    inst = random_instance(seed)
    best = FOUND[seed]
    for backend, connectivity, extras in [(b, c, False) for b, c in METHODS] + EXTRAS:
        for tree_bound in (False, True) if extras else (False,):
            r = solve(
                inst,
                MilpOptions(
                    backend=backend,
                    connectivity=connectivity,
                    tree_bound=tree_bound,
                    layer_cuts=extras,
                ),
            )
            label = (backend, connectivity, tree_bound, extras)
            if best is None:
                assert r.status.value in ("infeasible", "no_solution"), label
            else:
                assert r.status.value == "optimal" and r.objective == best, label


@pytest.mark.parametrize("seed", range(6))
def test_connected_greedy_is_registrable_and_never_below_the_optimum(seed):
    inst = random_instance(seed)
    best = FOUND[seed]
    g = connected_greedy_plan(inst, RULE)
    if best is None:
        assert g.status.value == "infeasible"
        return
    a = inst.by_candidate.tocsr()
    adj, _ = overlap_adjacency(a, inst.target_length_m, RULE, inst.groups)
    assert np.asarray(a[list(g.selected)].sum(axis=0)).ravel().all()
    assert not disconnected_groups(adj, inst.groups, g.selected)
    assert g.objective >= best


def test_windows_greedy_is_the_chain():
    # the connected greedy starts at a window and adds linked windows (steps of at most 2: a step of 3 shares
    # 1 of 4 pieces < 30 %); windows 0 and 8 are the only seers of pieces 0 and 11, so the chain 0, 2, 4, 6, 8
    # is the connected optimum, and the greedy finds it
    inst = instance(WINDOWS, 12, ["g"] * 9)
    g = connected_greedy_plan(inst, RULE)
    assert g.selected == (0, 2, 4, 6, 8) and g.info["connected"]
    assert (inst.coverage_count(g.selected) >= 1).all()


def test_branch_and_cut_needs_pyscipopt():
    with pytest.raises(UsageError):
        MilpOptions(backend="cpsat", connectivity="bc")


def test_the_random_instances_are_not_trivial():
    # seeds 0..5: four have a connected cover, each dearer than the plain cover; two have none
    found = [FOUND[seed] for seed in range(6)]
    plain = [solve(random_instance(seed), MilpOptions(overlap=None)).objective for seed in range(6)]
    assert sum(f is not None for f in found) == 4
    assert all(f > p for f, p in zip(found, plain) if f is not None)


@pytest.mark.parametrize("seed", range(6))
def test_two_cpsat_workers_agree_with_enumeration(seed):
    """threads = 2 runs two CP-SAT workers (full LP first); the cut loop still proves the enumerated optimum."""
    inst = random_instance(seed)
    r = solve(inst, MilpOptions(backend="cpsat", connectivity="loop", threads=2))
    if FOUND[seed] is None:
        assert r.status.value in ("infeasible", "no_solution")
    else:
        assert r.status.value == "optimal" and r.objective == FOUND[seed]


def test_component_cut_needs_a_neighbour_of_the_component():
    """Windows 0 and 1 chosen alone (a part that cannot see piece 11): the cuts include
    x_2 + x_3 >= x_0 + x_1 - 1 (window 0's and 1's other neighbours), and every cut holds on the chain."""
    from planner.solve.connectivity import connectivity_cuts, essential_targets

    inst = instance(WINDOWS, 12, ["g"] * 9)
    a = inst.by_candidate.tocsr()
    adj, _ = overlap_adjacency(a, inst.target_length_m, RULE, inst.groups)
    ess = essential_targets(a, inst.groups)["g"]
    cuts = connectivity_cuts(adj, [[0, 1], [8]], a, ess)
    found = {(tuple(int(i) for i in idx), tuple(float(c) for c in coef), lb) for idx, coef, lb in cuts}
    assert ((2, 3, 0, 1), (1.0, 1.0, -1.0, -1.0), -1.0) in found
    chain = np.zeros(9)
    chain[[0, 2, 4, 6, 8]] = 1
    assert all(float(coef @ chain[idx]) >= lb for idx, coef, lb in cuts)
