"""Sparse least squares for :mod:`planner.network.adjustment`: the design matrix, normal equations and
the parts of their inverse the adjustment needs.

Every observation touches at most five unknowns (two points and a station's orientation), so the
design matrix A (scipy.sparse, CSR) holds at most five entries a row. The normal matrix
N = A^T P A is scaled to a unit diagonal (S N S, S = diag(N)^-1/2) and factored by SuperLU with the
diagonal as pivots (a Cholesky factorisation in LU form; fill-reducing order of N + N^T). The
adjustment needs of Q = N^-1 only

- the entries on the pattern of N: the redundancy numbers are r_i = 1 - p_i a_i Q a_i^T, and
  a_i Q a_i^T sums Q over the pairs of unknowns of observation i, which are the pattern of N;
- the 2 x 2 block of every point (its error ellipse);

so Q is formed a block of columns at a time (solves with the factor) and only those entries are kept:
memory O(entries of N + unknowns x block), not O(unknowns^2). The full coordinate covariance is
formed only when asked for (:attr:`planner.network.adjustment.Adjustment.qxx`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from planner.errors import InputError

#: observation kinds as codes (the order of :data:`planner.network.adjustment.KINDS`)
X, Y, DX, DY, DISTANCE, DIRECTION = range(6)
CODES = {"x": X, "y": Y, "dx": DX, "dy": DY, "distance": DISTANCE, "direction": DIRECTION}
#: a pivot of the unit-diagonal normal matrix below this is a datum defect (an exact defect leaves
#: a pivot of the order of the rounding error, 1e-16; a network of sound geometry, pivots near 1)
PIVOT_TOL = 1e-10
#: entries of the dense block of Q columns formed at a time
BLOCK_ENTRIES = 2_000_000
#: below this many unknowns a defect is counted as before, by the rank of the dense N
DENSE_RANK_MAX = 3000


class Design:
    """The observations of a network as index arrays, and their Jacobian at given coordinates.

    Parameters
    ----------
    names : sequence of str
        The points, in the order of the rows of the coordinate arrays.
    unknown : sequence of str
        The points to be found, in the order of their columns (x, y each).
    observations : sequence of Obs
        The observations (:class:`planner.network.adjustment.Obs`), their points among ``names``.

    Attributes
    ----------
    orient : list of str
        The stations that take directions (one orientation unknown each, after the points' columns).
    n_unknowns : int
        Columns of A.
    """

    def __init__(self, names: Sequence[str], unknown: Sequence[str], observations: Sequence[Any]) -> None:
        index = {n: i for i, n in enumerate(names)}
        self.names = list(names)
        self.orient = sorted({o.at for o in observations if o.kind == "direction"})
        ocol = {s: 2 * len(unknown) + k for k, s in enumerate(self.orient)}
        self.kind = np.array([CODES[o.kind] for o in observations], dtype=np.int64)
        self.at = np.array([index[o.at] for o in observations], dtype=np.int64)
        self.to = np.array([-1 if o.kind in ("x", "y") else index[o.to] for o in observations], dtype=np.int64)
        self.col = np.full(len(names), -1, dtype=np.int64)
        self.col[[index[n] for n in unknown]] = 2 * np.arange(len(unknown))
        self.orient_col = np.array([ocol[o.at] if o.kind == "direction" else -1 for o in observations], dtype=np.int64)
        self.n_unknowns = 2 * len(unknown) + len(self.orient)

    def jacobian(self, xy: NDArray[np.float64]) -> tuple[sp.csr_matrix, NDArray[np.float64]]:
        """A (sparse, sorted indices) and the computed values f(X0) at the points ``xy`` (n x 2, metres).

        Raises
        ------
        InputError
            On a distance or direction between coincident points.
        """
        k, at, to = self.kind, self.at, self.to
        n = len(k)
        rel = to >= 0
        to_ = np.where(rel, to, at)
        dx, dy = xy[to_, 0] - xy[at, 0], xy[to_, 1] - xy[at, 1]
        s2 = dx * dx + dy * dy
        geo = (k == DISTANCE) | (k == DIRECTION)
        bad = np.flatnonzero(geo & (s2 == 0))
        if bad.size:
            i = int(bad[0])
            raise InputError("observation between coincident points", row=i + 1, field=[*CODES][k[i]],
                             value=f"{self.names[at[i]]}->{self.names[to[i]]}")
        safe2 = np.where(geo, s2, 1.0)
        s = np.sqrt(safe2)
        f = np.select([k == X, k == Y, k == DX, k == DY, k == DISTANCE],
                      [xy[at, 0], xy[at, 1], dx, dy, s], np.arctan2(dy, dx))
        dist, dirn = k == DISTANCE, k == DIRECTION
        # the partial derivatives by the at point's x, y and the to point's x, y (section 2.1)
        ga = (np.select([dist, dirn], [-dx / s, dy / safe2], 0.0), np.select([dist, dirn], [-dy / s, -dx / safe2], 0.0))
        gt = (np.select([dist, dirn], [dx / s, -dy / safe2], 0.0), np.select([dist, dirn], [dy / s, dx / safe2], 0.0))
        rows: list[NDArray[np.int64]] = []
        cols: list[NDArray[np.int64]] = []
        vals: list[NDArray[np.float64]] = []

        def put(mask: NDArray[np.bool_], c: NDArray[np.int64], v: NDArray[np.float64] | float) -> None:
            m = mask & (c >= 0)
            rows.append(np.flatnonzero(m))
            cols.append(c[m])
            vals.append(np.broadcast_to(v, (n,))[m])

        ca, ct = self.col[at], np.where(rel, self.col[to_], -1)
        put(k == X, ca, 1.0)
        put(k == Y, np.where(ca >= 0, ca + 1, -1), 1.0)
        for comp, kk in ((0, DX), (1, DY)):
            # a relative observation of a point to itself: the to point's +1 (as the dense design wrote it last)
            put((k == kk) & (to_ != at), np.where(ca >= 0, ca + comp, -1), -1.0)
            put(k == kk, np.where(ct >= 0, ct + comp, -1), 1.0)
        for comp in (0, 1):
            put(geo, np.where(ca >= 0, ca + comp, -1), ga[comp])
            put(geo, np.where(ct >= 0, ct + comp, -1), gt[comp])
        put(dirn, self.orient_col, -1.0)
        a = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                          shape=(n, self.n_unknowns))
        a.sort_indices()
        return a, f


class Normal:
    """N = A^T P A of a design matrix, scaled to a unit diagonal and factored (see the module text).

    Raises
    ------
    InputError
        On a datum defect: some unknown is not determined by the observations.
    """

    def __init__(self, a: sp.csr_matrix, w: NDArray[np.float64]) -> None:
        self.a, self.w = a, w
        u = a.shape[1]
        n = (a.T @ sp.diags(w) @ a).tocsc()
        d = n.diagonal()
        self.s = np.where(d > 0, 1.0 / np.sqrt(np.where(d > 0, d, 1.0)), 1.0)
        self.lu = None
        if u and np.all(d > 0):
            m = sp.diags(self.s) @ n @ sp.diags(self.s)
            try:
                self.lu = spla.splu(m.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                    options={"SymmetricMode": True, "Equil": False})
            except RuntimeError:  # an exactly zero pivot
                self.lu = None
        if u and (self.lu is None or np.min(np.abs(self.lu.U.diagonal())) < PIVOT_TOL):
            raise InputError(f"datum defect: the network leaves {self._defect(n)} "
                             "unknown(s) undetermined (fix control points or add observations)", field="network")

    def _defect(self, n: sp.csc_matrix) -> int:
        """How many unknowns are undetermined: by the dense rank (as the dense solver counts) on small
        networks, else by the small pivots."""
        u = n.shape[0]
        if u <= DENSE_RANK_MAX or self.lu is None:
            return int(u - np.linalg.matrix_rank(n.toarray()))
        return int(np.sum(np.abs(self.lu.U.diagonal()) < PIVOT_TOL))

    def solve(self, b: NDArray[np.float64]) -> NDArray[np.float64]:
        """N^-1 b (b a vector or a matrix of columns)."""
        if self.lu is None:
            return np.zeros_like(b)
        s = self.s if b.ndim == 1 else self.s[:, None]
        return s * self.lu.solve(np.ascontiguousarray(s * b))

    def inverse_on(self, pattern: sp.csc_matrix) -> NDArray[np.float64]:
        """The entries of N^-1 on ``pattern`` (CSC, sorted indices), in the order of ``pattern.data``."""
        u = pattern.shape[0]
        out = np.empty(pattern.nnz)
        if self.lu is None:
            return out
        step = max(1, min(u, BLOCK_ENTRIES // max(u, 1)))
        ptr, idx = pattern.indptr, pattern.indices
        for c0 in range(0, u, step):
            c1 = min(u, c0 + step)
            e = np.zeros((u, c1 - c0))
            e[np.arange(c0, c1), np.arange(c1 - c0)] = 1.0
            x = self.lu.solve(e)  # columns c0..c1 of (S N S)^-1
            lo, hi = ptr[c0], ptr[c1]
            rows = idx[lo:hi]
            cols = np.repeat(np.arange(c0, c1), np.diff(ptr[c0:c1 + 1]))
            out[lo:hi] = x[rows, cols - c0] * self.s[rows] * self.s[cols]
        return out

    def columns(self, k: int) -> NDArray[np.float64]:
        """The first ``k`` rows and columns of N^-1 (dense)."""
        u = self.a.shape[1]
        e = np.zeros((u, k))
        e[np.arange(k), np.arange(k)] = 1.0
        return self.solve(e)[:k]


def selected_inverse(normal: Normal, n_points: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """diag(A Q A^T) per observation and the 2 x 2 blocks of Q per unknown point (``n_points`` x 2 x 2),
    from the entries of Q on the pattern of N and on the points' blocks only."""
    a = normal.a
    u = a.shape[1]
    ones = sp.csr_matrix((np.ones(a.nnz), a.indices, a.indptr), shape=a.shape)
    k = np.arange(2 * n_points)
    partner = k ^ 1  # x <-> y of the same point
    blocks = sp.csc_matrix((np.ones(2 * len(k)), (np.concatenate([k, k]), np.concatenate([k, partner]))), shape=(u, u))
    pattern = (ones.T @ ones + blocks).tocsc()
    pattern.sort_indices()
    q = normal.inverse_on(pattern)
    keys = np.repeat(np.arange(u, dtype=np.int64), np.diff(pattern.indptr)) * u + pattern.indices

    def entry(r: NDArray[np.int64], c: NDArray[np.int64]) -> NDArray[np.float64]:
        return q[np.searchsorted(keys, c.astype(np.int64) * u + r)]

    lengths = np.diff(a.indptr)
    qa = np.zeros(a.shape[0])
    for p in range(int(lengths.max(initial=0))):
        for r in range(int(lengths.max(initial=0))):
            rows = np.flatnonzero(lengths > max(p, r))
            ip, ir = a.indptr[rows] + p, a.indptr[rows] + r
            qa[rows] += a.data[ip] * a.data[ir] * entry(a.indices[ip], a.indices[ir])
    x, y = 2 * np.arange(n_points), 2 * np.arange(n_points) + 1
    b = np.stack([entry(x, x), entry(y, x), entry(y, x), entry(y, y)], axis=1).reshape(n_points, 2, 2)
    return qa, b
