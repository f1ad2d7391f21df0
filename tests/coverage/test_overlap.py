"""The registration-overlap relation by hand: the share rule, the minimum shared length, the link distance, the groups
and the links through openings (planner.coverage.overlap)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from planner.coverage.overlap import OverlapRule, overlap_adjacency, overlap_graph

# five 1-m pieces; c0 sees 0, 1, 2 (3 m), c1 sees 2, 3 (2 m), c2 sees 3, 4 (2 m). Shared: c0-c1 piece 2 (1 m), c1-c2
# piece 3 (1 m), c0-c2 nothing. Rule 30 %: 1 m >= 0.3 x min(3, 2) = 0.6 m for both pairs
A = sp.csr_matrix(np.array([[1, 1, 1, 0, 0], [0, 0, 1, 1, 0], [0, 0, 0, 1, 1]], dtype=bool))
ONE_M = np.ones(5)


def _pairs(adj: sp.csr_matrix) -> set[tuple[int, int]]:
    return {(int(i), int(j)) for i, j in zip(*sp.triu(adj, k=1).nonzero())}


def test_thirty_percent_links_the_chain_and_records_the_shared_length():
    adj, share = overlap_adjacency(A, ONE_M, OverlapRule(0.3))
    assert _pairs(adj) == {(0, 1), (1, 2)}
    assert (adj != adj.T).nnz == 0  # symmetric
    assert share[0, 1] == share[1, 2] == pytest.approx(1.0)


def test_sixty_percent_links_nothing():
    # 1 m < 0.6 x 2 m = 1.2 m for both pairs
    assert _pairs(overlap_adjacency(A, ONE_M, OverlapRule(0.6))[0]) == set()


def test_a_minimum_shared_length_above_the_shares_links_nothing():
    assert _pairs(overlap_adjacency(A, ONE_M, OverlapRule(0.3, min_shared_m=1.5))[0]) == set()
    assert _pairs(overlap_adjacency(A, ONE_M, OverlapRule(0.3, min_shared_m=1.0))[0]) == {(0, 1), (1, 2)}


def test_the_link_distance_drops_the_far_pair():
    # stations at x = 0, 4 and 10 m: c0-c1 4 m apart, c1-c2 6 m; a 5-m limit keeps c0-c1 only
    xy = np.array([[0.0, 0.0], [4.0, 0.0], [10.0, 0.0]])
    assert _pairs(overlap_adjacency(A, ONE_M, OverlapRule(0.3, max_link_m=5.0), xy=xy)[0]) == {(0, 1)}


def test_only_stations_of_one_group_are_related():
    assert _pairs(overlap_adjacency(A, ONE_M, OverlapRule(0.3), groups=["g", "h", "h"])[0]) == {(1, 2)}


def test_piece_lengths_weigh_the_share():
    # piece 2 only 0.5 m long: c0-c1 share 0.5 m against 0.3 x min(2.5, 1.5) = 0.45 m (linked); at 40 %, 0.5 < 0.6 (not
    # linked) while c1-c2 still share 1 m >= 0.4 x 1.5 = 0.6 m
    lengths = np.array([1.0, 1.0, 0.5, 1.0, 1.0])
    assert _pairs(overlap_adjacency(A, lengths, OverlapRule(0.3))[0]) == {(0, 1), (1, 2)}
    assert _pairs(overlap_adjacency(A, lengths, OverlapRule(0.4))[0]) == {(1, 2)}


def test_links_through_an_opening_join_with_no_shared_wall_but_keep_the_group_rule():
    links = sp.csr_matrix(([True, True], ([0, 2], [2, 0])), shape=(3, 3))
    adj, share = overlap_adjacency(A, ONE_M, OverlapRule(0.6), links=links)
    assert _pairs(adj) == {(0, 2)} and share[0, 2] == 0.0
    assert _pairs(overlap_adjacency(A, ONE_M, OverlapRule(0.6), groups=["g", "g", "h"], links=links)[0]) == set()


def test_graph_on_some_stations_carries_shared_and_length():
    xy = np.array([[0.0, 0.0], [3.0, 4.0], [10.0, 0.0]])
    g = overlap_graph(A, ONE_M, [0, 1, 2], OverlapRule(0.3), xy=xy)
    assert set(g.edges) == {(0, 1), (1, 2)}
    assert g.edges[0, 1]["shared_m"] == pytest.approx(1.0) and g.edges[0, 1]["length_m"] == pytest.approx(5.0)
    assert set(overlap_graph(A, ONE_M, [0, 2], OverlapRule(0.3)).edges) == set()  # c1, the bridge, left out


@pytest.mark.parametrize("seed", range(4))
def test_one_product_per_group_over_the_walls_equals_the_whole_product(seed):
    # random coverage over wall pieces of random lengths and floor patches (length 0), three groups: the relation and
    # the shared lengths, bit for bit, as one filtered product over every column with the group rule applied after
    from planner.coverage.gram import filtered_gram
    from planner.coverage.overlap import group_ids, link_filter

    rng = np.random.default_rng(seed)
    n, walls, floors = 60, 30, 40
    a = sp.csr_matrix(rng.random((n, walls + floors)) < 0.2)
    lengths = np.concatenate([rng.uniform(0.2, 1.5, walls), np.zeros(floors)])
    groups = [("Z", int(g)) for g in rng.integers(0, 3, n)]
    rule = OverlapRule(0.3)
    adj, share = overlap_adjacency(a, lengths, rule, groups)
    f = a.astype(np.float64)
    _, keep = link_filter(rule, np.asarray(f @ lengths).ravel(), group_ids(groups))
    whole = filtered_gram(f.tocsr(), lengths, keep)
    assert (share != whole).nnz == 0 and np.array_equal(share.data, whole.data)
    assert np.array_equal(share.indptr, whole.indptr) and np.array_equal(share.indices, whole.indices)
    assert (adj != (whole != 0)).nnz == 0
