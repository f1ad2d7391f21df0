"""The connected greedy (planner.solve.bundles through connectivity.connected_greedy): hand-checked answers,
and on random small instances a cover of every coverable target, one bundle per group, the same each run."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.coverage.overlap import OverlapRule, overlap_adjacency
from planner.solve.connectivity import components, connected_greedy, disconnected_groups
from planner.solve.greedy import connected_greedy_plan
from planner.solve.instance import CoverInstance

RULE = OverlapRule(0.3)


def matrix(cover: list[set[int]], n_targets: int) -> sp.csr_matrix:
    rows = [i for i, c in enumerate(cover) for _ in c]
    cols = [t for c in cover for t in sorted(c)]
    return sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(len(cover), n_targets))


def links(n: int, pairs: list[tuple[int, int]]) -> sp.csr_matrix:
    r = [i for i, j in pairs] + [j for i, j in pairs]
    c = [j for i, j in pairs] + [i for i, j in pairs]
    return sp.csr_matrix((np.ones(len(r), dtype=bool), (r, c)), shape=(n, n))


def test_bundles_grow_together_so_a_shared_target_goes_to_the_cheaper_group():
    # 8 unit pieces; group g: c0 sees 0-3, c1 sees 3-4 (shares 1 of its 2 pieces with c0: linked at 30 %);
    # group h: c2 sees 4-7. Both groups see piece 4. Taken: c0 (4 new; ties with c2 go to the lower index),
    # then c2 (4 new, against 1 for c1): 2 stations, each group one bundle, the optimum. Growing g alone
    # first for all g can see (the former greedy) took c1 as well: 3.
    inst = CoverInstance(
        matrix([{0, 1, 2, 3}, {3, 4}, {4, 5, 6, 7}], 8), np.ones(3), groups=("g", "g", "h"), target_length_m=np.ones(8)
    )
    r = connected_greedy_plan(inst, RULE)
    assert r.selected == (0, 2) and r.objective == 2.0


def test_a_bridge_through_a_station_that_adds_nothing():
    # one group, path c0 - c1 - c2 (given links); c0 sees targets 0, 1; c1 only 0; c2 only 2.
    # c0 first (2 new); its one linked station c1 adds nothing, so the bridge c1 -> c2 (2 stations, 1 new
    # target) is taken; c1 stays, it holds the bundle together: (0, 1, 2), the only connected cover.
    a = matrix([{0, 1}, {0}, {2}], 3)
    got = connected_greedy(a, links(3, [(0, 1), (1, 2)]), ["g"] * 3, np.ones(3), np.ones(3, dtype=bool))
    assert got == [0, 1, 2]


def test_a_group_stuck_in_the_wrong_component_is_fixed_and_the_pass_restarted():
    # group g: c0 (alone) sees 0, 1, 2; c1 (0, 1) and c2 (2, 3) linked. Group h: d0 = 3 sees 3 (alone),
    # d1 = 4 sees 4 (alone; the only seer of 4, so h is fixed to d1's component up front). The first pass
    # takes c0 (3 new) then d1, and target 3 is left to c2 and d0, both outside their group's component:
    # g (of c2, the lower index) is fixed to c2's component and the pass restarted: c1, c2, d1, optimal
    # (target 3 needs c2, as h cannot hold d0 beside d1; then c0 is out and 0, 1 need c1).
    a = matrix([{0, 1, 2}, {0, 1}, {2, 3}, {3}, {4}], 5)
    got = connected_greedy(a, links(5, [(1, 2)]), ["g", "g", "g", "h", "h"], np.ones(5), np.ones(5, dtype=bool))
    assert got == [1, 2, 4]


def test_no_connected_cover_is_none():
    # g must hold c0 (only seer of 0) and c1 (only seer of 1), which are not linked: no connected cover
    a = matrix([{0}, {1}], 2)
    assert connected_greedy(a, links(2, []), ["g", "g"], np.ones(2), np.ones(2, dtype=bool)) is None
    # linked, they are one: both taken
    assert connected_greedy(a, links(2, [(0, 1)]), ["g", "g"], np.ones(2), np.ones(2, dtype=bool)) == [0, 1]
    # a target no candidate sees cannot be covered at all
    assert connected_greedy(matrix([{0}], 2), links(1, []), ["g"], np.ones(1), np.ones(2, dtype=bool)) is None


def test_costs_turn_the_choice():
    # c0 sees 0-2 at cost 5; c1, c2, c3 one piece each at cost 1, all linked to each other (one group):
    # per unit of cost the singletons win (1 against 3/5), so all three are taken and c0 never is
    a = matrix([{0, 1, 2}, {0}, {1}, {2}], 3)
    adj = links(4, [(i, j) for i in range(4) for j in range(i + 1, 4)])
    got = connected_greedy(a, adj, ["g"] * 4, np.array([5.0, 1.0, 1.0, 1.0]), np.ones(3, dtype=bool))
    assert got == [1, 2, 3]


@st.composite
def instances(draw: st.DrawFn) -> tuple[sp.csr_matrix, list[str]]:
    n_cand = draw(st.integers(1, 12))
    n_targ = draw(st.integers(1, 10))
    cells = draw(st.lists(st.lists(st.booleans(), min_size=n_targ, max_size=n_targ), min_size=n_cand, max_size=n_cand))
    groups = draw(st.lists(st.sampled_from(["g", "h", "k"]), min_size=n_cand, max_size=n_cand))
    return sp.csr_matrix(np.array(cells, dtype=bool).reshape(n_cand, n_targ)), groups


@pytest.mark.slow
@settings(derandomize=True, max_examples=300, deadline=None)
@given(instances(), st.integers(0, 3))
def test_random_instances_give_a_connected_cover_of_every_coverable_target(case, starts):
    a, groups = case
    adj, _ = overlap_adjacency(a, np.ones(a.shape[1]), RULE, groups)
    need = np.asarray(a.sum(axis=0)).ravel() > 0  # the coverable targets
    got = connected_greedy(a, adj, groups, np.ones(a.shape[0]), need, starts)
    assert got == connected_greedy(a, adj, groups, np.ones(a.shape[0]), need, starts)  # the same every run
    one_part = all(len(components(adj, [i for i, g in enumerate(groups) if g == grp])) == 1 for grp in set(groups))
    if one_part:  # every needed target is then reachable by a bridge: a cover is always found
        assert got is not None
    if got is not None:
        assert got == sorted(set(got))
        assert np.asarray(a[got].sum(axis=0)).ravel()[need].all()
        assert not disconnected_groups(adj, groups, got)
