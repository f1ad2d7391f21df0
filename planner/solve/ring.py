"""The connected cover of a ring of wall pieces by arcs, solved exactly as a shortest walk.

A zone-side's wall is a ring (or a chain) of pieces, and a station usually sees one run of
consecutive pieces: an arc. Two linked stations share wall, so their arcs overlap. For such a block the
connected optimum is a shortest path, not a search:

**Theorem.** Let every candidate j cover the arc h_j of a cyclic order of the pieces, and let every
linked pair's arcs overlap or touch. Then a cheapest connected set of candidates whose arcs cover the
required pieces costs exactly as much as a cheapest *walk* in the link graph whose arcs, unrolled onto
the line, cover a stretch that leaves out no required piece.

*Proof.* (<=) Take an optimal set C and a spanning tree of its links. Unroll the ring onto the line
(the universal cover) and lay the tree's arcs down from a root, each child on the copy that overlaps or
touches its parent's: their union is one interval U, and U projects onto every required piece. The path
in the tree from the arc holding U's left end to the arc holding its right end has a union that
contains U (consecutive arcs touch), and its cost is at most C's. (>=) A walk's distinct candidates are
linked in a chain, and the union of its arcs covers every required piece: a feasible set no dearer than
the walk. Hence the cheapest walk, found by Dijkstra from every start on the unrolled graph (copies of
the ring at offsets -n, 0, n, 2n), is the optimum. Complexity: O(C (E + C) log C) for C candidates and E
links, with the sources taken in chunks so memory stays O(chunk x C).

**A bound in general.** With each candidate's coverage replaced by the smallest arc that holds it (a
superset) and the links kept, every connected plan stays feasible, so the walk's cost is a lower bound
for the block in any cyclic order of its pieces, valid whenever every linked pair's arcs overlap or
touch (checked; otherwise :func:`ring_bound` answers ``None``). Where every candidate's coverage *is*
its arc, the walk is an optimal plan. Polygon A (cached pool of ``scripts/bench_connectivity.py``,
pieces in the outline's order): outside 15 and inside 10, its connected optima, in 0.1-0.5 s, where the
cut loop left a bound of 13 and 9 after 60 s (docs/milp.md). A bound only over the candidate pool given.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.csgraph import dijkstra

#: copies of the ring on the line: a cheapest walk from a leftmost arc on copy 0 stays on copies 0 and 1
_LIFTS = (-1, 0, 1, 2)
#: Dijkstra sources per call (memory: this many rows of len(_LIFTS) x C distances)
_CHUNK = 256


@dataclass(frozen=True)
class RingBound:
    """The cheapest walk over a block's arcs.

    ``bound``: a lower bound on the block's connected optimum over its candidate pool (exact when
    ``exact_arcs`` equals the candidates that cover anything); ``walk``: the distinct candidates of
    the walk (block indices), a plan of cost ``bound`` when every one of them covers its whole arc;
    ``exact_arcs``: candidates whose coverage is exactly their arc.
    """

    bound: float
    walk: tuple[int, ...]
    exact_arcs: int


def arcs(cover: sp.csr_matrix) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_]]:
    """Each row's smallest cyclic arc [start, end] (end may pass n: it wraps) over the n columns, whether the
    row covers all of it, and -1 for empty rows. The arc leaves out the row's widest gap."""
    n = cover.shape[1]
    start = np.full(cover.shape[0], -1, dtype=np.int64)
    end = np.full(cover.shape[0], -1, dtype=np.int64)
    exact = np.zeros(cover.shape[0], dtype=bool)
    for i in range(cover.shape[0]):
        cols = np.sort(cover.indices[cover.indptr[i]:cover.indptr[i + 1]])
        if cols.size == 0:
            continue
        gaps = np.diff(np.append(cols, cols[0] + n))  # gaps[k]: from cols[k] to the next covered column
        k = int(np.argmax(gaps))
        start[i] = cols[(k + 1) % cols.size]
        end[i] = cols[k] + (n if cols[k] < start[i] else 0)
        exact[i] = end[i] - start[i] + 1 == cols.size
    return start, end, exact


def _gap_before(required: NDArray[np.bool_]) -> NDArray[np.int64]:
    """For each column p, how many columns just before p (cyclically) are not required."""
    n = required.size
    idx = np.arange(n)
    last = np.maximum.accumulate(np.where(required, idx, -1))  # last required column <= p
    prev = np.concatenate([[-1], last[:-1]])  # last required column < p
    wrap = np.flatnonzero(required)[-1] - n  # the last required column, one turn back
    return idx - np.where(prev >= 0, prev, wrap) - 1


def ring_bound(cover: sp.csr_matrix, required: NDArray[np.bool_], adj: sp.csr_matrix,
               cost: NDArray[np.float64]) -> RingBound | None:
    """The cheapest walk over ``cover``'s arcs (candidates x pieces in cyclic order) that covers every
    ``required`` piece, linked by ``adj``; ``None`` when the theorem does not apply (a linked pair's arcs
    neither overlap nor touch, a cost not > 0, nothing required)."""
    m, n = cover.shape
    if not required.any() or np.any(cost <= 0):
        return None
    start, end, exact = arcs(cover)
    lifts = np.asarray(_LIFTS)
    pairs = sp.triu(adj, k=1).tocoo()
    i, j = pairs.row.astype(np.int64), pairs.col.astype(np.int64)
    if np.any(start[i] < 0) or np.any(start[j] < 0):
        return None
    rows, cols, touch = [], [], np.zeros(i.size, dtype=bool)
    for li, ki in enumerate(lifts):
        for lj, kj in enumerate(lifts):
            ok = (start[j] + kj * n <= end[i] + ki * n + 1) & (start[i] + ki * n <= end[j] + kj * n + 1)
            touch |= ok
            rows += [li * m + i[ok], lj * m + j[ok]]
            cols += [lj * m + j[ok], li * m + i[ok]]
    if not touch.all():
        return None
    r, c = np.concatenate(rows), np.concatenate(cols)
    # entering node v costs cost[v]: a walk's length plus its first node's cost is its cost
    graph = sp.csr_matrix((cost[c % m], (r, c)), shape=(len(lifts) * m, len(lifts) * m))
    ends = (end[None, :] + lifts[:, None] * n).ravel()
    need = _gap_before(required)
    best, walk = np.inf, ()
    zero = int(np.flatnonzero(lifts == 0)[0])
    sources = np.flatnonzero(start >= 0)
    for lo in range(0, sources.size, _CHUNK):
        src = sources[lo:lo + _CHUNK]
        dist, pred = dijkstra(graph, indices=zero * m + src, return_predecessors=True)
        for row, s in enumerate(src):
            goal = ends >= start[s] + n - 1 - need[start[s]]
            d = np.where(goal, dist[row], np.inf)
            v = int(np.argmin(d))
            if d[v] + cost[s] < best - 1e-9:
                best, walk = float(d[v] + cost[s]), _path(pred[row], zero * m + int(s), v, m)
    if not np.isfinite(best):
        return None
    return RingBound(best, walk, int(exact.sum()))


def _path(pred: NDArray[np.int32], source: int, v: int, m: int) -> tuple[int, ...]:
    """The distinct candidates on the predecessor path from ``source`` to ``v`` (nodes are lift * m + j)."""
    out = {v % m}
    while v != source:
        v = int(pred[v])
        out.add(v % m)
    return tuple(sorted(out))
