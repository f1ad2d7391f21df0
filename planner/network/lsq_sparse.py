"""Sparse least squares for :mod:`planner.network.adjustment`: the design matrix, and of Q = N^-1 the entries the
results need.

Every observation touches at most five unknowns (two points and a station's orientation), so the design matrix A
(scipy.sparse, CSR) holds at most five entries a row, and the normal equations (:class:`planner.network.normal.Normal`)
are sparse. The adjustment needs of Q only

- the entries on the pattern of N: the redundancy numbers are r_i = 1 - p_i a_i Q a_i^T, and a_i Q a_i^T sums Q over the
  pairs of unknowns of observation i, which are the pattern of N;
- the 2 x 2 block of every point (its error ellipse);

so only those are formed: time and memory grow with the observations, not with their square. The full coordinate
covariance is formed only when asked for (:attr:`planner.network.adjustment.Adjustment.qxx`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.core.errors import InputError
from planner.network.normal import Normal

#: observation kinds as codes (the order of :data:`planner.network.adjustment.KINDS`)
X, Y, DX, DY, DISTANCE, DIRECTION = range(6)
CODES = {"x": X, "y": Y, "dx": DX, "dy": DY, "distance": DISTANCE, "direction": DIRECTION}


class Design:
    """The observations of a network as index arrays, and their Jacobian at given coordinates.

    ``names``: the points, in the order of the rows of the coordinate arrays; ``unknown``: the points to be found, in
    the order of their columns (x, y each); ``observations``: :class:`planner.network.adjustment.Obs`. ``orient``: the
    stations that take directions (one orientation unknown each, after the points' columns); ``n_unknowns``: the columns
    of A.
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
        """A (sparse, sorted indices) and the computed values f(X0) at the points ``xy`` (n x 2, metres); InputError on
        a distance or direction between coincident points."""
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
            raise InputError(
                "observation between coincident points",
                row=i + 1,
                field=[*CODES][k[i]],
                value=f"{self.names[at[i]]}->{self.names[to[i]]}",
            )
        safe2 = np.where(geo, s2, 1.0)
        s = np.sqrt(safe2)
        f = np.select(
            [k == X, k == Y, k == DX, k == DY, k == DISTANCE], [xy[at, 0], xy[at, 1], dx, dy, s], np.arctan2(dy, dx)
        )
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
        a = sp.csr_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, self.n_unknowns)
        )
        a.sort_indices()
        return a, f


def selected_inverse(normal: Normal, n_points: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """diag(A Q A^T) per observation and the 2 x 2 blocks of Q per unknown point (``n_points`` x 2 x 2), from the
    entries of Q on the pattern of N (and of the points' blocks) only."""
    a = normal.a
    u, k = a.shape[1], normal.k
    ones = sp.csr_matrix((np.ones(a.nnz), a.indices, a.indptr), shape=a.shape)
    c = np.arange(2 * n_points)
    blocks = sp.csc_matrix((np.ones(2 * len(c)), (np.concatenate([c, c]), np.concatenate([c, c ^ 1]))), shape=(u, u))
    # the points coupled through an orientation: the fill of its elimination (planner.network.normal)
    through = ones[:, :k].T @ ones[:, k:]
    fill = sp.block_diag([through @ through.T, sp.csr_matrix((u - k, u - k))]).tocsc()
    pattern = (ones.T @ ones + blocks + fill).tocsc()
    pattern.sort_indices()
    entry = normal.inverse(pattern)
    ao = a[:, k:].tocsr()
    oriented = np.diff(ao.indptr) > 0
    lengths = np.where(oriented, 0, np.diff(a.indptr))
    most = int(lengths.max(initial=0))
    qa = np.zeros(a.shape[0])
    for p in range(most):
        for r in range(most):
            rows = np.flatnonzero(lengths > max(p, r))
            ip, ir = a.indptr[rows] + p, a.indptr[rows] + r
            qa[rows] += a.data[ip] * a.data[ir] * entry(a.indices[ip], a.indices[ir])
    # a direction: a Q a^T = a~ Q_pp a~^T + c^2 / N_oo with a~ its row less the station's mean (normal.Normal._reduced),
    # c its orientation coefficient; the sum over a's own entries cancels to ~1e-9 where the redundancy is ~0
    station = np.full(a.shape[0], -1, dtype=np.int64)
    station[oriented] = ao.indices[ao.indptr[:-1][oriented]]
    coef = np.zeros(a.shape[0])
    coef[oriented] = ao.data[ao.indptr[:-1][oriented]]
    by_station = np.argsort(station, kind="stable")
    bounds = np.searchsorted(station[by_station], np.arange(u - k + 1))
    for t in range(u - k):
        rows = by_station[bounds[t] : bounds[t + 1]]
        sub = normal.centred[rows]
        cols = np.unique(sub.indices)
        d = sub[:, cols].toarray()
        q = entry(np.repeat(cols, len(cols)), np.tile(cols, len(cols))).reshape(len(cols), len(cols))
        qa[rows] = np.einsum("ij,jk,ik->i", d, q, d) + coef[rows] ** 2 / normal.noo[t]
    x, y = 2 * np.arange(n_points), 2 * np.arange(n_points) + 1
    b = np.stack([entry(x, x), entry(y, x), entry(y, x), entry(y, y)], axis=1).reshape(n_points, 2, 2)
    return qa, b
