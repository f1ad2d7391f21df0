"""Offline two-sided dominance maxima: fixed points (x_i, y_i) and fixed queries (X_q, Y_q); for any weights w, the
largest w_i with x_i <= X_q and y_i >= Y_q, for every query at once.

The ring walks over short arcs (:mod:`planner.bounds.arc_reach`) ask this once per station of the walk with new
weights (each arc's reach), where the links it replaces would be formed pairwise: O(m^2) for m arcs.

**Method.** A merge-sort tree over the points in the order of x, padded to P = 2^L: at level l the points lie in blocks
of 2^l consecutive ones, each block sorted by y. The points with x_i <= X_q are a prefix [0, p) of the x order, which is
the union of one block per set bit l of p (the one starting at p with its l + 1 low bits cleared); within a block those
with y_i >= Y_q are a suffix of its y order. The geometry fixes where each query's suffix begins in each block, so it is
found once (a binary search per query and level); each call then takes, per level, the suffix maxima of the weights
within the blocks and gathers them at those places.

**Cost.** Building: O(P log^2 P) (a sort per level); memory O(P log P) indices. Each call: O(P log P) for the suffix
maxima plus O(Q log P) gathers, with no Python loop over points or queries. Property test:
``tests/solve/test_dominance.py`` (equal to the brute-force maximum on random points, ties and empty queries).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


class DominanceMax:
    """The points ``x``, ``y`` and queries ``qx``, ``qy`` (float arrays), fixed; :meth:`__call__` answers for weights."""

    def __init__(
        self, x: NDArray[np.float64], y: NDArray[np.float64], qx: NDArray[np.float64], qy: NDArray[np.float64]
    ) -> None:
        m = x.size
        self.m = m
        levels = max(1, int(np.ceil(np.log2(max(m, 1)))))
        self.size = size = 1 << levels
        by_x = np.argsort(x, kind="stable")
        ys = np.sort(y)
        y_rank = np.full(size, -1, dtype=np.int64)  # padding: below every query (never in a queried block anyway)
        y_rank[:m] = np.searchsorted(ys, y[by_x], side="left")  # equal y, equal rank
        prefix = np.searchsorted(x[by_x], qx, side="right")  # the points with x <= X: the first `prefix` of by_x
        lower = np.searchsorted(ys, qy, side="left")  # y >= Y: rank >= lower
        self.perms: list[NDArray[np.int32]] = []  # per level: the x order's slots, block by block in the order of y
        self.hits: list[tuple[NDArray[np.int64], NDArray[np.int64]]] = []  # per level: (queries, their suffix start)
        slot = np.arange(size)
        points = np.full(size, m, dtype=np.int32)  # the x order's point indices, padded with m (the padding weight)
        points[:m] = by_x
        perm = slot  # level 0: blocks of one slot
        for level in range(levels + 1):
            key = (perm >> level) * (m + 2) + y_rank[perm] + 1
            if level:  # each block is two blocks of the level below, each in order: a merge (timsort finds the runs)
                order = np.argsort(key, kind="stable")
                perm, key = perm[order], key[order]
            use = np.flatnonzero((prefix >> level) & 1)  # the queries whose prefix takes a block at this level
            start = (prefix[use] >> (level + 1)) << 1
            at = np.searchsorted(key, start * (m + 2) + lower[use] + 1, side="left")
            keep = at < (start + 1) << level  # some point of the block has y >= Y
            self.perms.append(points[perm])
            self.hits.append((use[keep], at[keep]))
        self.q = qx.size

    def __call__(self, w: NDArray[np.int64], empty: int) -> NDArray[np.int64]:
        """The largest ``w`` over each query's points, ``empty`` where it has none (and where that is larger)."""
        best = np.full(self.q, empty, dtype=np.int64)
        padded = np.full(self.m + 1, np.iinfo(np.int64).min, dtype=np.int64)  # the last: the padding's weight
        padded[: self.m] = w
        for level, (perm, (use, at)) in enumerate(zip(self.perms, self.hits)):
            if not use.size:
                continue
            blocks = padded[perm].reshape(-1, 1 << level)[:, ::-1]
            suffix = np.maximum.accumulate(blocks, axis=1)[:, ::-1].ravel()
            best[use] = np.maximum(best[use], suffix[at])  # each query takes at most one block per level
        return best
