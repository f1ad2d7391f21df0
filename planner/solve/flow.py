"""Registration connectivity as a single-commodity flow (Dehbi et al., ISPRS J. 2021).

Per group g (zone-side) with members V_g and the overlap edges among them as arcs in both directions, with U_g an
upper bound on the group's station count:

    r_i in {0, 1},  r_i <= x_i,  sum_{i in V_g} r_i <= 1  (= 1 when g has essential targets)
    0 <= f_ij <= (U_g - 1) x_i,   f_ij <= (U_g - 1) x_j               every arc (i, j)
    sum_j f_ji - sum_j f_ij >= x_i - U_g r_i                          every i in V_g

The root (the station with r_i = 1, chosen by the solver) sends one unit to every other chosen station along chosen
stations only. A chosen part without the root would need a net inflow equal to its size, but no flow enters it (flow
runs only between chosen, overlapping stations), so every feasible x is connected; and a connected choice routes the
units along a spanning tree. U_g is |V_g|, or less when an incumbent plan bounds the station count (only plans at most
as costly as it are sought).
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order

from planner.solve.connectivity import group_members


class FlowModel:
    """The flow variables and rows of every group, added to ``backend`` (which must have ``add_vars``), and their
    layout, so that a plan can be turned into a full hint."""

    def __init__(
        self,
        backend: Any,
        adj: sp.csr_matrix,
        groups: Sequence[Hashable],
        essential: dict[Hashable, np.ndarray],
        cost: np.ndarray,
        incumbent: Sequence[int] | None,
    ) -> None:
        self.adj = adj.tocsr()
        index = group_members(groups, range(len(groups)))
        self.members = {g: np.asarray(v, dtype=np.int64) for g, v in index.items()}
        self.essential = essential
        cap = len(cost)
        if incumbent is not None and len(incumbent) and cost.min() > 0:
            cap = int(np.floor(cost[list(incumbent)].sum() / cost.min() + 1e-9))
        self.upper = {g: max(1, min(len(m), cap)) for g, m in self.members.items()}
        self.root: dict[Hashable, int] = {}  # group -> index of its first root variable
        self.arcs: dict[Hashable, tuple[int, np.ndarray, np.ndarray]] = {}  # group -> (first arc var, tails, heads)
        rows = []
        for g, m in self.members.items():
            u = self.upper[g]
            sub = self.adj[m][:, m].tocoo()
            tails, heads = m[sub.row], m[sub.col]  # both directions: adj is symmetric
            r0 = len(backend.x)
            backend.add_vars(len(m), 1.0, binary=True)
            f0 = len(backend.x)
            backend.add_vars(len(tails), float(max(u - 1, 0)), binary=False)
            self.root[g], self.arcs[g] = r0, (f0, tails, heads)
            r = r0 + np.arange(len(m))
            rows += [(np.array([i, ri]), np.array([1.0, -1.0]), 0.0) for i, ri in zip(m, r)]
            rows.append((r, -np.ones(len(m)), -1.0))
            ess = self.essential.get(g)
            if ess is not None and ess.any():
                rows.append((r, np.ones(len(m)), 1.0))
            f = f0 + np.arange(len(tails))
            rows += [(np.array([t, fk]), np.array([u - 1.0, -1.0]), 0.0) for t, fk in zip(tails, f)]
            rows += [(np.array([h, fk]), np.array([u - 1.0, -1.0]), 0.0) for h, fk in zip(heads, f)]
            pos = {int(v): k for k, v in enumerate(m)}
            into: list[list[int]] = [[] for _ in m]
            out: list[list[int]] = [[] for _ in m]
            for k, (t, h) in enumerate(zip(tails, heads)):
                out[pos[int(t)]].append(int(f[k]))
                into[pos[int(h)]].append(int(f[k]))
            for k, i in enumerate(m):
                idx = np.array(into[k] + out[k] + [int(i), int(r[k])], dtype=np.int64)
                coef = np.concatenate([np.ones(len(into[k])), -np.ones(len(out[k])), [-1.0, float(u)]])
                rows.append((idx, coef, 0.0))
        backend.add_rows(rows)

    def hint(self, selected: Sequence[int]) -> dict[int, float]:
        """Values of every variable for a connected plan: x, a root per group, a BFS tree's flows."""
        on = np.zeros(self.adj.shape[0], dtype=bool)
        on[list(selected)] = True
        values = {int(i): 1.0 for i in selected}
        for g, m in self.members.items():
            r0 = self.root[g]
            f0, tails, heads = self.arcs[g]
            values.update({r0 + k: 0.0 for k in range(len(m))})
            values.update({f0 + k: 0.0 for k in range(len(tails))})
            chosen = m[on[m]]
            if chosen.size == 0:
                continue
            root = int(chosen[0])
            values[r0 + int(np.flatnonzero(m == root)[0])] = 1.0
            keep = sp.diags(on.astype(float)) @ self.adj @ sp.diags(on.astype(float))
            order, pred = breadth_first_order(keep.tocsr(), root, directed=False, return_predecessors=True)
            below = {int(v): 1.0 for v in order}
            for v in order[::-1]:  # subtree sizes, leaves first
                p = int(pred[v])
                if p >= 0:
                    below[p] += below[int(v)]
            arc = {(int(t), int(h)): f0 + k for k, (t, h) in enumerate(zip(tails, heads))}
            for v in order:
                p = int(pred[v])
                if p >= 0:
                    values[arc[(p, int(v))]] = below[int(v)]
        return values
