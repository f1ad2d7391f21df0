"""The dense least squares of :mod:`planner.network.adjustment` (``method="dense"`` or ``"qr"``): the design matrix of
:class:`planner.network.lsq_sparse.Design` made dense, and the normal matrix inverted whole. Memory and time grow with
observations x unknowns^2; kept as an independent cross-check of the sparse solver on small networks.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
from numpy.typing import NDArray

from planner.core.errors import InputError


def solve(a: NDArray[np.float64], w: NDArray[np.float64], l: NDArray[np.float64], method: str) -> NDArray[np.float64]:
    """The corrections X = N^-1 A^T P l (``method`` ``qr``: least squares on sqrt(P) A instead); InputError on a datum
    defect (N of less than full rank)."""
    n = a.T @ (a * w[:, None])
    if np.linalg.matrix_rank(n) < n.shape[0]:
        raise InputError(
            f"datum defect: the network leaves {n.shape[0] - np.linalg.matrix_rank(n)} "
            "unknown(s) undetermined (fix control points or add observations)",
            field="network",
        )
    if method == "qr":
        sw = np.sqrt(w)
        return np.asarray(sla.lstsq(a * sw[:, None], l * sw, lapack_driver="gelsy")[0])
    return np.asarray(sla.cho_solve(sla.cho_factor(n), a.T @ (w * l)))


def covariance(
    a: NDArray[np.float64], w: NDArray[np.float64], n_points: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """diag(A Q A^T), the points' 2 x 2 blocks of Q = N^-1, and Q of the points' coordinates."""
    q = np.linalg.inv(a.T @ (a * w[:, None]))
    qa = np.einsum("ij,jk,ik->i", a, q, a)
    blocks = np.array([q[2 * k : 2 * k + 2, 2 * k : 2 * k + 2] for k in range(n_points)]).reshape(n_points, 2, 2)
    f64 = np.float64
    return (
        np.asarray(qa, dtype=f64),
        np.asarray(blocks, dtype=f64),
        np.asarray(q[: 2 * n_points, : 2 * n_points], dtype=f64),
    )
