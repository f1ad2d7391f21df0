"""The precision part of a coverage region (:mod:`planner.coverage.regions`): the positions whose view of a piece's end
has e(S, theta) <= sigma_req, star-shaped about the end and bounded by rho(theta) = sqrt(S_lim(theta)^2 - dz^2), drawn
inside the true curve."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.coverage.visibility import PrecisionRule, SightLimits
from planner.instrument.accuracy import IncidenceErrorTable, derive_theta_max_deg, max_slant_for_view_m

#: points of the precision boundary rho(theta) per end of a piece
PRECISION_SAMPLES = 257
#: the precision boundary's chord error may be up to this before it is sampled more finely (m)
PRECISION_CHORD_M = 1e-3


def precision_region(
    end: NDArray, tangent: NDArray, normal: NDArray, dz: float, limits: SightLimits
) -> shapely.Geometry:
    """Positions whose (horizontal-incidence) view of ``end`` has e(S, theta) <= sigma_req (see
    :func:`precision_profile`), as a polygon with its apex at ``end``."""
    rule = limits.precision
    a, r = precision_profile(rule, round(dz, 9), limits.theta_max_deg)
    if a.size == 0:
        return shapely.Polygon()
    pts = end + np.outer(r * np.cos(a), normal) + np.outer(r * np.sin(a), tangent)
    fan = shapely.Polygon(np.vstack([end, pts]))
    return fan if fan.is_valid else shapely.make_valid(fan)


@lru_cache(maxsize=256)
def precision_profile(rule: PrecisionRule, dz: float, theta_max_deg: float) -> tuple[NDArray, NDArray]:
    """The boundary rho(theta) = sqrt(S_lim(theta)^2 - dz^2) of the precision part of a region, theta from the normal
    (radians) and rho (m), drawn inside the true curve. theta runs to ``top`` (theta_max, or where not even S = dz meets
    sigma_req); rho falls like sqrt(top - theta) there, so theta is sampled as top (1 - (1 - u)^2), u uniform, plus the
    table's angles (kinks). Each vertex is pulled in by the larger chord error of its two sectors; samples double until
    that error is at most ``PRECISION_CHORD_M``. Cached: pieces of equal height share it."""
    args = (rule.scanner, rule.budget, rule.sigma_req_m, rule.incidence_model)
    top = min(theta_max_deg, derive_theta_max_deg(dz, *args))
    if top <= 0.0:
        return np.zeros(0), np.zeros(0)

    def rho(th: NDArray) -> NDArray:
        return np.sqrt(np.maximum(max_slant_for_view_m(np.abs(th), *args) ** 2 - dz * dz, 0.0))

    kinks = [k for k in (IncidenceErrorTable().theta_deg if rule.incidence_model == "table" else ()) if 0.0 < k < top]
    n = PRECISION_SAMPLES
    while True:
        u = np.linspace(-1.0, 1.0, n)
        th = np.unique(np.concatenate([np.sign(u) * top * (1.0 - (1.0 - np.abs(u)) ** 2), kinks, np.negative(kinks)]))
        th_m = (th[:-1] + th[1:]) / 2.0  # the table's kinks are sample points: between samples the curve is smooth
        r, r_m = rho(th), rho(th_m)
        p0, p1, pm = (
            np.column_stack([rr * np.cos(np.radians(tt)), rr * np.sin(np.radians(tt))])
            for tt, rr in ((th[:-1], r[:-1]), (th[1:], r[1:]), (th_m, r_m))
        )
        err = _point_segment_m(pm, p0, p1)  # how far the curve strays from each chord
        if err.max() <= PRECISION_CHORD_M or n > 64 * PRECISION_SAMPLES:  # (a cap; never reached in the tests)
            break
        n = 2 * n - 1
    pull = np.maximum(np.concatenate([[0.0], err]), np.concatenate([err, [0.0]]))
    return np.radians(th), np.maximum(r - pull, 0.0)


def _point_segment_m(p: NDArray, a: NDArray, b: NDArray) -> NDArray[np.float64]:
    """Distance of each point p from the segment a-b (row-wise)."""
    ab, ap = b - a, p - a
    L2 = np.einsum("ij,ij->i", ab, ab)
    s = np.clip(np.einsum("ij,ij->i", ap, ab) / np.where(L2 > 0, L2, 1.0), 0.0, 1.0)
    return np.hypot(*(ap - s[:, None] * ab).T)
