"""Joining a cover's parts by linking stations (planner.solve.steiner)."""

from __future__ import annotations

import itertools

import numpy as np
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.solve.connectivity import components
from planner.solve.steiner import steiner_join


def _graph(n: int, edges: list[tuple[int, int]]) -> sp.csr_matrix:
    rows = [u for u, v in edges] + [v for u, v in edges]
    cols = [v for u, v in edges] + [u for u, v in edges]
    return sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(n, n))


def test_a_path_is_joined_by_its_middle_stations() -> None:
    # 0 - 1 - 2 - 3 - 4 and 0 - 5 - 6 - 4: the chosen 0 and 4 are joined by the shorter chain 5, 6 (two
    # stations), not 1, 2, 3 (three)
    adj = _graph(7, [(0, 1), (1, 2), (2, 3), (3, 4), (0, 5), (5, 6), (6, 4)])
    assert steiner_join(adj, ["g"] * 7, [0, 4]) == [0, 4, 5, 6]


def test_three_parts_share_one_hub() -> None:
    # a star: 0, 1, 2 each linked only to the hub 3; one station (the hub) joins all three
    adj = _graph(4, [(0, 3), (1, 3), (2, 3)])
    assert steiner_join(adj, ["g"] * 4, [0, 1, 2]) == [0, 1, 2, 3]


def test_groups_are_joined_apart_and_none_when_impossible() -> None:
    adj = _graph(6, [(0, 1), (1, 2), (3, 4)])
    groups = ["a", "a", "a", "b", "b", "b"]
    assert steiner_join(adj, groups, [0, 2, 3, 4]) == [0, 1, 2, 3, 4]
    assert steiner_join(adj, groups, [3, 5]) is None  # 5 is linked to nothing


def _best_join(adj: sp.csr_matrix, chosen: list[int]) -> int | None:
    """Brute force: the fewest stations to add so that ``chosen`` is connected (None: impossible)."""
    others = [v for v in range(adj.shape[0]) if v not in chosen]
    for k in range(len(others) + 1):
        for extra in itertools.combinations(others, k):
            if len(components(adj, chosen + list(extra))) <= 1:
                return k
    return None


@settings(max_examples=60, deadline=None)
@given(
    n=st.integers(3, 8),
    data=st.data(),
)
def test_the_join_is_connected_and_never_below_the_fewest_stations(n: int, data: st.DataObject) -> None:
    pairs = list(itertools.combinations(range(n), 2))
    edges = data.draw(st.lists(st.sampled_from(pairs), unique=True, max_size=len(pairs)))
    chosen = data.draw(st.lists(st.integers(0, n - 1), unique=True, min_size=1, max_size=n))
    adj = _graph(n, edges)
    out = steiner_join(adj, ["g"] * n, chosen)
    best = _best_join(adj, sorted(chosen))
    if best is None:
        assert out is None
        return
    assert out is not None and set(chosen) <= set(out)
    assert len(components(adj, out)) == 1
    assert len(out) - len(chosen) >= best  # the brute force's fewest is a floor the heuristic cannot beat
