"""Stitching tile plans by hand, and the LP bound with an implied row (planner.tiles.stitch)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from planner.tiles.bound import lp_bound
from planner.tiles.stitch import prune, stitch
from tests.solve.test_connectivity_methods import WINDOWS, instance
from tests.solve.test_local_search import _adjacency


def test_two_tile_plans_are_pruned_and_joined_into_the_chain():
    # windows j..j+3 of 12 pieces (j = 0..8), linked when at most 2 apart. Tile plans {0, 1, 2} and {6, 7, 8}:
    # pruning (fewest pieces first, ties by index) drops 1 (pieces 1..4 stay seen by 0 and 2, and 0-2 stay
    # linked) and 7 (6 and 8 cover 6..11 and stay linked); 4 then joins the parts {0, 2} and {6, 8}
    inst = instance(WINDOWS, 12, ["g"] * 9)
    a, adj = _adjacency(inst)
    got = stitch(a, adj, ["g"] * 9, [[0, 1, 2], [6, 7, 8]])
    assert got.selected == (0, 2, 4, 6, 8) and got.parts == {"g": 1}
    assert (got.union, got.pruned, got.added) == (6, 2, 1)
    assert (inst.coverage_count(got.selected) >= 1).all()


def test_prune_keeps_a_station_whose_removal_splits_its_group():
    # 0, 2, 4, 6, 8: every piece of 4..7 is also seen by 2 or 6, but without 4 the chain breaks in two
    inst = instance(WINDOWS, 12, ["g"] * 9)
    a, adj = _adjacency(inst)
    assert prune(a, adj, ["g"] * 9, [0, 2, 4, 6, 8]) == [0, 2, 4, 6, 8]


def test_lp_bound_drops_an_implied_row_and_keeps_the_optimum():
    # candidates x pieces: c0 and c1 see pieces 0, 1; c2 sees 1, 2. Piece 1 is seen by every candidate that
    # sees piece 0 (implied, dropped); x0 + x1 >= 1 and x2 >= 1 leave the optimum 2
    a = sp.csr_matrix(np.array([[1, 1, 0], [1, 1, 0], [0, 1, 1]], dtype=bool))
    assert lp_bound(a) == pytest.approx(2.0)
