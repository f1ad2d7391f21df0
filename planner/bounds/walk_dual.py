"""The ring walk with the cover rows added back by multipliers, its Lagrangian dual found by column generation.

**The bound.** For a connected cover over candidates (here patches: :mod:`planner.bounds.patch_cover`) whose sets are
held by arcs of a ring, every connected cover C holds a walk over the ring (:mod:`planner.solve.ring`). For any
multipliers lambda >= 0 on the cover rows (targets t, ``sub``: candidates x targets) and reduced costs
rc_j = c_j - sum_t lambda_t a_jt,

    c(C) >= sum_{j in C} rc_j + sum_t lambda_t >= walk(max(rc, 0)) + sum_j min(rc_j, 0) + sum_t lambda_t = L(lambda)

(:func:`planner.solve.ring.lagrangian_bound` proves it), so every L(lambda) is a lower bound, whatever lambda is.

**The multipliers** (Dantzig-Wolfe). The best L is the value of the LP over the convex hull of walks, relaxed by the
single candidates: min sum_k |W_k| mu_k + sum_j c_j s_j subject to sum_k mu_k (sum_{j in W_k} a_j) + sum_j s_j a_j >= 1
on every target, sum_k mu_k = 1, mu, s >= 0. It is solved over the walks found so far (the *master*: one HiGHS model,
each round's walks added as columns and solved from the last basis); it starts from the cheapest walk from every anchor
(one search, the one that finds the cheapest walk). Its duals on the cover rows, smoothed toward the best multipliers
yet (Wentges, weight :data:`SMOOTHING`), price new walks (the cheapest from each anchor) under max(rc, 0), the cheapest
of which is also L at those multipliers. The master's value never falls below the best L
(it is the LP over fewer walks), so once ceil(best L) reaches ceil(master) no multipliers raise the rounded bound, and
the search stops. Where the subgradient ascent oscillates for tens of steps (polygon A's inside: 50 steps, 8.06), this
reaches the dual's 8.5 in a few walks.

Every limit is a count (walks, walk work): the same bound under any load.
"""

from __future__ import annotations

import math
from typing import SupportsInt

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.csgraph import dijkstra

from planner.solve.ring import _EPS, _LIFTS, RingBound, RingGraph, _path

#: the weight of the best multipliers yet in the multipliers that price the next walk (Wentges smoothing)
SMOOTHING = 0.5
#: below this a value is taken as its integer (rounding of the LP and of the walk's sums)
_TOL = 1e-6
#: walks added to the master per pricing at most: the cheapest walk from each anchor, the cheapest first
COLUMNS = 64


class Goal:
    """A goal that is set while the bound runs: a cover started before the plan's count is known runs with no goal
    (a huge one) until it is told the count. Each round reads it, so the rounds are those of a run given the count from
    the start, the same up to that run's last one; a bound that kept going past it is higher, and capped at the count
    (which every valid bound of the zone-side stays under) it is the same."""

    def __init__(self, value: int = 1 << 40) -> None:
        self.value = value

    def __int__(self) -> int:
        return self.value


def walk_dual_bound(
    ring: RingGraph,
    sub: sp.csr_matrix,
    cost: NDArray[np.float64],
    goal: SupportsInt,
    walks: int,
    first: RingBound | None = None,
) -> tuple[float, int]:
    """The best L(lambda) found (module docstring), and the walks priced after the first. ``sub``: candidates x the
    targets whose cover is added back; ``cost``: per candidate (> 0); ``goal``: stop once the rounded bound reaches it (read each round: a run started ahead learns it later, :class:`Goal`);
    ``walks``: at most this many walks priced after the first; ``first``: the cheapest walk under ``cost`` where known,
    else the cheapest walk from every anchor is found (one search, as the cheapest walk's) and they all start the
    master. -inf where the ring has no walk at all."""
    if first is None:
        start = anchor_walks(ring, cost, np.inf)
        if not start:
            return -math.inf, 0
        best, found = start[0][0], [walk for _, walk in start[:COLUMNS]]
    else:
        best, found = first.bound, [first.walk]
    sub = sub.tocsr()
    master = _Master(sub, cost)
    try:
        master.add(found)
        centre = np.zeros(sub.shape[1])
        for k in range(walks):
            got_master = master.solve()
            if got_master is None:
                return best, k
            value, lam_m = got_master
            if math.ceil(best - _TOL) >= min(int(goal), math.ceil(value - _TOL)):
                return best, k
            lam = lam_m if k == 0 else SMOOTHING * centre + (1.0 - SMOOTHING) * lam_m
            rc = cost - sub @ lam
            price = np.maximum(rc, 0.0)
            # the cheapest walk costs at most the cheapest of the walks found so far: each branch searched no farther
            known = min(float(price[list(c)].sum()) for c in found)
            got_walks = anchor_walks(ring, price, known + _TOL) or anchor_walks(ring, price, np.inf)
            if not got_walks:
                return best, k + 1
            low = got_walks[0][0]
            got = float(lam.sum() + low + np.minimum(rc, 0.0).sum())
            if got > best:
                best, centre = got, lam
            new = [walk for _, walk in got_walks[:COLUMNS]]
            found.extend(new)
            master.add(new)
    finally:
        master.close()
    return best, walks


def anchor_walks(ring: RingGraph, price: NDArray[np.float64], limit: float) -> list[tuple[float, tuple[int, ...]]]:
    """The cheapest walk from each anchor of ``ring`` under node costs ``price`` (>= 0), distinct, the cheapest first,
    each as (a lower bound on the cheapest walk's cost, the walk's candidates): :meth:`RingGraph.walk`'s search, every
    anchor's best kept instead of the best one. The first value is the least Dijkstra total less ``_EPS`` per lifted
    node (the totals carry at most that much of it), so at most the cheapest walk's cost. Each branch is searched no
    farther than ``limit``: empty where no walk keeps within it."""
    graph = ring.graph
    graph.data = price[graph.indices % ring.m] + _EPS
    src = ring._sources()
    dist, pred = dijkstra(graph, indices=src, return_predecessors=True, limit=limit)
    size, base = _LIFTS.size * ring.n + ring.n, -ring.n
    out: dict[tuple[int, ...], float] = {}
    for row, s in enumerate(src.tolist()):
        d = dist[row]
        reach = np.flatnonzero(np.isfinite(d))
        if reach.size == 0:
            continue
        right = np.full(size + 1, np.inf)  # right[e]: the cheapest right end at lifted end >= e
        np.minimum.at(right, np.clip(ring.hi[reach] - base, 0, size), d[reach])
        right = np.minimum.accumulate(right[::-1])[::-1]
        need = np.clip(ring.need[reach] - base, 0, size)
        total = d[reach] + right[need]
        k = int(np.argmin(total))
        if not np.isfinite(total[k]):
            continue
        left = int(reach[k])
        ends = reach[ring.hi[reach] - base >= need[k]]
        r = int(ends[np.argmin(d[ends])])
        walk = tuple(sorted({v % ring.m for v in _path(pred[row], s, left) + _path(pred[row], s, r)}))
        value = float(total[k] + price[s % ring.m] + _EPS)
        out[walk] = min(out.get(walk, np.inf), value)
    ranked = sorted((v, w) for w, v in out.items())
    if ranked:
        ranked[0] = (ranked[0][0] - _EPS * graph.shape[0], ranked[0][1])
    return ranked


class _Master:
    """The master LP (module docstring) kept in one HiGHS model (``highspy``, 1 thread, simplex): the single candidates
    first, then the walks as they come (cover rows >= 1, one convexity row = 1). Each solve starts from the last
    optimal basis: the new walks enter at 0, so it stays primal feasible, and a round costs a few pivots instead of a
    solve from scratch."""

    def __init__(self, sub: sp.csr_matrix, cost: NDArray[np.float64]) -> None:
        import highspy

        self._inf = highspy.kHighsInf
        self._h = h = highspy.Highs()
        h.setOptionValue("output_flag", False)
        h.setOptionValue("threads", 1)
        h.setOptionValue("random_seed", 0)
        h.setOptionValue("presolve", "off")
        self.sub = sub.astype(np.float64).tocsr()
        n_t = self.sub.shape[1]
        none = np.zeros(0, np.int32)
        h.addRows(n_t, np.ones(n_t), np.full(n_t, self._inf), 0, none, none, np.zeros(0))
        h.addRows(1, np.ones(1), np.ones(1), 0, none, none, np.zeros(0))  # the walks' weights sum to one
        self.cost = np.asarray(cost, dtype=np.float64)
        self._cols(self.sub, self.cost)

    def _cols(self, a: sp.csr_matrix, cost: NDArray[np.float64]) -> None:
        """Columns: the rows of ``a`` (their entries on the cover rows and the convexity row) at ``cost``."""
        a = a.tocsr()
        a.sort_indices()
        n = a.shape[0]
        self._h.addCols(
            n, cost, np.zeros(n), np.full(n, self._inf), a.nnz, a.indptr[:-1].astype(np.int32),
            a.indices.astype(np.int32), a.data.astype(np.float64),
        )  # fmt: skip

    def add(self, walks: list[tuple[int, ...]]) -> None:
        """The walks' columns: how many of each walk's candidates cover each target, and 1 on the convexity row; each
        costs its candidates' costs."""
        if not walks:
            return
        r = np.repeat(np.arange(len(walks)), [len(w) for w in walks])
        c = np.concatenate([np.asarray(w, dtype=np.int64) for w in walks])
        pick = sp.csr_matrix((np.ones(r.size), (r, c)), shape=(len(walks), self.sub.shape[0]))
        cols = (pick @ self.sub).tocsr()
        cols = sp.hstack([cols, sp.csr_matrix(np.ones((len(walks), 1)))], format="csr")  # the convexity row
        self._cols(cols, np.asarray(pick @ self.cost, dtype=np.float64))

    def solve(self) -> tuple[float, NDArray[np.float64]] | None:
        """The master's value and its duals on the cover rows (>= 0); None where HiGHS does not solve it."""
        h = self._h
        h.run()
        if h.modelStatusToString(h.getModelStatus()) != "Optimal":
            return None
        dual = np.asarray(h.getSolution().row_dual, dtype=np.float64)[: self.sub.shape[1]]
        return float(h.getInfo().objective_function_value), np.maximum(dual, 0.0)

    def close(self) -> None:
        """Free HiGHS's model now (see :class:`planner.solve.pricing.WarmCoverLp`)."""
        self._h.clear()
