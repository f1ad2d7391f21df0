"""The dense least squares of :mod:`planner.network.adjustment` (``method="dense"`` or ``"qr"``): a dense design matrix
and the normal matrix inverted whole. Memory and time grow with observations x unknowns^2; kept as an independent
cross-check of the sparse solver (:mod:`planner.network.lsq_sparse`) on small networks.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import scipy.linalg as sla
from numpy.typing import NDArray

from planner.core.errors import InputError
from planner.network.normal import refuse_defect


def design(
    coords: Mapping[str, tuple[float, float]], unknown: Sequence[str], obs: Sequence[Any]
) -> tuple[NDArray[np.float64], NDArray[np.float64], list[str]]:
    """The dense design matrix A (observations x unknowns, ``unknown`` in the order of their columns), the observations
    computed at ``coords`` (metres; orientations 0) and the stations with an orientation unknown, in the order of their
    columns; ``obs`` in radians and metres."""
    orient = sorted({o.at for o in obs if o.kind == "direction"})
    col = {name: 2 * k for k, name in enumerate(unknown)}
    ocol = {s: 2 * len(unknown) + k for k, s in enumerate(orient)}
    a = np.zeros((len(obs), 2 * len(unknown) + len(orient)))
    f = np.zeros(len(obs))
    for i, o in enumerate(obs):
        xi, yi = coords[o.at]
        if o.kind in ("x", "y"):
            f[i] = xi if o.kind == "x" else yi
            if o.at in col:
                a[i, col[o.at] + (0 if o.kind == "x" else 1)] = 1.0
            continue
        assert o.to is not None  # only x/y observations have no target, and they were handled above
        xj, yj = coords[o.to]
        dx, dy = xj - xi, yj - yi
        s2 = dx * dx + dy * dy
        if o.kind in ("dx", "dy"):
            k = 0 if o.kind == "dx" else 1
            f[i] = dx if k == 0 else dy
            if o.at in col:
                a[i, col[o.at] + k] = -1.0
            if o.to in col:
                a[i, col[o.to] + k] = 1.0
            continue
        if s2 == 0:
            raise InputError("observation between coincident points", row=i + 1, field=o.kind, value=f"{o.at}->{o.to}")
        if o.kind == "distance":
            s = math.sqrt(s2)
            f[i] = s
            g = (-dx / s, -dy / s, dx / s, dy / s)
        else:  # direction: azimuth from +x, counter-clockwise, minus the station's orientation
            f[i] = math.atan2(dy, dx)
            g = (dy / s2, -dx / s2, -dy / s2, dx / s2)
            a[i, ocol[o.at]] = -1.0
        if o.at in col:
            a[i, col[o.at]], a[i, col[o.at] + 1] = g[0], g[1]
        if o.to in col:
            a[i, col[o.to]], a[i, col[o.to] + 1] = g[2], g[3]
    return a, f, orient


def solve(a: NDArray[np.float64], w: NDArray[np.float64], l: NDArray[np.float64], method: str) -> NDArray[np.float64]:
    """The corrections X = N^-1 A^T P l (``method`` ``qr``: least squares on sqrt(P) A instead); InputError on a datum
    defect (a pivot of N on the unit diagonal below :data:`planner.network.normal.PIVOT_TOL`)."""
    n = a.T @ (a * w[:, None])
    refuse_defect(n)  # decided and counted as the sparse solver does
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
