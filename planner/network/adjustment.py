"""Parametric least-squares adjustment of a 2-D network (chapter 2 of seed 000, seed 003).

    V = A X - L,  P = diag(1 / sigma^2),  N = A^T P A,  Q = N^-1,  X = Q A^T P L,
    m_0^2 = V^T P V / (n - u)

Observation kinds: ``direction`` (with one orientation unknown per station that takes directions), ``distance``,
``x``/``y`` (a coordinate observed directly, e.g. a control point with sigmas) and ``dx``/``dy`` (a relative position,
e.g. a registration link between two scanner stations). Internally radians and metres; :func:`adjust` converts from the
caller's units.

The solver is sparse (:mod:`planner.network.lsq_sparse`): A in scipy.sparse, N factored by SuperLU, and of Q only the
entries the results need, so time and memory grow with the observations, not with their square. ``method="dense"`` keeps
the dense solver (:mod:`planner.network.lsq_dense`) as a cross-check.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.typing import NDArray
from scipy import special  # the chi-square functions scipy.stats calls, without its 1 s import

from planner.core.errors import InputError
from planner.network import lsq_dense, lsq_sparse
from planner.network.normal import Normal

KINDS = ("direction", "distance", "x", "y", "dx", "dy")
ANGLE_UNITS = {"rad": 1.0, "deg": math.pi / 180.0, "gon": math.pi / 200.0, "arcsec": math.pi / 648000.0}
LENGTH_UNITS = {"m": 1.0, "mm": 1e-3}
#: the solvers: ``sparse`` (``normal`` is the same: normal equations), ``dense`` and ``qr`` (dense A)
METHODS = ("sparse", "normal", "dense", "qr")
#: the smallest sigma an observation may have: 1 micrometre, 1e-8 rad (0.002 arcsec); finer is no survey
#: measurement (a typo, or a unit mix-up), and 1/sigma^2 of 1e-300 is no number
MIN_SIGMA_M, MIN_SIGMA_RAD = 1e-6, 1e-8
#: 95 % scale of a 2-D error ellipse: sqrt(chi2_2(0.95)) = 2.4477
ELLIPSE_95 = math.sqrt(special.chdtri(2, 1.0 - 0.95))  # the quantile as stats.chi2.ppf computes it


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
    """An adjusted point: coordinates, sigmas and the error ellipse (semi-axes, azimuth of a from +x)."""

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
        """sqrt(sigma_x^2 + sigma_y^2)."""
        return math.hypot(self.sigma_x, self.sigma_y)


def relative(at: str, to: str, xy: Mapping[str, tuple[float, float]], sigma: float) -> list[Obs]:
    """The ``dx`` and ``dy`` observations of ``to`` from ``at`` at the coordinates ``xy``, each of ``sigma``."""
    return [Obs("dx", at, to, xy[to][0] - xy[at][0], sigma), Obs("dy", at, to, xy[to][1] - xy[at][1], sigma)]


def _no_covariance() -> NDArray[np.float64]:
    return np.zeros((0, 0))


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
    observations: tuple[Obs, ...]
    #: forms the covariance of the points' coordinates when asked for (:attr:`qxx`)
    covariance: Callable[[], NDArray[np.float64]] = field(default=_no_covariance, repr=False)

    @cached_property
    def qxx(self) -> NDArray[np.float64]:
        """The covariance matrix of the unknown points' coordinates (x, y of each, in the order of :attr:`points`; the
        caller's length unit squared), formed on first use."""
        return self.covariance()

    def point(self, name: str) -> PointResult:
        """The point named ``name``."""
        return next(p for p in self.points if p.name == name)

    def unchecked(self, tol: float = 1e-6) -> list[int]:
        """Observations with redundancy number ~0: nothing else checks them."""
        return [i for i, r in enumerate(self.redundancy) if r < tol]

    def worst_residual(self) -> tuple[int, float] | None:
        """The observation with the largest standardised residual, and that residual (None: no residuals)."""
        if self.m0 is None or len(self.standardized) == 0:
            return None
        k = int(np.nanargmax(np.abs(self.standardized)))
        return k, float(self.standardized[k])


def _wrap(angle: NDArray[np.float64]) -> NDArray[np.float64]:
    return (angle + math.pi) % (2 * math.pi) - math.pi


def _checked(
    xy: Mapping[str, object], observations: Sequence[Obs], ka: float, kl: float, angle_unit: str, length_unit: str
) -> list[Obs]:
    """The observations in radians and metres, each checked (kind, points, sigma)."""
    obs = [
        Obs(
            o.kind,
            o.at,
            o.to,
            o.value * (ka if o.kind == "direction" else kl),
            o.sigma * (ka if o.kind == "direction" else kl),
        )
        for o in observations
    ]
    for k, o in enumerate(obs, 1):
        where = {"row": f"observations[{k}]", "field": o.kind, "value": f"{o.at}->{o.to}"}
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
            raise InputError(
                f"sigma must be at least {least_si / k_unit:g} {unit}, got {o.sigma / k_unit:g}: no survey "
                "observation is that precise, and its weight 1/sigma^2 would swamp the adjustment",
                **where,
            )
    return obs


def _orientations(
    f: NDArray[np.float64], values: NDArray[np.float64], station: NDArray[np.int64], n: int
) -> NDArray[np.float64]:
    """Approximate orientation of each station: the mean of its directions' f - value (wrapped)."""
    groups: list[list[int]] = [[] for _ in range(n)]
    for i, s in enumerate(station.tolist()):
        if s >= 0:
            groups[s].append(i)
    d = _wrap(f - values)
    return np.array([float(np.mean(d[g])) for g in groups])


def adjust(
    coords: Mapping[str, tuple[float, float]],
    fixed: Sequence[str],
    observations: Sequence[Obs],
    *,
    observed: bool = False,
    angle_unit: str = "rad",
    length_unit: str = "m",
    method: str = "sparse",
    sigma0: float = 1.0,
    max_iter: int = 10,
) -> Adjustment:
    """Design (``observed=False``: covariance, redundancy numbers, no residuals) or adjustment of a network.

    ``coords``: approximate (design) coordinates of every point, in ``length_unit``, in the order of the unknowns;
    ``fixed``: the known points; ``observations``: values and sigmas in ``angle_unit`` (directions) and ``length_unit``
    (the rest; :data:`ANGLE_UNITS`, :data:`LENGTH_UNITS`); results come back in ``length_unit``. ``observed``: adjust
    the observed values, iterated to convergence (at most ``max_iter`` times). ``method``: ``sparse`` (or ``normal``,
    see the module text), ``dense`` (Cholesky, the whole inverse) or ``qr`` (least squares on sqrt(P) A); all give the
    same answer. ``sigma0``: the a priori standard deviation of unit weight (the chi-square test, and the scale of a
    design).

    InputError on an unknown kind, method or point, a sigma out of range, coincident points of a distance or
    direction, or a datum defect.
    """
    if method not in METHODS:
        raise InputError(f"unknown adjustment method (known: {', '.join(METHODS)})", field="method", value=method)
    ka, kl = ANGLE_UNITS[angle_unit], LENGTH_UNITS[length_unit]
    names = list(coords)
    xy = np.array([(c[0] * kl, c[1] * kl) for c in coords.values()], dtype=float).reshape(-1, 2)
    obs = _checked(coords, observations, ka, kl, angle_unit, length_unit)
    held = set(fixed)
    unknown = [n for n in names if n not in held]
    uidx = np.array([k for k, n in enumerate(names) if n not in held], dtype=np.int64)
    w = np.array([1.0 / o.sigma**2 for o in obs])
    dx, l, a_dense, normal = _iterate(names, unknown, uidx, xy, obs, w, method, max_iter if observed else 0)
    if a_dense is not None:
        qa, blocks, q = lsq_dense.covariance(a_dense, w, len(unknown))
        v = a_dense @ dx - l
        n_unk = a_dense.shape[1]

        def cov() -> NDArray[np.float64]:
            return q
    else:
        assert normal is not None
        qa, blocks = lsq_sparse.selected_inverse(normal, len(unknown))
        v = normal.a @ dx - l
        n_unk = normal.a.shape[1]
        cov = _lazy(normal, 2 * len(unknown))
    return _results(unknown, xy[uidx], obs, w, qa, blocks, cov, v if observed else None, n_unk, kl, sigma0)


#: a point that still moves more than this in the last iteration: the adjustment has not converged (refused)
NOT_CONVERGED_M = 1e-6


def _iterate(
    names: list[str],
    unknown: list[str],
    uidx: NDArray[np.int64],
    xy: NDArray[np.float64],
    obs: list[Obs],
    w: NDArray[np.float64],
    method: str,
    max_iter: int,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64] | None, Normal | None]:
    """Gauss-Newton iterations of the adjustment (``max_iter`` 0: the design only, one linearisation, no observed
    values); moves ``xy`` (metres) in place. Returns the last corrections, the reduced observations, and the dense
    design matrix (dense methods) or the normal equations (sparse)."""
    observed = max_iter > 0
    values = np.array([o.value for o in obs])
    is_dir = np.array([o.kind == "direction" for o in obs], dtype=bool)
    dense = method in ("dense", "qr")
    plan = lsq_sparse.Design(names, unknown, obs)
    station_of = {st: k for k, st in enumerate(plan.orient)}
    orient_station = np.array([station_of[o.at] if o.kind == "direction" else -1 for o in obs], dtype=np.int64)
    orient_val = np.zeros(len(plan.orient))
    l = np.zeros(len(obs))
    dx = np.zeros(plan.n_unknowns)
    a_dense: NDArray[np.float64] | None = None
    normal: Normal | None = None
    nu = len(unknown)
    for it in range(max(max_iter, 1)):
        if dense:
            a_dense, f, _ = lsq_dense.design({n: (float(p[0]), float(p[1])) for n, p in zip(names, xy)}, unknown, obs)
        else:
            a_sparse, f = plan.jacobian(xy)
            normal = Normal(a_sparse, w, len(plan.orient))
        if observed:
            if it == 0:
                orient_val = _orientations(f, values, orient_station, len(plan.orient))
            f = f - np.where(is_dir, orient_val[np.maximum(orient_station, 0)] if len(plan.orient) else 0.0, 0.0)
            l = values - f
            l = np.where(is_dir, _wrap(l), l)
        if a_dense is not None:
            dx = lsq_dense.solve(a_dense, w, l, method)
        elif observed:
            assert normal is not None
            dx = normal.solve(normal.a.T @ (w * l))
        xy[uidx, 0] += dx[0 : 2 * nu : 2]
        xy[uidx, 1] += dx[1 : 2 * nu : 2]
        orient_val = orient_val + dx[2 * nu :]
        if not observed or np.max(np.abs(dx[: 2 * nu]), initial=0.0) < 1e-12:
            break
    moved = np.hypot(dx[0 : 2 * nu : 2], dx[1 : 2 * nu : 2]) if observed else np.zeros(0)
    if moved.size and moved.max() > NOT_CONVERGED_M:
        worst = int(np.argmax(moved))
        raise InputError(
            f"the adjustment did not converge in {max_iter} iterations: point {unknown[worst]} still moved "
            f"{moved[worst]:.3g} m in the last (observations that contradict each other, or approximate coordinates "
            "too far off)"
        )
    return dx, l, a_dense, normal


def _lazy(normal: Normal, k: int) -> Callable[[], NDArray[np.float64]]:
    """Q of the first ``k`` unknowns, from A and P again (the factor is not kept)."""
    a, w, n_orient = normal.a, normal.w, normal.a.shape[1] - normal.k

    def cov() -> NDArray[np.float64]:
        return Normal(a, w, n_orient).columns(k)

    return cov


def _results(
    unknown: Sequence[str],
    xy: NDArray[np.float64],
    obs: Sequence[Obs],
    w: NDArray[np.float64],
    qa: NDArray[np.float64],
    blocks: NDArray[np.float64],
    cov: Callable[[], NDArray[np.float64]],
    v: NDArray[np.float64] | None,
    n_unk: int,
    kl: float,
    sigma0: float,
) -> Adjustment:
    """The :class:`Adjustment` from diag(A Q A^T), the points' blocks of Q and the residuals (None: a design)."""
    n_obs = len(obs)
    dof = n_obs - n_unk
    qvv = 1.0 / w - qa
    redundancy = np.clip(qvv * w, 0.0, 1.0)
    if v is not None:
        m0 = math.sqrt(float(v @ (w * v)) / dof) if dof > 0 else None
        with np.errstate(divide="ignore", invalid="ignore"):
            std = np.where(qvv > 1e-15, v / np.sqrt(np.maximum(qvv, 1e-300)), np.nan)
        chi2 = dof * (m0 / sigma0) ** 2 if m0 is not None else None
        p = float(2 * min(special.chdtr(dof, chi2), special.chdtrc(dof, chi2))) if chi2 is not None else None
        passed = None if p is None else p >= 0.05
    else:
        v, m0, std, p, passed = np.zeros(n_obs), None, np.full(n_obs, np.nan), None, None
    scale = (m0 if m0 is not None else sigma0) ** 2
    points = []
    for k, name in enumerate(unknown):
        c = blocks[k] * scale
        lam, vec = np.linalg.eigh(c)
        az = math.degrees(math.atan2(vec[1, 1], vec[0, 1])) % 180.0
        points.append(
            PointResult(
                name,
                float(xy[k, 0]) / kl,
                float(xy[k, 1]) / kl,
                math.sqrt(c[0, 0]) / kl,
                math.sqrt(c[1, 1]) / kl,
                math.sqrt(max(lam[1], 0.0)) / kl,
                math.sqrt(max(lam[0], 0.0)) / kl,
                az,
            )
        )

    def qxx() -> NDArray[np.float64]:
        return cov() * scale / kl**2

    return Adjustment(tuple(points), v, redundancy, std, m0, dof, p, passed, tuple(obs), qxx)
