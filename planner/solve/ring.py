"""The connected cover of a ring of wall pieces by arcs, solved exactly as a shortest walk.

A zone-side's wall is a ring (or a chain) of pieces, and a station usually sees one run of consecutive pieces: an arc.
Two linked stations share wall, so their arcs overlap. For such a block the connected optimum is a shortest path, not
a search:

**Theorem.** Let every candidate j cover the arc h_j of a cyclic order of the pieces, and let every linked pair's arcs
overlap or touch. Then a cheapest connected set of candidates whose arcs cover the required pieces costs exactly as
much as a cheapest *walk* in the link graph whose arcs, unrolled onto the line, cover a stretch that leaves out no
required piece.

*Proof.* (<=) Take an optimal set C and a spanning tree of its links. Unroll the ring onto the line (the universal
cover) and lay the tree's arcs down from a root, each child on the copy that overlaps or touches its parent's: their
union is one interval U, and U projects onto every required piece. The path in the tree from the arc holding U's left
end to the arc holding its right end has a union that contains U (consecutive arcs touch), and its cost is at most
C's. (>=) A walk's distinct candidates are linked in a chain, and the union of its arcs covers every required piece: a
feasible set no dearer than the walk.

**Search.** Fix the required piece q seen (by arc) by the fewest candidates. The optimal path holds an arc M over q;
from M it runs left to its leftmost arc and right to its rightmost. So one Dijkstra per such M on the unrolled graph
(copies of the ring at offsets -n, 0, n, 2n; entering a node costs its candidate's cost) gives every left end's and
right end's cost, and the best pair whose stretch leaves out no required piece is found with suffix minima: O(|M| (E +
C) log C) for C candidates and E links.

**A bound in general.** With each candidate's coverage replaced by the smallest arc that holds it (a superset) and the
links kept, every connected plan stays feasible, so the walk's cost is a lower bound for the block in any cyclic order
of its pieces, valid whenever every linked pair's arcs overlap or touch (checked; otherwise :func:`ring_graph` answers
``None``). Where every candidate's coverage *is* its arc, the walk is an optimal plan. Where arcs have holes (stations
inside a concave outline see around a corner), :func:`lagrangian_bound` adds the cover rows back with multipliers.
Bounds are over the candidate pool given.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.csgraph import dijkstra

#: copies of the ring on the line: a walk from an arc over q on copy 0 stays within one turn either side
_LIFTS = np.array([-1, 0, 1, 2])
#: added to every node cost so that zero costs stay edges for Dijkstra; taken off the bound again
_EPS = 1e-9


@dataclass(frozen=True)
class RingBound:
    """The cheapest walk over a block's arcs. ``bound``: a lower bound on the block's connected optimum over its
    candidate pool (exact when ``exact_arcs`` equals the candidates that cover anything); ``walk``: the distinct
    candidates of the walk (block indices), a plan of cost ``bound`` when every one of them covers its whole arc;
    ``exact_arcs``: candidates whose coverage is exactly their arc."""

    bound: float
    walk: tuple[int, ...]
    exact_arcs: int


def cyclic_arcs(u: sp.csr_matrix) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Each non-empty row's smallest cyclic arc [start, end] over the n columns (end may pass n), leaving out the
    row's widest gap (first widest on ties); rows must be non-empty."""
    u = u.tocsr()
    u.sort_indices()
    n = u.shape[1]
    cols = u.indices.astype(np.int64)
    first = u.indptr[:-1]
    last = u.indptr[1:] - 1
    nxt = np.empty_like(cols)
    nxt[:-1] = cols[1:]
    nxt[last] = cols[first] + n  # the wrap gap, from each row's last column to its first one turn on
    gaps = nxt - cols
    top = np.maximum.reduceat(gaps, first)
    idx = np.arange(cols.size)
    row = np.repeat(np.arange(u.shape[0]), np.diff(u.indptr))
    k = np.minimum.reduceat(np.where(gaps == top[row], idx, cols.size), first)  # first widest gap per row
    k_next = np.where(k == last, first, k + 1)
    start = cols[k_next]
    end = cols[k] + np.where(cols[k] < start, n, 0)
    return start, end


def arcs(cover: sp.csr_matrix) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_]]:
    """:func:`cyclic_arcs` of every row, -1 for empty rows, and whether the row covers all of its arc."""
    cover = cover.tocsr()
    size = cover.getnnz(axis=1)
    start = np.full(cover.shape[0], -1, dtype=np.int64)
    end = np.full(cover.shape[0], -1, dtype=np.int64)
    live = np.flatnonzero(size)
    if live.size:
        start[live], end[live] = cyclic_arcs(cover[live])
    return start, end, (size > 0) & (end - start + 1 == size)


class RingGraph:
    """The unrolled link graph of a block's arcs, built once; :meth:`walk` prices it for any node costs."""

    def __init__(
        self,
        start: NDArray[np.int64],
        end: NDArray[np.int64],
        exact: NDArray[np.bool_],
        required: NDArray[np.bool_],
        graph: sp.csr_matrix,
    ) -> None:
        self.m, self.n = start.size, required.size
        self.exact_arcs = int(exact.sum())
        self.graph = graph  # pattern of the lifted link graph; its data are set per pricing
        self._head = graph.indices % self.m
        lift = np.repeat(_LIFTS, self.m)
        self.lo = np.tile(start, _LIFTS.size) + lift * self.n  # lifted start and end of every node
        self.hi = np.tile(end, _LIFTS.size) + lift * self.n
        idx = np.arange(self.n)
        last = np.maximum.accumulate(np.where(required, idx, -1))
        prev = np.concatenate([[-1], last[:-1]])  # the last required piece before p, or -1
        prev = np.where(prev >= 0, prev, np.flatnonzero(required)[-1] - self.n)
        # a walk whose stretch starts at lifted s must reach the required piece just before s, one turn on
        self.need = self.lo - np.mod(self.lo, self.n) + prev[np.mod(self.lo, self.n)] + self.n
        alive = start >= 0
        q = np.flatnonzero(required)
        seers = [
            (np.flatnonzero(alive & (((start <= p) & (end >= p)) | ((start <= p + self.n) & (end >= p + self.n)))))
            for p in q
        ]
        self.anchors = min(seers, key=len)  # the arcs over the required piece fewest arcs hold
        self.q = int(q[min(range(len(seers)), key=lambda k: len(seers[k]))])

    def walk(self, cost: NDArray[np.float64], limit: float = np.inf) -> RingBound | None:
        """The cheapest walk for node costs ``cost`` (>= 0), or None when no walk covers the ring (with ``limit``:
        none whose two branches from the anchor each cost at most ``limit``, the anchor not counted)."""
        self.graph.data = cost[self._head] + _EPS
        zero = int(np.flatnonzero(_LIFTS == 0)[0])
        src = zero * self.m + self.anchors
        # an anchor's copy must hold q itself: the copy at offset 0 or the one a turn back
        src = np.where((self.lo[src] <= self.q) & (self.hi[src] >= self.q), src, src - self.m)
        dist, pred = dijkstra(self.graph, indices=src, return_predecessors=True, limit=limit)
        best, pick = np.inf, None
        size = _LIFTS.size * self.n + self.n  # lifted positions from -n to 3n + n
        base = -self.n
        for row, s in enumerate(src):
            d = dist[row]
            reach = np.isfinite(d)
            right = np.full(size + 1, np.inf)  # right[e]: cheapest right end at lifted end >= e
            np.minimum.at(right, np.clip(self.hi[reach] - base, 0, size), d[reach])
            right = np.minimum.accumulate(right[::-1])[::-1]
            need = np.clip(self.need[reach] - base, 0, size)
            total = d[reach] + right[need]
            if total.size and total.min() + cost[s % self.m] + _EPS < best:
                k = int(np.argmin(total))
                left = int(np.flatnonzero(reach)[k])
                e = np.flatnonzero(reach & (self.hi - base >= need[k]))
                r = int(e[np.argmin(d[e])])
                best, pick = float(total[k] + cost[s % self.m] + _EPS), (pred[row], int(s), left, r)
        if pick is None:
            return None
        pr, source, left, r = pick
        lpath, rpath = _path(pr, source, left), _path(pr, source, r)
        walk = tuple(sorted({v % self.m for v in lpath + rpath}))
        # the walk's own cost (anchor once); Dijkstra chose it with _EPS per node, which can pass over a walk cheaper
        # by at most _EPS per lifted node: exact for integral costs, otherwise that much is taken off
        true = float(
            cost[np.asarray(lpath) % self.m].sum() + cost[np.asarray(rpath[1:], dtype=np.int64) % self.m].sum()
        )
        exact = bool(np.all(cost == np.round(cost)))
        return RingBound(true if exact else true - _EPS * self.graph.shape[0], walk, self.exact_arcs)

    def _sources(self) -> NDArray[np.int64]:
        """The anchors' nodes: the copy at offset 0 where it holds q, else the one a turn back."""
        zero = int(np.flatnonzero(_LIFTS == 0)[0])
        src = zero * self.m + self.anchors
        return np.where((self.lo[src] <= self.q) & (self.hi[src] >= self.q), src, src - self.m)


def ring_graph(cover: sp.csr_matrix, required: NDArray[np.bool_], adj: sp.csr_matrix) -> RingGraph | None:
    """The unrolled link graph of ``cover``'s arcs (candidates x pieces in cyclic order), ``required`` pieces to
    cover, links ``adj``; ``None`` when the theorem does not apply (a linked pair's arcs neither overlap nor touch,
    nothing required)."""
    m, n = cover.shape
    if not required.any():
        return None
    start, end, exact = arcs(cover)
    pairs = sp.triu(adj, k=1).tocoo()
    i, j = pairs.row.astype(np.int64), pairs.col.astype(np.int64)
    if np.any(start[i] < 0) or np.any(start[j] < 0):
        return None
    # lifted links as 32-bit node numbers, one half (i's copy to j's) per lift pair, mirrored once at the end: int64
    # lists and their copies take gigabytes on a fine grid
    idx = np.int32 if _LIFTS.size * m < np.iinfo(np.int32).max else np.int64
    i32, j32 = i.astype(idx), j.astype(idx)
    rows, cols, touch = [], [], np.zeros(i.size, dtype=bool)
    for li, ki in enumerate(_LIFTS):
        for lj, kj in enumerate(_LIFTS):
            if abs(ki - kj) > 1:  # an arc is shorter than a turn: copies two turns apart never touch
                continue
            ok = (start[j] + kj * n <= end[i] + ki * n + 1) & (start[i] + ki * n <= end[j] + kj * n + 1)
            touch |= ok
            rows.append(i32[ok] + idx(li * m))
            cols.append(j32[ok] + idx(lj * m))
    if not touch.all():
        return None
    r, c = np.concatenate(rows), np.concatenate(cols)
    del rows, cols
    size = _LIFTS.size * m
    half = sp.csr_matrix((np.ones(r.size), (r, c)), shape=(size, size))
    del r, c
    graph = (half + half.T).tocsr()
    graph.data[:] = 1.0
    graph.sort_indices()
    return RingGraph(start, end, exact, required, graph)


def ring_bound(
    cover: sp.csr_matrix, required: NDArray[np.bool_], adj: sp.csr_matrix, cost: NDArray[np.float64]
) -> RingBound | None:
    """The cheapest walk over ``cover``'s arcs that covers every ``required`` piece (see :func:`ring_graph`); ``None``
    when the theorem does not apply, a cost is not > 0, or no walk covers the ring."""
    if np.any(cost <= 0):
        return None
    g = ring_graph(cover, required, adj)
    return g.walk(cost) if g is not None else None


def lagrangian_bound(
    ring: RingGraph,
    sub: sp.csr_matrix,
    cost: NDArray[np.float64],
    lam: NDArray[np.float64],
    target: float,
    stop_above: float,
    iterations: int,
    give_up: int = 20,
) -> tuple[float, int]:
    """The ring bound with the cover rows added back by multipliers, raised by subgradient ascent.

    For lambda >= 0 on the required targets (columns of ``sub``, candidates x targets) and reduced costs
    rc = c - sub lambda, every connected cover C (it contains a path P over the ring, by the theorem above)
    costs  c(C) = sum_C rc + sum_C sum_{t seen by j} lambda_t >= sum_C rc + sum_t lambda_t
               >= walk(max(rc, 0)) + sum_j min(rc_j, 0) + sum_t lambda_t  =: L(lambda),
    so every L(lambda) is a lower bound; at the cover LP's duals it is at least the LP's value. Ascent from ``lam``:
    Polyak steps toward ``target`` (the incumbent's cost), the step factor 2 halved after 20 steps without a better L.
    Stops after ``iterations`` steps, once L > ``stop_above`` (with integral costs, the incumbent's cost - 1: the
    incumbent is then proven), or after ``give_up`` steps none of which raised L above its first value (the ring adds
    nothing near these multipliers). Returns the best L and the steps taken."""
    best, factor, stall, first = -np.inf, 2.0, 0, np.inf
    for step in range(iterations):
        rc = cost - sub @ lam
        w = ring.walk(np.maximum(rc, 0.0))
        if w is None:
            return np.inf, step + 1
        value = float(lam.sum() + w.bound + np.minimum(rc, 0.0).sum())
        first = value if step == 0 else first
        if value > best + 1e-9:
            best, stall = value, 0
        else:
            stall += 1
            if stall >= 20:
                factor, stall = factor / 2, 0
        if best > stop_above or (step + 1 >= give_up and best <= first + 1e-9):
            return best, step + 1
        use = np.zeros(cost.size)
        walk = np.asarray(w.walk)
        use[walk[rc[walk] > 0]] = 1.0
        use[rc < 0] = 1.0
        g = 1.0 - sub.T @ use
        g[(lam <= 0) & (g < 0)] = 0.0
        norm = float(g @ g)
        if norm == 0.0:
            return best, step + 1
        lam = np.maximum(lam + factor * (target - value) / norm * g, 0.0)
    return best, iterations


def _path(pred: NDArray[np.int32], source: int, v: int) -> list[int]:
    """The nodes on the predecessor path from ``source`` to ``v``, source first."""
    out = [v]
    while v != source:
        v = int(pred[v])
        out.append(v)
    return out[::-1]
