"""The LP half of geometric pricing (the other: :func:`planner.coverage.arrangement.heaviest_points`).

LP (over the current pool, x >= 0; the upper bound x <= 1 is redundant at the optimum)::

    minimise sum_j x_j   subject to   sum_{j sees t} x_j >= 1   for every piece t

Its dual prices each piece, y_t >= 0, with sum_{t seen by j} y_t <= 1 for every pooled j. A position p whose regions
carry sum_{t: p in R_t} y_t > 1 is a column of negative reduced cost; when no position has one, the LP value bounds
every cover drawn from anywhere in the plane (Tozoni, de Rezende, de Souza, "Algorithm 966", ACM TOMS 2016, do the
same for point guards).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import linprog

from planner.core.errors import InternalError


@dataclass(frozen=True, eq=False)
class CoverLp:
    """The optimum of the cover LP: its value, primal x (per candidate) and dual y (per piece)."""

    value: float
    x: NDArray[np.float64]
    y: NDArray[np.float64]


def cover_lp(by_target: sp.csr_matrix, cost: NDArray[np.float64] | None = None) -> CoverLp:
    """Solve the cover LP with HiGHS (scipy); every piece must be seen by some column."""
    n_t, n_c = by_target.shape
    c = np.ones(n_c) if cost is None else np.asarray(cost, float)
    res = linprog(c, A_ub=-by_target.astype(np.float64).tocsr(), b_ub=-np.ones(n_t), bounds=(0, None), method="highs")
    if res.status != 0:
        raise InternalError(f"cover LP ended with status {res.status}: {res.message}")
    y = np.maximum(-np.asarray(res.ineqlin.marginals, dtype=float), 0.0)
    return CoverLp(float(res.fun), np.asarray(res.x, float), y)


class WarmCoverLp:
    """The cover LP kept in one HiGHS model (``highspy``, 1 thread): columns are appended between solves and each
    re-solve starts from the last optimal basis (the new columns enter at 0, so the basis stays primal feasible)."""

    def __init__(self, by_target: sp.csr_matrix) -> None:
        import highspy

        self._h = h = highspy.Highs()
        h.setOptionValue("output_flag", False)
        h.setOptionValue("threads", 1)
        h.setOptionValue("random_seed", 0)
        n_t, _ = by_target.shape
        self.n_t = n_t
        no_entries = np.zeros(0, np.int32)
        h.addRows(n_t, np.ones(n_t), np.full(n_t, highspy.kHighsInf), 0, no_entries, no_entries, np.zeros(0))
        self.add_columns(by_target.T.tocsr())

    def add_columns(self, by_candidate: sp.csr_matrix) -> None:
        """Append candidates (rows of ``by_candidate``: the pieces each covers) as columns of cost 1."""
        a = by_candidate.astype(np.float64).tocsr()
        n = a.shape[0]
        if n == 0:
            return
        starts, index = a.indptr[:-1].astype(np.int32), a.indices.astype(np.int32)
        self._h.addCols(n, np.ones(n), np.zeros(n), np.full(n, np.inf), a.nnz, starts, index, a.data)

    def close(self) -> None:
        """Free HiGHS's model and solver data now: the ``Highs`` object sits in a reference cycle with its callbacks,
        so its memory would stay allocated until a full garbage collection, which a planning run may never reach."""
        self._h.clear()

    def solve(self) -> CoverLp:
        h = self._h
        h.run()
        status = h.getModelStatus()
        if h.modelStatusToString(status) != "Optimal":
            raise InternalError(f"cover LP ended with status {h.modelStatusToString(status)}")
        sol = h.getSolution()
        y = np.maximum(np.asarray(sol.row_dual, float), 0.0)
        return CoverLp(float(h.getInfo().objective_function_value), np.asarray(sol.col_value, float), y)
