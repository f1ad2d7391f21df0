"""The ring walk with the cover rows added back by multipliers, its Lagrangian dual found by column generation.

**The bound.** For a connected cover over candidates (here patches: :mod:`planner.bounds.patch_cover`) whose sets are
held by arcs of a ring, every connected cover C holds a walk over the ring (:mod:`planner.solve.ring`). For any
multipliers lambda >= 0 on the cover rows (targets t, ``sub``: candidates x targets) and reduced costs
rc_j = c_j - sum_t lambda_t a_jt,

    c(C) >= sum_{j in C} rc_j + sum_t lambda_t >= walk(max(rc, 0)) + sum_j min(rc_j, 0) + sum_t lambda_t = L(lambda)

(:func:`planner.solve.ring.lagrangian_bound` proves it), so every L(lambda) is a lower bound, whatever lambda is.

**The multipliers** (Dantzig-Wolfe). The best L is the value of the LP over the convex hull of walks, relaxed by the
single candidates: min sum_k |W_k| mu_k + sum_j c_j s_j subject to sum_k mu_k (sum_{j in W_k} a_j) + sum_j s_j a_j >= 1
on every target, sum_k mu_k = 1, mu, s >= 0. It is solved over the walks found so far (the *master*, HiGHS); its duals
on the cover rows, smoothed toward the best multipliers yet (Wentges, weight :data:`SMOOTHING`), price a new walk: the
cheapest walk under max(rc, 0), which is also L at those multipliers. The master's value never falls below the best L
(it is the LP over fewer walks), so once ceil(best L) reaches ceil(master) no multipliers raise the rounded bound, and
the search stops. Where the subgradient ascent oscillates for tens of steps (polygon A's inside: 50 steps, 8.06), this
reaches the dual's 8.5 in a few walks.

Every limit is a count (walks, walk work): the same bound under any load.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import linprog

from planner.solve.ring import RingGraph

#: the weight of the best multipliers yet in the multipliers that price the next walk (Wentges smoothing)
SMOOTHING = 0.5
#: below this a value is taken as its integer (rounding of the LP and of the walk's sums)
_TOL = 1e-6


def walk_dual_bound(
    ring: RingGraph, sub: sp.csr_matrix, cost: NDArray[np.float64], goal: int, walks: int
) -> tuple[float, int]:
    """The best L(lambda) found (module docstring), and the walks priced after the first. ``sub``: candidates x the
    targets whose cover is added back; ``cost``: per candidate (> 0); ``goal``: stop once the rounded bound reaches it;
    ``walks``: at most this many walks priced after the first. -inf where the ring has no walk at all."""
    first = ring.walk(cost)
    if first is None:
        return -math.inf, 0
    best = first.bound
    m, n_t = sub.shape
    sub = sub.tocsr()
    found = [first.walk]
    cols = [_column(sub, first.walk)]
    prices = [float(cost[list(first.walk)].sum())]
    centre = np.zeros(n_t)
    rows = sp.csc_matrix(-sub.T)
    for k in range(walks):
        master = _master(rows, cost, cols, prices)
        if master is None:
            return best, k
        value, lam_m = master
        if math.ceil(best - _TOL) >= min(goal, math.ceil(value - _TOL)):
            return best, k
        lam = lam_m if k == 0 else SMOOTHING * centre + (1.0 - SMOOTHING) * lam_m
        rc = cost - sub @ lam
        price = np.maximum(rc, 0.0)
        # the cheapest walk costs at most the cheapest of the walks found so far: each branch searched no farther
        known = min(float(price[list(c)].sum()) for c in found)
        w = ring.walk(price, limit=known + _TOL)
        w = ring.walk(price) if w is None else w
        if w is None:
            return best, k + 1
        got = float(lam.sum() + w.bound + np.minimum(rc, 0.0).sum())
        if got > best:
            best, centre = got, lam
        found.append(w.walk)
        cols.append(_column(sub, w.walk))
        prices.append(float(cost[list(w.walk)].sum()))
    return best, walks


def _column(sub: sp.csr_matrix, walk: tuple[int, ...]) -> NDArray[np.float64]:
    """A walk's column in the master: how many of its candidates cover each target."""
    return np.asarray(sub[list(walk)].sum(axis=0), dtype=np.float64).ravel()


def _master(
    rows: sp.csc_matrix, cost: NDArray[np.float64], cols: list[NDArray[np.float64]], prices: list[float]
) -> tuple[float, NDArray[np.float64]] | None:
    """The master LP over the single candidates (``rows``: -sub transposed) and the walks so far (their columns and
    costs): its value and its duals on the cover rows (>= 0); None where HiGHS does not solve it."""
    m, k = rows.shape[1], len(cols)
    a_ub = sp.hstack([rows, sp.csc_matrix(-np.stack(cols, axis=1))], format="csc")
    c = np.concatenate([cost, prices])
    a_eq = sp.csr_matrix(np.concatenate([np.zeros(m), np.ones(k)])[None, :])
    lp = linprog(c, A_ub=a_ub, b_ub=-np.ones(rows.shape[0]), A_eq=a_eq, b_eq=[1.0], bounds=(0, None), method="highs")
    if lp.status != 0:
        return None
    return float(lp.fun), np.maximum(-np.asarray(lp.ineqlin.marginals, dtype=np.float64), 0.0)
