"""A block whose targets include floor patches (targets of no wall length, planner.plan.methods.with_columns): no ring
bound, one connected-greedy seed, no neighbour cuts and at most SURFACE_ROUNDS CP-SAT rounds; its plan still a
connected cover under a valid bound, and a walls-only block keeps its ring bound."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from planner.coverage.overlap import overlap_adjacency
from planner.solve import block
from planner.solve.connectivity import disconnected_groups
from planner.solve.decompose import block_solvers
from planner.solve.instance import CoverInstance
from planner.solve.milp import MilpOptions, solve
from tests.solve.test_connectivity_methods import RULE, WINDOWS, brute_force, instance


def _with_floor(inst: CoverInstance, floor: list[set[int]]) -> CoverInstance:
    """``inst`` with one floor patch per entry of ``floor`` (the candidates that see it), of length 0."""
    rows = [c for k, seers in enumerate(floor) for c in sorted(seers)]
    cols = [k for k, seers in enumerate(floor) for _ in seers]
    extra = sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(inst.shape[0], len(floor)))
    return CoverInstance(
        sp.hstack([inst.by_candidate, extra], format="csr"),
        inst.cost,
        groups=inst.groups,
        target_length_m=np.concatenate([inst.lengths_m, np.zeros(len(floor))]),
    )


def test_a_block_with_floor_patches_skips_the_ring_and_stays_a_connected_cover():
    walls = instance(WINDOWS, 12, ["g"] * 9)
    floored = _with_floor(walls, [{1, 2}, {3}, {5, 6}, {7}])
    o = MilpOptions(overlap=RULE)
    (solver,) = block_solvers(floored, o)[1]
    assert solver.surfaces and solver.ring is None
    (plain,) = block_solvers(walls, o)[1]
    assert not plain.surfaces and plain.ring is not None  # the walls alone: the ring bound as before
    r = solve(floored, o)
    plan = list(r.selected)
    seen = np.asarray(floored.by_candidate[plan].sum(axis=0)).ravel() > 0
    adj, _ = overlap_adjacency(floored.by_candidate, floored.lengths_m, RULE, floored.groups)
    assert seen.all() and not disconnected_groups(adj, floored.groups, plan)
    assert r.info["rounds"] <= block.SURFACE_ROUNDS
    assert r.bound is not None and r.bound <= r.objective
    best = brute_force(floored)  # the floor patches share no wall: links by the wall pieces alone
    assert best is not None and r.bound <= best <= r.objective
