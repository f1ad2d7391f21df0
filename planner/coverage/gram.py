"""Candidate x candidate products of the coverage matrix, in row blocks, keeping only the pairs asked for.

The full product A W A^T (shared wall between every two candidates) of a dense pool has up to C^2 entries even when only
a few pairs matter; computing it a block of rows at a time and filtering each block keeps memory proportional to the
pairs kept plus one block.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

#: entries of one block's product (rows x candidates at worst) before filtering
BLOCK_ENTRIES = 8_000_000


def cat(xs: list[np.ndarray], dt: type) -> np.ndarray:
    """The arrays ``xs`` end to end as ``dt`` (empty when there are none)."""
    return np.concatenate(xs).astype(dt) if xs else np.zeros(0, dt)


Keep = Callable[[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]], NDArray[np.bool_]]


def filtered_gram(a: sp.csr_matrix, weights: NDArray[np.float64] | None, keep: Keep) -> sp.csr_matrix:
    """The C x C matrix A diag(w) A^T restricted to the entries (i, j, v) where ``keep(i, j, v)`` holds. ``keep`` gets
    global row and column indices and the values of one block at a time."""
    a = a.astype(np.float64).tocsr()
    n = a.shape[0]
    right = (a if weights is None else a @ sp.diags(np.asarray(weights, float))).T.tocsc()
    step = max(1, BLOCK_ENTRIES // max(n, 1))  # a block's product has at most step x n entries
    rows, cols, vals = [], [], []
    for lo in range(0, n, step):
        prod = (a[lo : lo + step] @ right).tocoo()
        r, c, v = prod.row.astype(np.int64) + lo, prod.col.astype(np.int64), prod.data
        m = keep(r, c, v)
        rows.append(r[m])
        cols.append(c[m])
        vals.append(v[m])
    out = sp.csr_matrix((cat(vals, np.float64), (cat(rows, np.int64), cat(cols, np.int64))), shape=(n, n))
    out.sort_indices()
    return out
