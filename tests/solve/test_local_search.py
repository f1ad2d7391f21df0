"""The swap local search keeps plans connected covers, never grows them, is deterministic, and finds the
smaller connected plans derived by hand or by enumeration."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from planner.coverage.overlap import overlap_adjacency
from planner.solve.connectivity import disconnected_groups
from planner.solve.greedy import connected_greedy_plan
from planner.solve.local_search import shrink
from planner.solve.milp import MilpOptions, solve
from tests.solve.test_connectivity_methods import FOUND, RULE, WINDOWS, instance, random_instance


def _adjacency(inst):
    a = inst.by_candidate.tocsr()
    adj, _ = overlap_adjacency(a, inst.target_length_m, RULE, inst.groups)
    return a, adj


def _is_connected_cover(inst, adj, plan) -> bool:
    seen = np.asarray(inst.by_candidate[list(plan)].sum(axis=0)).ravel() > 0
    return bool(seen.all()) and not disconnected_groups(adj, inst.groups, plan)


def test_windows_chain_of_seven_shrinks_to_the_chain_of_five():
    # windows j..j+3 on 12 pieces (see test_connectivity_methods): 0,1,2,4,5,6,8 is a connected cover of
    # 7 (steps of at most 2); 1 and 5 are redundant, and the connected optimum is 0,2,4,6,8 (5 stations)
    inst = instance(WINDOWS, 12, ["g"] * 9)
    a, adj = _adjacency(inst)
    plan = [0, 1, 2, 4, 5, 6, 8]
    assert _is_connected_cover(inst, adj, plan)
    assert shrink(a, adj, inst.groups, plan) == [0, 2, 4, 6, 8]


def test_a_swap_is_needed_to_reach_two_stations():
    # pieces 0..3; c0 = {0, 1}, c1 = {2, 3} (linked), c2 = {0}, c3 = {1, 2}, c4 = {3}; links by hand:
    # c0-c1, c2-c3, c3-c4. The chain c2, c3, c4 is a minimal connected cover of 3 (no station can go
    # without losing a piece), so 2 is reached only by dropping one and swapping: c0, c1
    cover = [{0, 1}, {2, 3}, {0}, {1, 2}, {3}]
    inst = instance(cover, 4, ["g"] * 5)
    a = inst.by_candidate.tocsr()
    adj = sp.csr_matrix(np.array([[0, 1, 0, 0, 0], [1, 0, 0, 0, 0], [0, 0, 0, 1, 0], [0, 0, 1, 0, 1],
                                  [0, 0, 0, 1, 0]], dtype=bool))
    assert shrink(a, adj, inst.groups, [2, 3, 4]) == [0, 1]
    # with the floor at 3 (a proven bound) nothing is tried
    assert shrink(a, adj, inst.groups, [2, 3, 4], floor=3) == [2, 3, 4]


@pytest.mark.parametrize("seed", range(6))
def test_from_the_connected_greedy_stays_a_connected_cover_not_below_the_optimum(seed):
    inst = random_instance(seed)
    a, adj = _adjacency(inst)
    greedy = connected_greedy_plan(inst, RULE, starts=1)
    if FOUND[seed] is None:
        pytest.skip("no connected cover")
    plan = shrink(a, adj, inst.groups, list(greedy.selected))
    assert _is_connected_cover(inst, adj, plan)
    assert FOUND[seed] <= len(plan) <= len(greedy.selected)
    assert shrink(a, adj, inst.groups, list(greedy.selected)) == plan  # no clock, no random numbers


def test_milp_closes_on_the_local_search_plan_and_reports_its_moves():
    # the windows: the first round's bound is 5 (the chain is forced by the cuts up front); either the
    # round's answer or the local search's plan meets it, and the result is optimal with 5 stations
    inst = instance(WINDOWS, 12, ["g"] * 9)
    r = solve(inst, MilpOptions(time_limit_s=20))
    off = solve(inst, MilpOptions(time_limit_s=20, local_search_moves=0))
    assert r.status.value == off.status.value == "optimal" and r.objective == off.objective == 5
    assert "local_search_moves" in r.info and off.info["local_search_moves"] == 0
