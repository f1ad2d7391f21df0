"""The overlap relation formed row by row as the dominance presolve asks for it, and kept only for the kept.

The connected MILP needs the overlap relation among the candidates the presolve keeps; the presolve needs, for
a candidate under test, its own links and those of the kept candidates that could replace it. Formed whole, the
relation is quadratic in a pool where thousands of candidates see much of one wall: polygon C on a 3-m grid,
22,367 distinct coverage rows, 26.7 million links and 2.2 GB to form them, of which the presolve keeps 2,238
candidates whose rows hold 2.9 million links (measured). Here rows are formed a block at a time in the
presolve's order (the candidate under test and the next ones), the rows of dropped candidates are let go at
once, and the relation among the kept is assembled at the end: memory follows the kept candidates' links plus
one block.

Links are formed among one representative per distinct (group, coverage row) only, as
:func:`planner.solve.milp.representatives` chooses them; the others get no links and are dropped by the
presolve in favour of their representative (same coverage; nothing to cover in links).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.coverage.gram import BLOCK_ENTRIES
from planner.coverage.overlap import OverlapRule, link_filter


class LazyLinks:
    """Rows of the overlap relation of ``a`` (candidates x pieces) under ``rule``, formed on demand.

    ``reps``: the candidates that get links (ascending); ``gid``: group of each candidate; ``order``: the order
    in which the presolve asks (rows are formed in blocks along it).
    """

    def __init__(self, a: sp.csr_matrix, lengths: NDArray[np.float64], rule: OverlapRule, gid: NDArray[np.int64],
                 reps: NDArray[np.int64], order: NDArray[np.int64]) -> None:
        self.n = a.shape[0]
        self._a = a.astype(np.float64).tocsr()
        self._reps = np.asarray(reps, dtype=np.int64)
        self._right = (self._a[self._reps] @ sp.diags(np.asarray(lengths, float))).T.tocsc()
        self._is_rep = np.zeros(self.n, dtype=bool)
        self._is_rep[self._reps] = True
        covered = np.asarray(self._a @ lengths).ravel()
        _, self._keep = link_filter(rule, covered, gid)
        self._order = np.asarray(order, dtype=np.int64)[self._is_rep[order]]
        self._pos = np.full(self.n, -1, dtype=np.int64)
        self._pos[self._order] = np.arange(self._order.size)
        self._rows: dict[int, NDArray[np.int64]] = {}
        self._step = max(1, BLOCK_ENTRIES // max(self._reps.size, 1))

    def row(self, i: int) -> NDArray[np.int64]:
        """The candidates linked to ``i`` (sorted); forms i's block when i's row is not held."""
        if not self._is_rep[i]:
            return np.zeros(0, dtype=np.int64)
        got = self._rows.get(i)
        if got is None:
            self._form(int(self._pos[i]))
            got = self._rows[i]
        return got

    def drop(self, i: int) -> None:
        """Let go of a dropped candidate's row (it is never asked for again)."""
        self._rows.pop(i, None)

    def _form(self, start: int) -> None:
        block = [int(c) for c in self._order[start:start + self._step] if int(c) not in self._rows]
        idx = np.asarray(block, dtype=np.int64)
        prod = (self._a[idx] @ self._right).tocoo()
        r, c, v = idx[prod.row], self._reps[prod.col], prod.data
        ok = self._keep(r, c, v)
        r, c = r[ok], c[ok]
        order = np.lexsort((c, r))
        r, c = r[order], c[order]
        cuts = np.searchsorted(r, idx)
        ends = np.searchsorted(r, idx, side="right")
        for k, i in enumerate(block):
            self._rows[i] = c[cuts[k]:ends[k]]

    def among(self, kept: NDArray[np.int64]) -> sp.csr_matrix:
        """The relation among ``kept`` (n x n, entries only between kept candidates), from the rows held."""
        mask = np.zeros(self.n, dtype=bool)
        mask[kept] = True
        rows, cols = [], []
        for i in np.asarray(kept).tolist():
            nb = self.row(i)
            nb = nb[mask[nb]]
            rows.append(np.full(nb.size, i, dtype=np.int64))
            cols.append(nb)
        r = np.concatenate(rows) if rows else np.zeros(0, np.int64)
        c = np.concatenate(cols) if cols else np.zeros(0, np.int64)
        return sp.csr_matrix((np.ones(r.size, dtype=bool), (r, c)), shape=(self.n, self.n))
