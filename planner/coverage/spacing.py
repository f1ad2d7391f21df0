"""Point spacing: how far apart a scan's points fall on a wall piece, per view.

A scanner turns by the same angular step ``delta`` (rad) horizontally and vertically; a setting "6.3 mm @ 10 m"
has delta = 6.3 mm / 10 m. On a vertical wall at perpendicular distance ``d`` from the station, a point at
horizontal distance ``hd`` (in plan) and height ``dz`` above or below the instrument lies at slant range
``s = sqrt(hd^2 + dz^2)``. One step moves the beam along the wall by

- horizontally: ``hd x delta / cos(alpha) = hd^2 x delta / d`` (alpha: the plan-view incidence, cos = d / hd);
- vertically: ``s^2 x delta / hd = (hd + dz^2 / hd) x delta`` (z = hd tan(eps), dz/deps = s^2 / hd).

Both are ``range x step / cos(incidence)`` in their own plane, the issue's rule of thumb, made exact for a
vertical wall. Over a piece a-b the horizontal spacing is largest at an end (``hd^2 / d`` = d + x^2 / d is
convex along the wall); the vertical one, ``f(hd) = hd + dz^2 / hd`` with dz the farther of the top and the foot
(as the range test takes it), is convex in ``hd`` and so largest at the piece's nearest or farthest plan distance.
The spacing a view gives a piece is the largest of the three, times delta: :func:`spacing_factors` returns that
factor (metres per radian of step), so ``factor x delta <= max_spacing`` decides each (view, setting).

What "spacing" measures: at one azimuth the beam sweeps a vertical line of the wall, so the points lie on
vertical columns ``hd^2 x delta / d`` apart, and along each column ``(hd + dz^2 / hd) x delta`` apart. Neighbouring
columns are shifted along their lines (at one elevation the beam climbs as it turns away from the perpendicular),
so two points of one elevation are further apart than the column gap, up to
``sqrt((hd^2 / d)^2 + (dz x / d)^2) x delta`` (x along the wall from the perpendicular's foot); but every point of
the wall still lies within half a column gap across and half a point gap along a column of a sample. The two gaps
are the lattice's spacing across and along, which the specifications' "point spacing" asks for; the distance
between points of one elevation is not.

The bound is over the whole piece, from its foot to its top, at both ends: a piece meets the spacing only
where every point of it does. Vertical walls only (the planner's wall model); floors and ceilings are not
checked for spacing.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.coverage.matrix import CoverageProblem

#: closer than this to a wall line a view has no finite spacing (the sight test refuses it anyway)
_EPS_M = 1e-9


def spacing_factors(problem: CoverageProblem, instrument_height_m: float | None = None) -> sp.csr_matrix:
    """C x T, on the pattern of ``problem.by_candidate``: the largest spacing over each seen piece per radian
    of angular step (metres), the larger of the horizontal and vertical spacing at the worst point of the
    piece. ``instrument_height_m``: the instrument's height above the floor (None: the problem's limits')."""
    ih = problem.limits.instrument_height_m if instrument_height_m is None else instrument_height_m
    m = problem.by_candidate.tocsr()
    rows = np.repeat(np.arange(m.shape[0]), np.diff(m.indptr))
    cols = m.indices
    xy = np.array([c.xy for c in problem.candidates], dtype=float).reshape(-1, 2)
    t = problem.targets
    values = view_factors(xy[rows], t.a[cols], t.b[cols], np.maximum(t.ha_m[cols], t.hb_m[cols]), ih)
    return sp.csr_matrix((values, cols.copy(), m.indptr.copy()), shape=m.shape)


def view_factors(
    station: NDArray[np.float64], a: NDArray[np.float64], b: NDArray[np.float64], top_m: NDArray[np.float64], ih: float
) -> NDArray[np.float64]:
    """Spacing per radian of step (m) over pieces a-b of wall height ``top_m`` seen from ``station`` (rows
    paired), the instrument ``ih`` above the floor: max(hd_max^2 / d, f(hd_min), f(hd_max)), f(h) = h + dz^2/h."""
    ab = b - a
    length = np.hypot(ab[:, 0], ab[:, 1])
    u = ab / np.maximum(length, _EPS_M)[:, None]
    pa = station - a
    d = np.maximum(np.abs(u[:, 0] * pa[:, 1] - u[:, 1] * pa[:, 0]), _EPS_M)  # perpendicular distance
    along = np.clip(pa[:, 0] * u[:, 0] + pa[:, 1] * u[:, 1], 0.0, length)
    hd_a = np.hypot(pa[:, 0], pa[:, 1])
    hd_b = np.hypot(*(station - b).T)
    hd_max = np.maximum(hd_a, hd_b)
    foot = a + u * along[:, None]
    hd_min = np.maximum(np.hypot(*(station - foot).T), _EPS_M)
    dz = np.maximum(np.abs(top_m - ih), ih)  # the farther of the top and the foot, vertically
    horizontal = hd_max**2 / d
    vertical = np.maximum(hd_min + dz**2 / hd_min, hd_max + dz**2 / hd_max)
    return np.asarray(np.maximum(horizontal, vertical), dtype=float)


def point_spacing_m(
    station: NDArray[np.float64],
    point: NDArray[np.float64],
    normal: NDArray[np.float64],
    top_m: NDArray[np.float64],
    ih: float,
    step_rad: NDArray[np.float64] | float,
) -> NDArray[np.float64]:
    """The spacing at one plan point of a wall (its whole height, foot to top) seen from ``station``: an
    independent evaluation for verification, per point, not per piece: max(hd^2 / d, hd + dz^2 / hd) x step."""
    v = point - station
    hd = np.maximum(np.hypot(v[:, 0], v[:, 1]), _EPS_M)
    d = np.maximum(np.abs(v[:, 0] * normal[:, 0] + v[:, 1] * normal[:, 1]), _EPS_M)
    dz = np.maximum(np.abs(top_m - ih), ih)
    return np.asarray(np.maximum(hd**2 / d, hd + dz**2 / hd) * step_rad, dtype=float)
