"""Minimum node separators on the overlap graph, for cutting off fractional points.

The node-separator inequalities (Fischetti, Leitner, Ljubic, Luipersbeck, Monaci, Resch, Salvagnin, Sinnl, "Thinning
out Steiner trees: a node-based model for uniform edge costs", Math. Prog. Comp. 9, 2017) say: when the chosen
stations of a zone-side must be connected, a station i and a station of a set T that must hold a chosen station can
only both be chosen when every set N of nodes that separates i from T holds a chosen one:

    sum_{v in N} x_v >= x_i.

Here T is the set of candidates that see an *essential* target of the group (one that only the group's candidates
see), so some station of T is always chosen. The most violated such cut for a point x* is a minimum vertex cut with
node capacities x*, i.e. a maximum flow on the split-node graph (v_in -> v_out with capacity x*_v, u_out -> v_in
unbounded for every overlap edge).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order, dijkstra, maximum_flow

#: LP values are scaled to integers for scipy's max-flow (int32 capacities)
FLOW_SCALE = 10_000
_BIG = 2**30


def split_graph(adj: sp.csr_matrix, capacity: np.ndarray) -> sp.csr_matrix:
    """Capacities of the split-node graph on 2n + 1 nodes (v_in = v, v_out = n + v, sink = 2n), no sink arcs yet."""
    n = adj.shape[0]
    coo = sp.triu(adj, k=1).tocoo()
    rows = np.concatenate([np.arange(n), n + coo.row, n + coo.col])
    cols = np.concatenate([n + np.arange(n), coo.col, coo.row])
    node_caps = np.round(np.clip(capacity, 0, None) * FLOW_SCALE).astype(np.int64)
    caps = np.concatenate([node_caps, np.full(2 * coo.row.size, _BIG, dtype=np.int64)])
    return sp.csr_matrix((caps.astype(np.int32), (rows, cols)), shape=(2 * n + 1, 2 * n + 1))


def min_node_separator(base: sp.csr_matrix, source: int, sinks: np.ndarray) -> tuple[float, np.ndarray]:
    """The value (in the capacity's units) and nodes of the smallest-capacity node set separating ``source`` from
    every node of ``sinks`` (sink nodes may be in it; the source's own capacity does not count)."""
    m = base.shape[0]
    n = (m - 1) // 2
    sink = 2 * n
    to_sink = (n + np.asarray(sinks), np.full(len(sinks), sink))  # every sink's out-node to the sink, unbounded
    extra = sp.csr_matrix((np.full(len(sinks), _BIG, dtype=np.int32), to_sink), shape=base.shape)
    graph = (base + extra).tocsr()
    graph.sort_indices()
    res = maximum_flow(graph, n + source, sink)
    residual = (graph.astype(np.int64) - res.flow.astype(np.int64)).tocsr()
    residual.data[residual.data < 0] = 0
    residual.eliminate_zeros()
    reach = np.zeros(m, dtype=bool)
    reach[breadth_first_order(residual, n + source, directed=True, return_predecessors=False)] = True
    nodes = np.flatnonzero(reach[:n] & ~reach[n : 2 * n])
    return res.flow_value / FLOW_SCALE, nodes


def anchor_targets(
    adj: sp.csr_matrix, seers: sp.csr_matrix, targets: np.ndarray, count: int
) -> list[tuple[int, np.ndarray]]:
    """Up to ``count`` targets spread out over the overlap graph (farthest-point order, start at the first), each with
    the hop distance of every candidate from the target's seers."""
    out: list[tuple[int, np.ndarray]] = []
    if targets.size == 0:
        return out
    nearest = np.full(targets.size, np.inf)
    pick = 0
    for _ in range(min(count, targets.size)):
        t = int(targets[pick])
        near = seers.indices[seers.indptr[t] : seers.indptr[t + 1]]
        dist = dijkstra(adj, directed=False, indices=near, unweighted=True, min_only=True)
        out.append((t, dist))
        nearest = np.minimum(nearest, nearest_seer(dist, seers, targets))
        finite = np.where(np.isfinite(nearest), nearest, -1)
        if finite.max() <= 0:
            break
        pick = int(np.argmax(finite))
    return out


def nearest_seer(dist: np.ndarray, seers: sp.csr_matrix, targets: np.ndarray) -> np.ndarray:
    """For each target, the least ``dist`` of a candidate that sees it (inf: none)."""
    return np.array([dist[seers.indices[seers.indptr[u] : seers.indptr[u + 1]]].min(initial=np.inf) for u in targets])


def layer_cuts(
    adj: sp.csr_matrix, a: sp.csr_matrix, members: np.ndarray, essential: np.ndarray, anchors: int = 8
) -> list[tuple[np.ndarray, np.ndarray, float]]:
    """Distance-layer cuts of one group: sum_{v in L_k} x_v >= 1. For an essential target t, let d(v) be the
    overlap-step distance of candidate v from the candidates that see t, and D the largest distance from them to the
    nearest seer of another essential target. Some chosen station sees t and one sees that other target, joined by a
    chosen path along which d rises by at most one per step; so for k = 1..D the layer L_k = {v: d(v) = k} holds a
    chosen station. Layers of disjoint support add up: the LP pays at least D + 1.
    """
    seers = a.T.tocsr()
    ess = np.flatnonzero(essential)
    in_group = np.zeros(adj.shape[0], dtype=bool)
    in_group[members] = True
    cuts = []
    for _t, dist in anchor_targets(adj, seers, ess, anchors):
        far = nearest_seer(dist, seers, ess)
        far = far[np.isfinite(far)]
        depth = int(far.max(initial=0))
        for k in range(1, depth + 1):
            layer = np.flatnonzero((dist == k) & in_group)
            if layer.size:
                cuts.append((layer.astype(np.int64), np.ones(layer.size), 1.0))
    return cuts
