"""Parametric least-squares adjustment of a 2-D network (chapter 2 of seed 000, seed 003).

    V = A X - L,  P = diag(1 / sigma^2),  N = A^T P A,  Q = N^-1,  X = Q A^T P L,
    m_0^2 = V^T P V / (n - u)

Observation kinds: ``direction`` (with one orientation unknown per station
that takes directions), ``distance``, ``x``/``y`` (a coordinate observed
directly, e.g. a control point with sigmas) and ``dx``/``dy`` (a relative
position, e.g. a registration link between two scanner stations). Internally
radians and metres; :func:`adjust` converts from the caller's units.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
from numpy.typing import NDArray
from scipy import stats

from planner.errors import InputError

KINDS = ("direction", "distance", "x", "y", "dx", "dy")
ANGLE_UNITS = {"rad": 1.0, "deg": math.pi / 180.0, "gon": math.pi / 200.0, "arcsec": math.pi / 648000.0}
LENGTH_UNITS = {"m": 1.0, "mm": 1e-3}
#: the smallest sigma an observation may have: 1 micrometre, 1e-8 rad (0.002 arcsec); finer is no survey
#: measurement (a typo, or a unit mix-up), and 1/sigma^2 of 1e-300 is no number
MIN_SIGMA_M, MIN_SIGMA_RAD = 1e-6, 1e-8
#: 95 % scale of a 2-D error ellipse: sqrt(chi2_2(0.95)) = 2.4477
ELLIPSE_95 = math.sqrt(stats.chi2.ppf(0.95, 2))


@dataclass(frozen=True)
class Obs:
    """One observation: ``kind`` from ``at`` to ``to`` (``to`` unused for x/y), value and sigma."""

    kind: str
    at: str
    to: str | None
    value: float
    sigma: float


@dataclass(frozen=True)
class PointResult:
    name: str
    x: float
    y: float
    sigma_x: float
    sigma_y: float
    ellipse_a: float
    ellipse_b: float
    ellipse_azimuth_deg: float

    @property
    def position_error(self) -> float:
        return math.hypot(self.sigma_x, self.sigma_y)


@dataclass(frozen=True, eq=False)
class Adjustment:
    """Adjusted (or design) coordinates and their accuracy, in the caller's length unit."""

    points: tuple[PointResult, ...]
    residuals: NDArray[np.float64]  # metres and radians, in observation order
    redundancy: NDArray[np.float64]
    standardized: NDArray[np.float64]
    m0: float | None
    dof: int
    chi2_p: float | None
    chi2_pass: bool | None
    qxx: NDArray[np.float64]
    observations: tuple[Obs, ...]

    @property
    def network_rms(self) -> float:
        """sqrt(trace of the coordinate covariance / number of points): the mean point error (2.11)."""
        return math.sqrt(sum(p.sigma_x**2 + p.sigma_y**2 for p in self.points) / max(len(self.points), 1))

    def point(self, name: str) -> PointResult:
        return next(p for p in self.points if p.name == name)

    def unchecked(self, tol: float = 1e-6) -> list[int]:
        """Observations with redundancy number ~0: nothing else checks them."""
        return [i for i, r in enumerate(self.redundancy) if r < tol]

    def worst_residual(self) -> tuple[int, float] | None:
        if self.m0 is None or len(self.standardized) == 0:
            return None
        k = int(np.nanargmax(np.abs(self.standardized)))
        return k, float(self.standardized[k])


def _design(coords: Mapping[str, tuple[float, float]], unknown: list[str], obs: Sequence[Obs]
            ) -> tuple[NDArray, NDArray, list[str]]:
    """Jacobian A and computed values f(X0) at the coordinates, and the orientation unknowns."""
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


def _wrap(angle: NDArray) -> NDArray:
    return (angle + math.pi) % (2 * math.pi) - math.pi


def adjust(
    coords: Mapping[str, tuple[float, float]], fixed: Sequence[str], observations: Sequence[Obs], *,
    observed: bool = False, angle_unit: str = "rad", length_unit: str = "m", method: str = "normal",
    sigma0: float = 1.0, max_iter: int = 10,
) -> Adjustment:
    """Design (``observed=False``: covariance only) or adjustment of a network.

    ``coords`` are approximate (design) coordinates; ``fixed`` points are
    known. Values and sigmas are in ``angle_unit`` (directions) and
    ``length_unit`` (the rest); results come back in ``length_unit``.
    ``method``: ``normal`` (N = A^T P A, solved by Cholesky) or ``qr``
    (scipy's least squares on sqrt(P) A); both give the same answer.
    """
    ka, kl = ANGLE_UNITS[angle_unit], LENGTH_UNITS[length_unit]
    xy = {n: (c[0] * kl, c[1] * kl) for n, c in coords.items()}
    obs = [Obs(o.kind, o.at, o.to, o.value * (ka if o.kind == "direction" else kl),
               o.sigma * (ka if o.kind == "direction" else kl)) for o in observations]
    for k, o in enumerate(obs, 1):
        where = dict(row=f"observations[{k}]", field=o.kind, value=f"{o.at}->{o.to}")
        if o.kind not in KINDS:
            raise InputError(f"unknown observation kind (known: {', '.join(KINDS)})", **where)
        strangers = [n for n in ((o.at,) if o.kind in ("x", "y") else (o.at, o.to)) if n not in xy]
        if strangers:
            raise InputError(f"names no point of the network: {strangers[0]}", **where)
        if not o.sigma > 0:
            raise InputError(f"sigma must be > 0, got {o.sigma:g}", **where)
        k_unit, least_si = (ka, MIN_SIGMA_RAD) if o.kind == "direction" else (kl, MIN_SIGMA_M)
        if o.sigma < least_si:
            unit = angle_unit if o.kind == "direction" else length_unit
            raise InputError(f"sigma must be at least {least_si / k_unit:g} {unit}, got {o.sigma / k_unit:g}: no survey "
                             "observation is that precise, and its weight 1/sigma^2 would swamp the adjustment", **where)
    unknown = [n for n in xy if n not in set(fixed)]
    w = np.array([1.0 / o.sigma**2 for o in obs])
    x_est = dict(xy)
    orient_val: dict[str, float] = {}
    for _ in range(max_iter if observed else 1):
        a, f, orient = _design(x_est, unknown, obs)
        if observed:
            for s in orient:
                orient_val.setdefault(s, float(np.mean([_wrap(np.array([f[i] - o.value]))[0] for i, o in enumerate(obs)
                                                        if o.kind == "direction" and o.at == s])))
            f = f - np.array([orient_val.get(o.at, 0.0) if o.kind == "direction" else 0.0 for o in obs])
            l = np.array([o.value for o in obs]) - f
            l = np.where([o.kind == "direction" for o in obs], _wrap(l), l)
        else:
            l = np.zeros(len(obs))
        dx = _solve(a, w, l, method)
        for k, n in enumerate(unknown):
            x_est[n] = (x_est[n][0] + dx[2 * k], x_est[n][1] + dx[2 * k + 1])
        for k, s in enumerate(orient):
            orient_val[s] = orient_val.get(s, 0.0) + dx[2 * len(unknown) + k]
        if not observed or np.max(np.abs(dx[:2 * len(unknown)]), initial=0.0) < 1e-12:
            break
    return _results(x_est, unknown, obs, a, w, l if observed else None, dx if observed else None, kl, sigma0)


def _solve(a: NDArray, w: NDArray, l: NDArray, method: str) -> NDArray:
    n = a.T @ (a * w[:, None])
    if np.linalg.matrix_rank(n) < n.shape[0]:
        raise InputError(f"datum defect: the network leaves {n.shape[0] - np.linalg.matrix_rank(n)} "
                         "unknown(s) undetermined (fix control points or add observations)", field="network")
    if method == "qr":
        sw = np.sqrt(w)
        return sla.lstsq(a * sw[:, None], l * sw, lapack_driver="gelsy")[0]
    return sla.cho_solve(sla.cho_factor(n), a.T @ (w * l))


def _results(xy, unknown, obs, a, w, l, dx, kl, sigma0) -> Adjustment:
    n_mat = a.T @ (a * w[:, None])
    q = np.linalg.inv(n_mat)
    n_obs, n_unk = a.shape
    dof = n_obs - n_unk
    qvv = 1.0 / w - np.einsum("ij,jk,ik->i", a, q, a)
    redundancy = np.clip(qvv * w, 0.0, 1.0)
    if l is not None:
        v = a @ dx - l
        m0 = math.sqrt(float(v @ (w * v)) / dof) if dof > 0 else None
        with np.errstate(divide="ignore", invalid="ignore"):
            std = np.where(qvv > 1e-15, v / np.sqrt(np.maximum(qvv, 1e-300)), np.nan)
        chi2 = dof * (m0 / sigma0) ** 2 if m0 is not None else None
        p = float(2 * min(stats.chi2.cdf(chi2, dof), stats.chi2.sf(chi2, dof))) if chi2 is not None else None
        passed = None if p is None else p >= 0.05
    else:
        v, m0, std, p, passed = np.zeros(n_obs), None, np.full(n_obs, np.nan), None, None
    scale = (m0 if m0 is not None else sigma0) ** 2
    points = []
    for k, name in enumerate(unknown):
        c = q[2 * k:2 * k + 2, 2 * k:2 * k + 2] * scale
        lam, vec = np.linalg.eigh(c)
        az = math.degrees(math.atan2(vec[1, 1], vec[0, 1])) % 180.0
        points.append(PointResult(name, xy[name][0] / kl, xy[name][1] / kl, math.sqrt(c[0, 0]) / kl,
                                  math.sqrt(c[1, 1]) / kl, math.sqrt(max(lam[1], 0.0)) / kl,
                                  math.sqrt(max(lam[0], 0.0)) / kl, az))
    qxx = q[:2 * len(unknown), :2 * len(unknown)] * scale / kl**2
    return Adjustment(tuple(points), v, redundancy, std, m0, dof, p, passed, qxx, tuple(obs))
