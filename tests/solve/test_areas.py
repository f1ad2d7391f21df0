"""Area rows: a connected block whose targets fall into areas no candidate sees across gets each area's plain-cover
minimum as a row and their sum as a bound; the connected optimum is unchanged."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import scipy.sparse as sp

from planner.coverage.overlap import OverlapRule
from planner.solve.areas import area_rows, target_areas
from planner.solve.instance import CoverInstance
from planner.solve.milp import MilpOptions, block_solvers, solve


def matrix(cover: list[set[int]], n: int) -> sp.csr_matrix:
    rows = [i for i, c in enumerate(cover) for _ in c]
    cols = [t for c in cover for t in sorted(c)]
    return sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(len(cover), n))


# two rooms: targets 0..3 (c0 and c1 each see one half, c2 sees all four) and targets 4..7 (c3, c4 halves, c5 all);
# c6 sees nothing of either room's walls but target 8, a door jamb seen from c6 alone. Links (openings): c2 - c6,
# c6 - c4, c0 - c1, c3 - c4
ROOMS = [{0, 1}, {2, 3}, {0, 1, 2, 3}, {4, 5}, {6, 7}, {4, 5, 6, 7}, {8}]
LINKS = [(2, 6), (6, 4), (0, 1), (3, 4)]


def rooms() -> CoverInstance:
    n = len(ROOMS)
    r, c = zip(*LINKS)
    rel = sp.csr_matrix((np.ones(2 * len(LINKS), dtype=bool), (r + c, c + r)), shape=(n, n))
    return CoverInstance(matrix(ROOMS, 9), np.ones(n), groups=("g",) * n, target_length_m=np.ones(9), relation=rel)


def test_areas_are_the_components_of_co_seen_targets():
    n, label = target_areas(matrix(ROOMS, 9))
    assert n == 3 and len(set(label[:4])) == 1 and len(set(label[4:8])) == 1 and label[0] != label[4] != label[8]


def test_rows_hold_each_areas_minimum():
    found = area_rows(matrix(ROOMS, 9), np.ones(7))
    assert found is not None and found.minimum == (1.0, 1.0, 1.0) and found.bound == 3.0
    assert [sorted(r[0].tolist()) for r in found.rows] == [[0, 1, 2], [3, 4, 5], [6]]


def test_weighted_minimum_and_one_area_gives_none():
    found = area_rows(matrix(ROOMS, 9), np.array([1.0, 1.0, 5.0, 2.0, 2.0, 3.5, 1.0]))
    assert found is not None and found.minimum == (2.0, 3.5, 1.0)
    assert area_rows(matrix([{0, 1}, {1, 2}], 3), np.ones(2)) is None


def test_connected_optimum_is_kept_and_bound_raised():
    # the connected optimum takes c2, c6 and c4 and then c3 (c4 alone misses 4, 5; c5 is linked to nobody)
    inst = rooms()
    rule = OverlapRule(0.3)
    on = solve(inst, MilpOptions(overlap=rule, time_limit_s=10, area_rows=True))
    off = solve(inst, MilpOptions(overlap=rule, time_limit_s=10))
    assert on.status.value == off.status.value == "optimal"
    assert on.objective == off.objective == 4.0 and on.selected == (2, 3, 4, 6)
    _, blocks = block_solvers(
        replace(inst), MilpOptions(overlap=rule, presolve=False, ring_bound=False, area_rows=True)
    )
    assert len(blocks) == 1 and blocks[0].areas is not None and blocks[0].bound >= 3.0
