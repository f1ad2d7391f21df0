"""Heights of the stations by trigonometric levelling: the 1-D part of a 2-D + 1-D adjustment.

A total station measuring slant distance S and zenith angle z to a point gives the height difference dh = S cos z, with

    sigma_dh^2 = (cos z * sigma_S)^2 + (S sin z * sigma_z)^2

(sigma_z in radians; for a level sight, sigma_dh ~ S sigma_z). Control points with a height are fixed; the adjustment is
linear: dh_ij = H_j - H_i.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from planner.core.errors import InputError
from planner.network.normal import Normal


@dataclass(frozen=True)
class HeightObs:
    at: str
    to: str
    dh_m: float
    sigma_m: float


def dh_sigma_m(slant_m: float, zenith_deg: float, sigma_s_m: float, sigma_z_arcsec: float) -> float:
    z = math.radians(zenith_deg)
    return math.hypot(math.cos(z) * sigma_s_m, slant_m * math.sin(z) * math.radians(sigma_z_arcsec / 3600.0))


@dataclass(frozen=True)
class HeightResult:
    heights_m: dict[str, float]
    sigma_m: dict[str, float]
    m0: float | None


def adjust_heights(
    approx: Mapping[str, float], fixed: Mapping[str, float], observations: Sequence[HeightObs], observed: bool = False
) -> HeightResult:
    """Least-squares heights (and their sigmas) of the points not in ``fixed``; sparse, as the plan adjustment, with
    only the diagonal of Q = N^-1 formed. InputError where some point reaches no point of known height."""
    unknown = [n for n in approx if n not in fixed]
    col = {n: k for k, n in enumerate(unknown)}
    rows: list[int] = []
    cols: list[int] = []
    vals: list[float] = []
    l = np.zeros(len(observations))
    w = np.array([1.0 / o.sigma_m**2 for o in observations])
    h0 = {**approx, **fixed}
    for i, o in enumerate(observations):
        for name, sign in ((o.at, -1.0), (o.to, 1.0)):
            if name in col and not (sign < 0 and o.to == o.at):  # a point to itself: +1 alone
                rows.append(i)
                cols.append(col[name])
                vals.append(sign)
        l[i] = (o.dh_m - (h0[o.to] - h0[o.at])) if observed else 0.0
    a = sp.csr_matrix((vals, (rows, cols)), shape=(len(observations), len(unknown)))
    try:
        normal = Normal(a, w)
    except InputError:
        raise InputError("height datum defect: some stations reach no point of known height", field="heights") from None
    x = normal.solve(a.T @ (w * l))
    dof = len(observations) - len(unknown)
    m0 = None
    if observed and dof > 0:
        v = a @ x - l
        m0 = math.sqrt(float(v @ (w * v)) / dof)
    scale = (m0 or 1.0) ** 2
    k = np.arange(len(unknown))
    q = normal.inverse(sp.identity(len(unknown), format="csc"))(k, k)
    return HeightResult(
        {n: h0[n] + x[k] for n, k in col.items()}, {n: math.sqrt(q[k] * scale) for n, k in col.items()}, m0
    )
