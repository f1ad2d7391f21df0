"""The connected greedy of a tiled site (one registration group over the whole pool) re-grows its bundle on its own
graph, not on a copy, and reads the seers of the pieces it covers in place; the same as a copied graph would give."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from planner.solve.bundles import Graph, _grow


def _site(seed: int = 3) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    rng = np.random.default_rng(seed)
    a = sp.random(60, 40, density=0.12, random_state=rng, format="csr").astype(bool)
    a = sp.csr_matrix(a + sp.eye(60, 40, format="csr", dtype=bool))  # every piece seen
    links = sp.random(60, 60, density=0.15, random_state=rng, format="csr").astype(bool)
    links = sp.csr_matrix(links + links.T + sp.eye(60, k=1, format="csr", dtype=bool) + sp.eye(60, k=-1, dtype=bool))
    return a, links


def test_whole_site_sub_graph_is_the_graph_itself_and_grows_alike() -> None:
    a, links = _site()
    one = np.zeros(60, dtype=np.int64)
    g = Graph.of(a, links, one, np.ones(60))
    everyone, pieces = np.arange(60), np.arange(40)
    assert g.sub(everyone, pieces) is g
    copied = Graph.of(g.a[everyone][:, pieces], g.adj[everyone][:, everyone], one, g.cost[everyone])
    need = np.ones(40, dtype=bool)
    for first in (None, 0, 17):
        order, left = _grow(g, need, {}, first)
        order2, left2 = _grow(copied, need, {}, first)
        assert order == order2 and np.array_equal(left, left2)
    part = np.arange(30)
    assert g.sub(part, pieces) is not g  # a part of the pool is copied


def test_seers_are_the_by_target_rows() -> None:
    a, links = _site(5)
    g = Graph.of(a, links, np.zeros(60, dtype=np.int64), np.ones(60))
    for targets in (np.array([3]), np.array([0, 7, 39]), np.arange(40)):
        assert np.array_equal(np.sort(g.seers(targets)), np.sort(g.by_target[targets].indices))
