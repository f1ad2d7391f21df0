"""The normal equations N = A^T P A of a network adjustment: factored once, solved, and of Q = N^-1 the entries the
results need (:mod:`planner.network.lsq_sparse`).

The orientation unknowns (one per station that takes directions) are eliminated first: each direction observation holds
one of them, so their block of N is diagonal, and the reduced matrix of the points' coordinates is N* = N_pp - N_po
N_oo^-1 N_op (the reduced normal equations of geodesy). N* is scaled to a unit diagonal (S N* S, S = diag(N*)^-1/2) and
factored:

- by LAPACK's Cholesky on a dense N* where that is no larger than ``DENSE_MAX`` unknowns and not sparse (most of it
  filled, or small): Q_pp = N*^-1 whole, and of the orientations' rows only Q_op = -N_oo^-1 N_op Q_pp and the diagonal
  of Q_oo;
- else by SuperLU (the diagonal as pivots: a Cholesky factorisation in LU form) on the sparse N*, and Q_pp only on the
  pattern the results need, a block of columns at a time (memory O(entries + unknowns x block)).

Either way the matrix is singular, a datum defect, where a diagonal entry of N* is below ``PIVOT_TOL`` times that of
N_pp (a point whose only tie is a single direction from a station keeps, after the station's orientation is eliminated, a
diagonal of rounding noise, which the unit scaling would make look sound), or a pivot or the smallest eigenvalue of
S N* S is below ``PIVOT_TOL`` (:func:`_singular`). The dense solver (:mod:`planner.network.lsq_dense`) decides and
counts a defect with the same rule (:func:`refuse_defect`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from planner.core.errors import InputError

#: a pivot of the unit-diagonal normal matrix below this is a datum defect (an exact defect leaves
#: a pivot of the order of the rounding error, 1e-16; a network of sound geometry, pivots near 1)
PIVOT_TOL = 1e-10
#: the most point unknowns factored dense (8 bytes each squared: 288 MB), and the share of N* filled
#: above which it is (or always, up to ``DENSE_SMALL`` unknowns)
DENSE_MAX, DENSE_FILL, DENSE_SMALL = 6000, 0.02, 1500
#: entries of the dense block of Q columns formed at a time (sparse factor)
BLOCK_ENTRIES = 2_000_000
#: below this many unknowns a defect is counted as the dense solver counts it, by the rank of N
DENSE_RANK_MAX = 3000

Lookup = Callable[[NDArray[np.int64], NDArray[np.int64]], NDArray[np.float64]]


def _splu(m: sp.spmatrix) -> spla.SuperLU:
    """SuperLU of a symmetric positive (semi)definite ``m`` with the diagonal as pivots: a Cholesky factorisation in LU
    form."""
    return spla.splu(
        m.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True, "Equil": False}
    )


def _unit(n: NDArray[np.float64]) -> NDArray[np.float64]:
    """``n`` scaled to a unit diagonal (a zero diagonal entry left 0): the rank and pivots of N do not depend on the
    units of the observations' weights."""
    d = np.diagonal(n)
    s = np.where(d > 0, 1.0 / np.sqrt(np.where(d > 0, d, 1.0)), 0.0)
    return np.asarray(n * s[:, None] * s[None, :])


def _defect(n: sp.spmatrix, pivots: NDArray[np.float64] | None) -> InputError:
    """The datum-defect error, with how many unknowns are undetermined (at least 1): the rank of N on the unit diagonal
    (small networks; both solvers count it so), else the small pivots (of a factorisation of N + 1e-13 I on the unit
    diagonal where none came)."""
    u = n.shape[0]
    if u <= DENSE_RANK_MAX:
        count = max(1, int(u - np.linalg.matrix_rank(_unit(n.toarray()))))
    else:
        if pivots is None:
            d = n.diagonal()
            s = sp.diags(1.0 / np.sqrt(np.where(d > 0, d, 1.0)))
            pivots = _splu(s @ n @ s + 1e-13 * sp.identity(u)).U.diagonal()
        count = max(1, int(np.sum(np.abs(pivots) < PIVOT_TOL)))
    return InputError(
        f"datum defect: the network leaves {count} unknown(s) undetermined (fix control points or add observations)",
        field="network",
    )


def _singular(pivots: NDArray[np.float64], solve: Callable[[NDArray[np.float64]], NDArray[np.float64]]) -> bool:
    """Whether the factored unit-diagonal matrix (its ``pivots``, and ``solve`` with its factor) is singular: a pivot
    below ``PIVOT_TOL``, or its smallest eigenvalue, by three steps of inverse iteration from a fixed start, below it.
    The pivots alone miss a defect where the elimination order makes an earlier pivot small (1e-7, say, fixing a
    rotation by one coordinate nearly along it): the last, exactly 0, then carries that pivot's amplified rounding error
    (1e-9, say) above the bound, whatever the order; the eigenvalue does not depend on the order."""
    if not len(pivots):
        return False
    if np.min(np.abs(pivots)) < PIVOT_TOL:
        return True
    x = np.random.default_rng(0).standard_normal(len(pivots))
    for _ in range(3):
        x = solve(x / np.linalg.norm(x))
        size = float(np.linalg.norm(x))
        if not np.isfinite(size) or size * PIVOT_TOL > 1.0:  # |m^-1 x| > 1 / PIVOT_TOL: an eigenvalue below it
            return True
    return False


def refuse_defect(n: NDArray[np.float64]) -> None:
    """InputError where the dense normal matrix ``n`` has a datum defect, by the rule of :class:`Normal`
    (:func:`_singular` of ``n`` on the unit diagonal; none positive definite: a defect too)."""
    m = _unit(n)
    try:
        chol = sla.cholesky(m, lower=True, check_finite=False)
    except np.linalg.LinAlgError:
        raise _defect(sp.csc_matrix(n), None) from None
    pivots = np.diag(chol) ** 2
    if np.min(np.diagonal(n), initial=1.0) <= 0 or _singular(
        pivots, lambda b: np.asarray(sla.cho_solve((chol, True), b, check_finite=False))
    ):
        raise _defect(sp.csc_matrix(n), pivots)


class Normal:
    """N = A^T P A of a design matrix ``a`` (its last ``n_orient`` columns orientation unknowns, each observation
    holding at most one) and weights ``w`` = 1 / sigma^2, reduced and factored (see the module text). Raises InputError
    on a datum defect: some unknown not determined by the observations.
    """

    def __init__(self, a: sp.csr_matrix, w: NDArray[np.float64], n_orient: int = 0) -> None:
        self.a, self.w = a, w
        u = a.shape[1]
        self.k = k = u - n_orient
        n = (a.T @ sp.diags(w) @ a).tocsc()
        self.npo = n[:k, k:].tocsc()
        self.noo = n[k:, k:].diagonal()
        reduced = self._reduced(a, w, k)
        d, d0 = reduced.diagonal(), n.diagonal()[:k]
        self.s = np.where(d > 0, 1.0 / np.sqrt(np.where(d > 0, d, 1.0)), 1.0)
        self.lu: spla.SuperLU | None = None
        self.chol: NDArray[np.float64] | None = None
        self.qpp: NDArray[np.float64] | None = None
        if np.any(self.noo <= 0) or np.any(d <= PIVOT_TOL * d0):
            raise _defect(n, None)
        if not k:
            return
        m = sp.diags(self.s) @ reduced @ sp.diags(self.s)
        dense = k <= DENSE_SMALL or (k <= DENSE_MAX and reduced.nnz >= DENSE_FILL * k * k)
        try:
            if dense:
                self.chol = np.asarray(sla.cholesky(m.toarray(), lower=True, check_finite=False))
                pivots = np.diag(self.chol) ** 2
            else:
                self.lu = _splu(m)
                pivots = self.lu.U.diagonal()
        except (np.linalg.LinAlgError, RuntimeError):  # not positive definite, or an exactly zero pivot
            raise _defect(n, None) from None
        if _singular(pivots, lambda b: self._solve_reduced(b / self.s) / self.s):  # (S N* S)^-1 b
            raise _defect(n, pivots)

    def _reduced(self, a: sp.csr_matrix, w: NDArray[np.float64], k: int) -> sp.csc_matrix:
        """N* = N_pp - N_po N_oo^-1 N_op, formed as A~^T P A~ with each direction's row of A_p less its station's
        weighted mean row (times its orientation coefficient): the same matrix, but a sum of squares of small
        differences, where the difference of the two large matrices kept only the digits their cancellation left
        (1e-9 of the redundancy numbers on a network of 7 points and 43 directions, whose condition allows 1e-13)."""
        ap, ao = a[:, :k].tocsr(), a[:, k:].tocsr()
        mean = sp.diags(1.0 / np.where(self.noo > 0, self.noo, 1.0)) @ self.npo.T  # N_oo^-1 N_op: one row a station
        self.centred = centred = (ap - ao @ mean).tocsr()
        return (centred.T @ sp.diags(w) @ centred).tocsc()

    def _solve_reduced(self, b: NDArray[np.float64]) -> NDArray[np.float64]:
        s = self.s if b.ndim == 1 else self.s[:, None]
        if self.chol is not None:
            x = sla.cho_solve((self.chol, True), s * b, check_finite=False)
        elif self.lu is not None:
            x = self.lu.solve(np.ascontiguousarray(s * b))
        else:
            return np.zeros_like(b)
        return np.asarray(s * x)

    def solve(self, b: NDArray[np.float64]) -> NDArray[np.float64]:
        """N^-1 b for a vector b (the points' unknowns first, then the orientations)."""
        k = self.k
        bp, bo = b[:k], b[k:]
        xp = self._solve_reduced(bp - self.npo @ (bo / self.noo))
        return np.concatenate([xp, (bo - self.npo.T @ xp) / self.noo])

    def columns(self, k: int) -> NDArray[np.float64]:
        """The first ``k`` rows and columns of N^-1 (dense; ``k`` at most the points' unknowns)."""
        e = np.zeros((self.k, k))
        e[np.arange(k), np.arange(k)] = 1.0
        return self._solve_reduced(e)[:k]

    def _pp_inverse(self) -> NDArray[np.float64]:
        if self.qpp is None:
            assert self.chol is not None
            # two triangular solves, not LAPACK's potri: OpenBLAS runs potri on its threads even for a 48 x 48
            # factor, and on a busy machine waiting for them took 100 ms a call (0.05 ms on one thread)
            inv = sla.cho_solve((self.chol, True), np.eye(len(self.chol)), check_finite=False)
            inv = np.tril(inv) + np.tril(inv, -1).T
            self.qpp = inv * self.s[:, None] * self.s[None, :]
        return self.qpp

    def inverse(self, pattern: sp.csc_matrix) -> Lookup:
        """Q = N^-1 at given (row, column) index pairs, all of them on ``pattern`` (CSC, sorted indices, symmetric,
        holding every 2 x 2 block of a point's pair of columns and no two orientations)."""
        k, u = self.k, pattern.shape[0]
        if self.chol is not None or not k:
            qpp = self._pp_inverse() if k else np.zeros((0, 0))
        else:
            pp = pattern[:k, :k].tocsc()
            pp.sort_indices()
            values = self._pp_on(pp)
            keys = np.repeat(np.arange(k, dtype=np.int64), np.diff(pp.indptr)) * k + pp.indices

            def pp_entry(r: NDArray[np.int64], c: NDArray[np.int64]) -> NDArray[np.float64]:
                return values[np.searchsorted(keys, c.astype(np.int64) * k + r)]

        dinv = 1.0 / self.noo
        # Q_op = -N_oo^-1 N_op Q_pp and diag Q_oo = N_oo^-1 + N_oo^-2 N_op Q_pp N_po, where the pattern needs them
        op = pattern[k:, :k].tocoo()
        o, p = op.row.astype(np.int64), op.col.astype(np.int64)
        npo = self.npo
        if self.chol is not None or not k:
            t = np.asarray(npo.T @ qpp) if k else np.zeros((u - k, 0))  # N_op Q_pp
            q_op = -dinv[o] * t[o, p]
            qoo = dinv + dinv**2 * np.asarray(sp.csr_matrix(npo.T).multiply(t).sum(axis=1)).ravel()
        else:
            j_of = [npo.indices[npo.indptr[t] : npo.indptr[t + 1]] for t in range(u - k)]
            v_of = [npo.data[npo.indptr[t] : npo.indptr[t + 1]] for t in range(u - k)]
            lens = np.array([len(j) for j in j_of], dtype=np.int64)
            rep = np.repeat(np.arange(len(o)), lens[o])
            jj = np.concatenate([j_of[t] for t in o]) if len(o) else np.zeros(0, dtype=np.int64)
            vv = np.concatenate([v_of[t] for t in o]) if len(o) else np.zeros(0)
            q_op = -dinv[o] * np.bincount(rep, vv * pp_entry(jj, p[rep]), minlength=len(o))
            qoo = dinv + dinv**2 * np.array(
                [
                    v @ pp_entry(np.repeat(j, len(j)), np.tile(j, len(j))).reshape(len(j), len(j)) @ v
                    for j, v in zip(j_of, v_of)
                ]
            )
        op_keys = o * k + p
        order = np.argsort(op_keys)
        op_keys, q_op = op_keys[order], q_op[order]

        def entry(r: NDArray[np.int64], c: NDArray[np.int64]) -> NDArray[np.float64]:
            r, c = np.asarray(r, dtype=np.int64), np.asarray(c, dtype=np.int64)
            lo, hi = np.minimum(r, c), np.maximum(r, c)
            out = np.empty(len(r))
            both = hi < k
            if self.chol is not None or not k:
                out[both] = qpp[lo[both], hi[both]]
            else:
                out[both] = pp_entry(lo[both], hi[both])
            mixed = (lo < k) & (hi >= k)
            out[mixed] = q_op[np.searchsorted(op_keys, (hi[mixed] - k) * k + lo[mixed])]
            orient = lo >= k
            out[orient] = qoo[lo[orient] - k]  # one orientation per observation: only the diagonal is asked
            return out

        return entry

    def _pp_on(self, pattern: sp.csc_matrix) -> NDArray[np.float64]:
        """The entries of N*^-1 on ``pattern`` (CSC, sorted indices), in the order of ``pattern.data``."""
        u = pattern.shape[0]
        out = np.empty(pattern.nnz)
        assert self.lu is not None
        step = max(1, min(u, BLOCK_ENTRIES // max(u, 1)))
        ptr, idx = pattern.indptr, pattern.indices
        for c0 in range(0, u, step):
            c1 = min(u, c0 + step)
            e = np.zeros((u, c1 - c0))
            e[np.arange(c0, c1), np.arange(c1 - c0)] = 1.0
            x = self.lu.solve(e)  # columns c0..c1 of (S N* S)^-1
            lo, hi = ptr[c0], ptr[c1]
            rows = idx[lo:hi]
            cols = np.repeat(np.arange(c0, c1), np.diff(ptr[c0 : c1 + 1]))
            out[lo:hi] = x[rows, cols - c0] * self.s[rows] * self.s[cols]
        return out
