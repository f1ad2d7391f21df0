"""The induced subgraph of a few stations read from their rows (:func:`planner.solve.bundles.induced`) against
scipy's own selection ``adj[nodes][:, nodes]``: the same entries, so the same components."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from planner.solve.bundles import induced
from planner.solve.connectivity import components


@pytest.mark.parametrize("seed", range(8))
def test_induced_equals_scipys_selection(seed: int) -> None:
    # random symmetric relations (some with rows left empty), any order of the nodes, none to all of them; a node
    # listed twice and a relation not in CSR go to scipy's selection
    rng = np.random.default_rng(seed)
    for _ in range(60):
        n = int(rng.integers(1, 30))
        upper = np.triu(rng.random((n, n)) < rng.random(), 1)
        adj = sp.csr_matrix(upper | upper.T)
        nodes = rng.choice(n, size=int(rng.integers(0, n + 1)), replace=False).tolist()
        got, want = induced(adj, nodes), adj[nodes][:, nodes]
        assert got.shape == want.shape and (got != want).nnz == 0
        if nodes:
            assert connected_components(got, directed=False)[1].tolist() == (
                connected_components(want, directed=False)[1].tolist()
            )
    adj = sp.csr_matrix(np.array([[0, 1, 0], [1, 0, 1], [0, 1, 0]], dtype=bool))
    assert (induced(adj, [1, 1, 2]) != adj[[1, 1, 2]][:, [1, 1, 2]]).nnz == 0
    assert (induced(adj.tocsc(), [0, 2]) != adj[[0, 2]][:, [0, 2]]).nnz == 0
    assert components(adj, [0, 2]) == [[0], [2]] and components(adj, [2, 1, 0]) == [[0, 1, 2]]
