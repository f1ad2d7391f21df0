"""The graph and gather steps of a local-search move (:mod:`planner.solve.local_search`): rows of a sparse matrix gathered
in one vectorised pass, the components and articulation counts of the chosen stations' overlap subgraph, and, where
that subgraph is dense, a scan-first forest and a sparse certificate of it.

Every value here is a property of the graph (a component's stations, the parts a removal adds), not of the order the
links are walked in, so the search's moves do not depend on how the subgraph is stored.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

#: rows gathered by slices below this many (a Python loop of slices is faster for a few rows than the index arrays)
_FEW = 24


def gather(m: sp.csr_matrix, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(position in ``rows``, column) of every stored entry of the rows ``rows`` of ``m``, in row order, without
    building a sparse matrix: one index array from the rows' starts and lengths (no Python loop over the rows)."""
    rows = np.asarray(rows, dtype=np.int64)
    start = m.indptr[rows].astype(np.int64)
    size = m.indptr[rows + 1] - start
    where = np.repeat(np.arange(len(rows)), size)
    return where, gather_cols(m, rows, start, size)


def gather_cols(
    m: sp.csr_matrix, rows: np.ndarray, start: np.ndarray | None = None, size: np.ndarray | None = None
) -> np.ndarray:
    """The columns of :func:`gather` alone (``start``, ``size``: the rows' starts and lengths, where known)."""
    if len(rows) < _FEW:
        ptr, ind = m.indptr, m.indices
        parts = [ind[ptr[r] : ptr[r + 1]] for r in np.asarray(rows).tolist()]
        return np.concatenate(parts) if parts else ind[:0]
    if start is None or size is None:
        rows = np.asarray(rows, dtype=np.int64)
        start = m.indptr[rows].astype(np.int64)
        size = m.indptr[rows + 1] - start
    total = int(size.sum())
    return m.indices[np.arange(total) + np.repeat(start - (np.cumsum(size) - size), size)]


def first_of(key: np.ndarray, stamp: np.ndarray) -> int:
    """Position of the least ``key``; ties to the least ``stamp`` (longest unchanged), then the lowest index."""
    tied = np.flatnonzero(key == key.min())
    return int(tied[0]) if tied.size == 1 else int(tied[np.argmin(stamp[tied])])


def distinct(x: np.ndarray) -> np.ndarray:
    """The distinct values of ``x``, ascending: ``np.unique`` by a sort (several times faster on a move's few thousand
    integers than numpy's hashed unique)."""
    x = np.sort(x)
    return x[np.concatenate(([True], x[1:] != x[:-1]))] if x.size else x


@dataclass(frozen=True, kw_only=True)
class Links:
    """S's overlap subgraph: as each station's neighbours (``lists``, by position in S), or, where it is dense, as a scan-first spanning forest
    (``tree``: each station's parent, -1 for a root, by position in S; ``pos``: each candidate's position, -1 off S)."""

    lists: list[list[int]] | None = None
    tree: np.ndarray | None = None
    pos: np.ndarray | None = None


class Graph:
    """S (``idx``, sorted), its links (:class:`Links`), each station's component (``label``,
    in order of each component's lowest station) out of ``n``, ``parts`` (sum over groups of components - 1), and, once
    computed, each station's split and each candidate's count of linked components."""

    def __init__(self, *, idx: np.ndarray, links: Links | None, label: np.ndarray, n: int, groups: np.ndarray) -> None:
        self.idx, self.links, self.label, self.n = idx, links, label, n
        self.parts = int(n - np.count_nonzero(groups))
        self.split: np.ndarray | None = None
        # S in pieces: the links of its components but the largest (station's position, candidate, component)
        self.linked: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        self.bridging: np.ndarray | None = None

    def without(self, c: int, groups: np.ndarray) -> Graph | None:
        """This graph less its station c, where c's removal adds no component (its split, computed, is 0: the others
        keep their stations; -1: c's own component goes), the components numbered again by their lowest stations; None
        otherwise (S's graph is then built again). Its links are not kept: :meth:`planner.solve.local_search._State.removal_cost` builds them when
        asked."""
        if self.split is None:
            return None
        k = int(np.searchsorted(self.idx, c))
        if self.split[k] > 0:
            return None
        label = np.delete(self.label, k)
        first = np.full(self.n, len(label))  # each component's lowest station now (c's may be a later one)
        np.minimum.at(first, label, np.arange(len(label)))
        rank = np.empty(self.n, dtype=np.int64)
        rank[np.argsort(first, kind="stable")] = np.arange(self.n)  # c's own component, gone, last
        return Graph(
            idx=np.delete(self.idx, k), links=None, label=rank[label], n=self.n - int(self.split[k] < 0), groups=groups
        )


def scan_forest(
    adj: sp.csr_matrix, idx: np.ndarray, pos: np.ndarray, avoid: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, int]:
    """A scan-first (breadth-first) spanning forest of the subgraph of ``adj`` on the nodes ``idx`` (``pos``: each
    node's position in ``idx``, -1 elsewhere), less the links of the forest ``avoid`` (a parent per position) where
    given: each position's parent (-1 for a root), its component, numbered in order of each component's lowest
    position, and the number of components. Each tree grows from the lowest position not yet reached, and the search
    stops once every position is reached: on a dense graph a few rows are read, not all of them."""
    m = len(idx)
    parent = np.full(m, -1, dtype=np.int64)
    label = np.full(m, -1, dtype=np.int64)
    ptr, ind = adj.indptr, adj.indices
    left, k = m, 0
    for root in range(m):
        if label[root] >= 0:
            continue
        label[root] = k
        left -= 1
        queue, head = [root], 0
        while head < len(queue) and left > 0:
            u = queue[head]
            head += 1
            nb = pos[ind[ptr[idx[u]] : ptr[idx[u] + 1]]]
            nb = nb[nb >= 0]
            if avoid is not None:
                nb = nb[(nb != avoid[u]) & (avoid[nb] != u)]
            new = nb[label[nb] < 0]
            label[new] = k
            parent[new] = u
            left -= new.size
            queue += new.tolist()
        k += 1
    return parent, label, k


def certificate(adj: sp.csr_matrix, idx: np.ndarray, links: Links) -> tuple[list[int], list[int]]:
    """A sparse subgraph of S's links (CSR lists, by position in S) with, for every station v, the components of S's
    graph without v: the forest ``links.tree`` and a scan-first forest of S's links less the first's (Cheriyan, Kao
    and Thurimella, "Scan-first search and sparse certificates: an improved parallel algorithm for k-vertex
    connectivity", SIAM J. Comput. 22(1):157-174, 1993; k = 2). :func:`walk` then follows at most 2 (n - 1) links,
    not the ones of a few hundred stations nearly all linked to each other (a plan on a fine floor grid)."""
    assert links.tree is not None and links.pos is not None
    first = links.tree
    second = scan_forest(adj, idx, links.pos, avoid=first)[0]
    child = [np.flatnonzero(f >= 0) for f in (first, second)]
    r = np.concatenate([child[0], first[child[0]], child[1], second[child[1]]])
    c = np.concatenate([first[child[0]], child[0], second[child[1]], child[1]])
    order = np.lexsort((c, r))
    ptr = np.concatenate([[0], np.cumsum(np.bincount(r, minlength=len(idx)))])
    return ptr.tolist(), c[order].tolist()


def walk(sub: tuple[list[int], list[int]] | list[list[int]]) -> tuple[int, list[int], list[int]]:
    """The number of components of the graph ``sub`` (each node's neighbours, or CSR lists: indptr, indices), each
    node's component (in order of each component's lowest node), and the components its removal adds to its own (-1
    for an isolated node): one iterative articulation-point pass (Hopcroft-Tarjan), O(nodes + links)."""
    if isinstance(sub, tuple):
        ptr, ind = sub
        sub = [ind[ptr[v] : ptr[v + 1]] for v in range(len(ptr) - 1)]
    n = len(sub)
    disc, low, out, label, up = [-1] * n, [0] * n, [0] * n, [-1] * n, [-1] * n
    clock = k = 0
    for root in range(n):
        if disc[root] >= 0:
            continue
        disc[root] = low[root] = clock
        label[root] = k
        clock += 1
        children = 0
        stack = [(root, iter(sub[root]))]
        while stack:
            v, rest = stack[-1]
            for w in rest:  # the next neighbour not walked yet: deeper, or a link back
                if disc[w] < 0:
                    disc[w] = low[w] = clock
                    label[w] = k
                    up[w] = v
                    clock += 1
                    children += v == root
                    stack.append((w, iter(sub[w])))
                    break
                if w != up[v] and disc[w] < low[v]:
                    low[v] = disc[w]
            else:  # v done
                stack.pop()
                p = up[v]
                if p >= 0:
                    if low[v] < low[p]:
                        low[p] = low[v]
                    if p != root and low[v] >= disc[p]:
                        out[p] += 1
        out[root] = children - 1
        k += 1
    return k, label, out


def split(sub: tuple[list[int], list[int]] | list[list[int]]) -> np.ndarray:
    """Components added to its own component by removing each node (-1 for an isolated node): :func:`walk`'s third
    value as an array."""
    return np.array(walk(sub)[2], dtype=np.int64)
