"""The cheapest unit-cost walk of a ring's arcs (:meth:`planner.solve.ring.RingGraph.walk` at unit costs) without the
unrolled graph and without anchors: the ring walks of the connected plane bound price every patch at one station.

**Reach.** Lay the arcs on the line (the ring unrolled). For a node v and k >= 1 let D_k(v) be the farthest lifted end
of the arcs on any path of at most k nodes that starts at v, with each next arc laid on the copy that overlaps or
touches the one before. Then D_1(v) = hi(v) and

    D_{k+1}(v) = max(D_k(v), max over links (v, u) of D_k(u) + d(v, u) n),

where d(v, u) is the highest turn (-1, 0 or 1) at which u's arc overlaps or touches v's: a path only reaches farther
on a higher copy, and the arcs after it move with it. A path's arcs, consecutive ones overlapping or touching, cover an
interval, so a path from L whose reach passes need(L) (the last required piece before L's start, one turn on) covers
every required piece; conversely every walk of :class:`~planner.solve.ring.RingGraph` is such a path (from its left
end through its anchor to its right end), with as many nodes as the walk's cost. So the cheapest walk costs the least
k with D_k(L) >= need(L) for some L. Copies only shift D and need by whole turns, so both are kept for copy 0.

**Cost.** One gather and one row maximum over the links per k, up to the walk's cost: O(k E) for E links, where
the unrolled graph holds each link up to 16 times and its breadth-first search runs from every anchor. Property test:
``tests/solve/test_ring_unit.py`` (equal to :meth:`RingGraph.walk` at unit costs on random rings, with holes and
limits). Short arcs need not form their links at all: :mod:`planner.bounds.arc_reach` takes each step's maxima as
dominance queries.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.solve.ring import arcs


class UnitRing:
    """A block's arcs, what each must reach and a step over their links (formed, or found as maxima at each step),
    ready for :meth:`unit_walk`."""

    def __init__(
        self,
        start: NDArray[np.int64],
        end: NDArray[np.int64],
        required: NDArray[np.bool_],
        linked: Callable[[NDArray[np.int64]], NDArray[np.int64]],
    ) -> None:
        self.n = required.size
        self.hi = end.astype(np.int64)
        idx = np.arange(self.n)
        last = np.maximum.accumulate(np.where(required, idx, -1))
        prev = np.concatenate([[-1], last[:-1]])  # the last required piece before p, or -1
        prev = np.where(prev >= 0, prev, np.flatnonzero(required)[-1] - self.n)
        lo = start.astype(np.int64)
        self.need = lo - np.mod(lo, self.n) + prev[np.mod(lo, self.n)] + self.n
        # the largest D(u) + d(v, u) n over each node v's links (the int64 minimum where none): from the links
        # formed (:class:`Links`) or without them (:func:`planner.bounds.arc_reach.short_arc_ring`)
        self.linked = linked

    def unit_walk(self, limit: float = np.inf) -> int | None:
        """The cheapest walk's cost where it is at most ``limit + 1`` (then both its branches from an anchor are
        within ``limit``, so it is :meth:`planner.solve.ring.RingGraph.walk`'s value at unit costs), else None (also where no
        walk covers the ring)."""
        reach, k = self.hi.copy(), 1
        while True:
            if np.any(reach >= self.need):
                return k
            if k > limit:
                return None
            grown = np.maximum(reach, self.linked(reach))
            if np.array_equal(grown, reach):
                return None  # no path reaches farther: no walk covers the ring
            reach, k = grown, k + 1


def unit_ring(cover: sp.csr_matrix, required: NDArray[np.bool_], adj: sp.csr_matrix) -> UnitRing | None:
    """:class:`UnitRing` of ``cover``'s arcs (candidates x pieces in cyclic order), ``required`` pieces, links ``adj``
    (symmetric); None where :func:`planner.solve.ring.ring_graph` is None (nothing required, a linked pair whose
    arcs neither overlap nor touch at any turn, an empty row linked)."""
    n = cover.shape[1]
    if not required.any():
        return None
    start, end, _exact = arcs(cover)
    adj = sp.csr_matrix(adj, dtype=bool)
    adj.sort_indices()
    i = np.repeat(np.arange(adj.shape[0]), np.diff(adj.indptr))
    j = adj.indices.astype(np.int64)
    if np.any(start[i] < 0) or np.any(start[j] < 0):
        return None
    turn = np.full(i.size, -2, dtype=np.int64)
    for d in (-1, 0, 1):  # the copy of j d turns on meets i's arc: overlaps or touches
        meet = (start[j] + d * n <= end[i] + 1) & (start[i] <= end[j] + d * n + 1)
        turn = np.where(meet, d, turn)
    if np.any(turn < -1):
        return None
    return UnitRing(start, end, required, Links(adj, turn * n))


class Links:
    """A ring's links formed, each with its highest turn times n (``shift``): called with the reach D, the largest
    D(u) + shift over each node's links, the int64 minimum where it has none."""

    def __init__(self, adj: sp.csr_matrix, shift: NDArray[np.int64]) -> None:
        self.adj, self.shift = adj, shift
        self.rows = np.flatnonzero(np.diff(adj.indptr))

    def __call__(self, reach: NDArray[np.int64]) -> NDArray[np.int64]:
        best = np.full(reach.size, np.iinfo(np.int64).min, dtype=np.int64)
        if self.rows.size:
            step = reach[self.adj.indices] + self.shift
            best[self.rows] = np.maximum.reduceat(step, self.adj.indptr[self.rows])
        return best
