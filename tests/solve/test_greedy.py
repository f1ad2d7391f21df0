"""Chvatal's greedy: cost per newly covered target, weights, the targets to cover (planner.solve.greedy)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from planner.solve.greedy import greedy_cover

# c0 sees targets 0, 1, 2 at cost 5; c1, c2, c3 see one target each at cost 1
A = sp.csr_matrix(np.array([[1, 1, 1], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=bool))


def test_weights_turn_the_choice():
    # unweighted: c0 covers 3 targets for 1 station (1/3 a target) and is taken alone
    plain = greedy_cover(A)
    assert plain.selected == (0,) and plain.objective == 1
    # weighted: c0 costs 5 / 3 = 1.67 a target, the singletons 1 / 1: the three singletons, cost 3
    weighted = greedy_cover(A, weights=[5.0, 1.0, 1.0, 1.0])
    assert weighted.selected == (1, 2, 3) and weighted.objective == 3.0


def test_only_the_targets_to_cover_count():
    # only target 1 must be covered: c0 and c2 both cover it (1 target each); the tie goes to the lower
    # index, c0, unweighted, and to c2 (cost 1 against 5) weighted
    must = np.array([False, True, False])
    assert greedy_cover(A, must_cover=must).selected == (0,)
    assert greedy_cover(A, must_cover=must, weights=[5.0, 1.0, 1.0, 1.0]).selected == (2,)
