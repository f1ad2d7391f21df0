"""A covering bound for connected choices: the tree (Hunter) bound on the union of coverage.

For sets A_1..A_k and any tree T on them, |A_1 u ... u A_k| <= sum |A_i| - sum_{(i,j) in T} |A_i n A_j| (Hunter 1976,
"An upper bound for the probability of a union", J. Appl. Prob. 13). Take A_i as the wall length station i sees among
the targets only its zone-side's candidates see (total L_g): a connected choice has a spanning tree of overlap edges,
so with y_e = 1 on that tree

    sum_i w_i x_i - sum_e s_e y_e >= L_g,   sum_e y_e = sum_i x_i - 1,   y_e <= x_u, y_e <= x_v

where w_i is station i's length and s_e the length both ends of edge e see. Linked stations share at least 30 % of the
smaller one's wall, so every station after the first pays for its overlap: the cover's LP bound rises. Lengths are
rounded to millimetres in the relaxing direction (w up, s down, L down) so that the rows stay valid on every backend.
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp

from planner.coverage.overlap import group_ids

Row = tuple[np.ndarray, np.ndarray, float]


def add_tree_bound(
    backend: Any, a: sp.csr_matrix, lengths: np.ndarray, adj: sp.csr_matrix, groups: Sequence[Hashable]
) -> int:
    """Add the tree-bound rows of every zone-side of a block (``a``: its candidates x all targets); the rows added."""
    a = a.astype(np.float64).tocsr()
    gid = group_ids(groups)
    upper = sp.triu(adj, k=1).tocoo()
    rows: list[Row] = []
    for k in range(int(gid.max(initial=-1)) + 1):
        mem = gid == k
        seen_in = np.asarray(a[mem].sum(axis=0)).ravel() > 0
        seen_out = np.asarray(a[~mem].sum(axis=0)).ravel() > 0 if (~mem).any() else np.zeros(a.shape[1], dtype=bool)
        own = seen_in & ~seen_out
        if not own.any():
            continue
        length = np.where(own, lengths, 0.0)
        members = np.flatnonzero(mem)
        w = np.ceil(np.asarray(a[members] @ length).ravel() * 1000) / 1000
        pick = mem[upper.row] & mem[upper.col]
        u, v = upper.row[pick], upper.col[pick]
        s = np.floor(np.asarray(a[u].multiply(a[v]) @ length).ravel() * 1000) / 1000
        y0 = len(backend.x)
        backend.add_vars(len(u), 1.0, binary=False)
        y = y0 + np.arange(len(u))
        total = np.floor(length.sum() * 1000) / 1000 - 0.01
        rows.append((np.concatenate([members, y]), np.concatenate([w, -s]), float(total)))
        rows.append((np.concatenate([members, y]), np.concatenate([np.ones(len(members)), -np.ones(len(u))]), 1.0))
        rows.append((np.concatenate([members, y]), np.concatenate([-np.ones(len(members)), np.ones(len(u))]), -1.0))
        rows += [(np.array([i, j]), np.array([1.0, -1.0]), 0.0) for i, j in zip(u, y)]
        rows += [(np.array([i, j]), np.array([1.0, -1.0]), 0.0) for i, j in zip(v, y)]
    backend.add_rows(rows)
    return len(rows)
