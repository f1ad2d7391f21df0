"""Lower bounds on the shortest visiting order: the Held-Karp 1-tree bound with a subgradient ascent, and
the exact Held-Karp dynamic programme for a few stations (a cross-check).

Node 0 is the start. A closed tour is the travelling salesman tour through every node. An open path
from node 0 (ending anywhere) is the tour through the nodes and a dummy node D that is joined to node 0
at cost 0 and to the path's last node at cost 0; its 1-tree is a spanning tree of the nodes, the edge
D-0 and D's cheapest other edge. With node penalties pi (edge cost c_ij + pi_i + pi_j) every 1-tree
costs at most the penalised optimum, which is the optimum plus 2 sum(pi): so

    L(pi) = one_tree(pi) - 2 sum(pi) <= optimum   for every pi,

and the ascent moves pi along the degree excess (deg - 2) with Polyak steps towards an upper bound.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

#: subgradient steps (each one minimum spanning tree, O(n^2) in numpy)
ASCENT_STEPS = 1500
#: the exact programme runs up to this many nodes (2^n n^2 work)
EXACT_MAX_NODES = 13


def _prim(c: NDArray[np.float64]) -> tuple[float, NDArray[np.int64]]:
    """Minimum spanning tree of the complete graph with costs ``c``: its cost and each node's degree."""
    n = len(c)
    deg = np.zeros(n, dtype=np.int64)
    if n < 2:
        return 0.0, deg
    inside = np.zeros(n, dtype=bool)
    inside[0] = True
    best, parent = c[0].copy(), np.zeros(n, dtype=np.int64)
    total = 0.0
    for _ in range(n - 1):
        cand = np.where(inside, np.inf, best)
        k = int(np.argmin(cand))
        total += float(cand[k])
        deg[k] += 1
        deg[parent[k]] += 1
        inside[k] = True
        closer = c[k] < best
        best = np.where(closer, c[k], best)
        parent = np.where(closer, k, parent)
    return total, deg


def one_tree(d: NDArray[np.float64], pi: NDArray[np.float64], closed: bool) -> tuple[float, NDArray[np.int64]]:
    """L(pi) of the module text and the degree of each node in the 1-tree."""
    c = d + pi[:, None] + pi[None, :]
    if closed:
        cost, deg_rest = _prim(c[1:, 1:])
        two = np.argsort(c[0, 1:], kind="stable")[:2] + 1
        deg = np.concatenate([[2], deg_rest])
        deg[two] += 1
        return cost + float(c[0, two].sum()) - 2.0 * float(pi.sum()), deg
    cost, deg = _prim(c)
    last = int(np.argmin(pi[1:])) + 1
    deg[0] += 1
    deg[last] += 1
    return cost + float(pi[0] + pi[last]) - 2.0 * float(pi.sum()), deg


def held_karp_bound(d: NDArray[np.float64], upper: float, closed: bool = False, steps: int = ASCENT_STEPS) -> float:
    """The best L(pi) found by the subgradient ascent (a lower bound on the optimum); ``upper``: the length
    of a known order (Polyak step target)."""
    n = len(d)
    if n <= 1:
        return 0.0
    if n == 2:
        return float(d[0, 1]) * (2.0 if closed else 1.0)
    pi, best, lam, since = np.zeros(n), -math.inf, 2.0, 0
    for _ in range(steps):
        value, deg = one_tree(d, pi, closed)
        if value > best + 1e-9:
            best, since = value, 0
        else:
            since += 1
            if since >= 50:  # no progress for a while: smaller steps
                lam, since = lam / 2.0, 0
        g = (deg - 2).astype(float)
        norm = float(g @ g)
        if norm == 0.0 or lam < 1e-6 or upper - best <= 1e-9 * max(upper, 1.0):
            break  # the 1-tree is a tour/path: optimal
        pi += lam * max(upper - value, 1e-6 * max(upper, 1.0)) / norm * g
    return max(best, 0.0)


def exact_order(d: NDArray[np.float64], closed: bool = False) -> tuple[float, list[int]]:
    """The shortest tour (``closed``) or path from node 0 by Held-Karp's dynamic programme (n <= 13)."""
    n = len(d)
    if n > EXACT_MAX_NODES:
        raise ValueError(f"the exact programme is for at most {EXACT_MAX_NODES} nodes, got {n}")
    if n == 1:
        return 0.0, [0]
    full = 1 << (n - 1)
    cost = np.full((full, n - 1), np.inf)
    back = np.full((full, n - 1), -1, dtype=np.int64)
    for k in range(n - 1):
        cost[1 << k, k] = d[0, k + 1]
    for mask in range(1, full):
        for k in range(n - 1):
            if not mask >> k & 1 or not math.isfinite(cost[mask, k]):
                continue
            for j in range(n - 1):
                if mask >> j & 1:
                    continue
                nxt = mask | 1 << j
                v = cost[mask, k] + d[k + 1, j + 1]
                if v < cost[nxt, j]:
                    cost[nxt, j], back[nxt, j] = v, k
    last = cost[full - 1] + (d[1:, 0] if closed else 0.0)
    k = int(np.argmin(last))
    total = float(last[k])
    order, mask = [], full - 1
    while k >= 0:
        order.append(k + 1)
        k, mask = int(back[mask, k]), mask & ~(1 << k)
    return total, [0] + order[::-1]
