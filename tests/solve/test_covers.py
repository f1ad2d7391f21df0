"""The cover methods behind one protocol (planner.solve.covers): each gives a cover of the same instance, the
MILP's no larger than the others', the connected ones registrable, and the plain ones refuse a rule."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from planner.core.errors import UsageError
from planner.coverage.overlap import OverlapRule
from planner.solve.backends import CAPABILITIES, NODE_LIMITED
from planner.solve.covers import COVERS
from planner.solve.instance import CoverInstance
from planner.solve.result import Status
from tests.solve.test_connected_greedy import matrix
from tests.solve.test_work_limit import random_cover

RULE = OverlapRule(0.3)


def covers(a: sp.csr_matrix, selected: tuple[int, ...]) -> bool:
    return bool(np.all(np.asarray(a[list(selected)].sum(axis=0)).ravel() > 0))


def test_every_method_covers_the_plain_instance_and_the_milp_is_smallest() -> None:
    inst = random_cover(5, n_cand=120, n_targ=200, density=0.03)
    results = {name: cover(inst, None) for name, cover in COVERS.items()}
    assert all(covers(inst.by_candidate, r.selected) for r in results.values())
    assert results["milp"].status is Status.OPTIMAL
    assert all(results["milp"].objective <= r.objective for r in results.values())
    assert results["milp"].stats is not None and results["greedy"].stats is None
    assert results["milp"].info["work"] == {**vars(results["milp"].stats.work)}


def test_the_connected_methods_keep_each_group_one_bundle_and_the_plain_ones_refuse_the_rule() -> None:
    # one group, a chain c0 - c1 - c2 of shared pieces; c0 and c2 alone cover everything but are not linked
    inst = CoverInstance(
        matrix([{0, 1, 2}, {2, 3}, {3, 4, 5}], 6), np.ones(3), groups=("g", "g", "g"), target_length_m=np.ones(6)
    )
    for name in ("connected-greedy", "milp"):
        assert COVERS[name](inst, RULE).selected == (0, 1, 2), name
    for name in ("greedy", "cft"):
        assert COVERS[name](inst, None).selected == (0, 2), name
        with pytest.raises(UsageError):
            COVERS[name](inst, RULE)


def test_backends_are_told_apart_by_their_capabilities() -> None:
    assert [n for n, c in CAPABILITIES.items() if c.work_limit] == ["cpsat"]
    assert NODE_LIMITED == ("scip", "pulp-cbc", "pyscipopt")
    assert [n for n, c in CAPABILITIES.items() if c.branch_and_cut] == ["pyscipopt"]
