"""Joining a cover's pieces into one registered network with few linking stations: a Steiner-tree view.

A plain cover (:mod:`planner.solve.cft`) usually falls apart under the overlap relation. Joining each registration
group's components is a node-weighted Steiner problem over the overlap graph (terminals: the components; cost: the
stations added).
:func:`steiner_join` uses Mehlhorn's construction (K. Mehlhorn, "A faster approximation algorithm for the Steiner
problem in graphs", Information Processing Letters 27, 1988), with node weights:

1. one multi-source shortest-path pass from every chosen station (distance 0) over ``adj``, each step costing the
   station it enters (0 for a chosen one): each candidate's distance to, and nearest, component (its Voronoi region);
2. every overlap pair (u, v) whose nearest components differ offers a bridge of cost d(u) + d(v);
3. a minimum spanning tree over the components with the cheapest bridge of each pair; its bridges' paths are added,
   cheapest first, skipping one whose components an earlier bridge already joined.

The result is at most twice the cost of the best tree through the Voronoi paths for edge weights (Mehlhorn's bound;
with node weights a heuristic). Cost per round: one Dijkstra, O(E log C), and one pass over the E overlap pairs; a
second round runs only if a group was left in pieces (never when its overlap graph is connected).
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components, dijkstra, minimum_spanning_tree

from planner.solve.connectivity import group_members


def steiner_join(
    adj: sp.csr_matrix, groups: Sequence[Hashable], selected: Sequence[int], cost: np.ndarray | None = None
) -> list[int] | None:
    """``selected`` with linking stations added so that each group's chosen stations are connected under ``adj``
    (module docstring), sorted; None when some group's components cannot be joined at all. ``cost``: each candidate's
    cost (default 1: stations)."""
    adj = sp.csr_matrix(adj, dtype=bool)
    n = adj.shape[0]
    cost = np.ones(n) if cost is None else np.asarray(cost, dtype=float)
    chosen = {int(i) for i in selected}
    for members in group_members(groups, sorted(chosen)).values():
        for _ in range(2):
            added = _join_once(adj, cost, members, chosen)
            if added is None:
                return None
            if not added:
                break
            chosen.update(added)
            members = sorted(set(members) | set(added))
    return sorted(chosen)


def _join_once(adj: sp.csr_matrix, cost: np.ndarray, members: list[int], chosen: set[int]) -> list[int] | None:
    """The stations one Mehlhorn round adds to join ``members``' components ([] when they are one; None when they
    cannot be joined)."""
    sub = adj[members][:, members]
    k, label = connected_components(sub, directed=False)
    if k <= 1:
        return []
    comp = np.full(adj.shape[0], -1, dtype=np.int64)
    comp[members] = label
    step = np.where(comp >= 0, 0.0, cost)  # entering a chosen station costs nothing
    weights = adj.astype(np.float64).multiply(step[None, :]).tocsr()
    weights.data[weights.data == 0] = 1e-9  # an explicit zero would read as "no edge"
    dist, pred, src = dijkstra(weights, directed=True, indices=members, min_only=True, return_predecessors=True)
    home = np.where(src >= 0, comp[np.maximum(src, 0)], -1)
    u, v = adj.nonzero()
    ok = (home[u] >= 0) & (home[v] >= 0) & (home[u] < home[v])
    u, v = u[ok], v[ok]
    bridge = np.round(dist[u], 6) + np.round(dist[v], 6) + 1e-6  # > 0: a spanning-tree edge of weight 0 vanishes
    if u.size == 0:
        return None
    order = np.lexsort((v, u, bridge))  # the cheapest bridge of each component pair, ties by index
    pair = home[u[order]] * k + home[v[order]]
    _, first = np.unique(pair, return_index=True)
    best = order[first]
    graph = sp.csr_matrix((bridge[best], (home[u[best]], home[v[best]])), shape=(k, k))
    tree = minimum_spanning_tree(graph).tocoo()
    if tree.nnz < k - 1:
        return None
    by_pair = {(int(home[u[b]]), int(home[v[b]])): int(b) for b in best}
    added: list[int] = []
    for p, q in zip(tree.row, tree.col, strict=True):
        b = by_pair[(min(p, q), max(p, q))]
        for end in (int(u[b]), int(v[b])):
            node = end
            while node >= 0 and node not in chosen:
                added.append(node)
                node = int(pred[node])
    return sorted(set(added))
