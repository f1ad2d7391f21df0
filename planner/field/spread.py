"""Three registration targets spread apart: the triple of candidate places with the largest smallest pairwise distance
among those whose triangle has no angle below :data:`MIN_ANGLE_DEG` (exact, not a heuristic).

Three targets nearly on one spot or on one line fix a registration badly (or not at all: collinear targets leave the
rotation about their line free). Where no triple of places makes a triangle with every angle at least
:data:`MIN_ANGLE_DEG`, the largest smallest distance over all triples is taken and the angle is said.

Exactness: every triangle has a shortest side (i, j), and the angle opposite it, at the third corner k, is its smallest
angle. So a triple with smallest side d and smallest angle >= a exists iff some pair (i, j) at distance d has a k with
|ik| >= d, |jk| >= d and the angle at k >= a. Scanning the pairs by decreasing distance, the first pair that has such a
k gives the maximum (:func:`spread_triple`); the tests check it against brute force on random small sets. An angle
counts as >= a when it is >= a - :data:`ANGLE_TOL_DEG` (exactly a, computed by any formula, must count).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray

#: the smallest angle of a target triangle that counts as well spread (deg): below it, the triangle's
#: thin side leaves the rotation about it weakly fixed
MIN_ANGLE_DEG = 30.0
#: targets of one link at least this far apart wherever the places allow (m)
MIN_SPREAD_M = 2.0
#: an angle this close below the bound counts as meeting it (deg): a triangle whose smallest angle is exactly the
#: bound (45 deg on a grid) comes out of floating point a few 1e-15 deg either side of it
ANGLE_TOL_DEG = 1e-9
_BLOCK = 256  # pairs tested per vectorised step


@dataclass(frozen=True)
class Spread:
    """A link's target geometry: the places chosen (indices), the smallest pairwise distance (m), the smallest angle of
    their triangle (deg; None for fewer than three places) and why it falls short ("" when it does not)."""

    chosen: tuple[int, ...]
    min_distance_m: float | None
    min_angle_deg: float | None
    note: str = ""


def triangle_angles(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """The three angles (deg) of the triangle ``p`` (3 x 2), the angle at corner k first at index k; a corner
    on top of another gets 0."""
    out = np.zeros(3)
    for k in range(3):
        u, v = p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]
        n = float(np.hypot(*u) * np.hypot(*v))
        out[k] = math.degrees(math.acos(max(-1.0, min(1.0, float(u @ v) / n)))) if n > 0 else 0.0
    return out


def _hull(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """The corners of the convex hull of ``p`` (all of ``p`` where it is a segment or a point)."""
    hull = shapely.MultiPoint([tuple(q) for q in p]).convex_hull
    return np.asarray(hull.exterior.coords) if hull.geom_type == "Polygon" else p


def _tall_enough(
    p: NDArray[np.float64], hull: NDArray[np.float64], pairs: NDArray[np.intp], a_deg: float
) -> NDArray[np.bool_]:
    """Which ``pairs`` (i, j) (P x 2) some point stands at least |ij| min(sin 2a, sin 120 deg) off the line
    through, for a = ``a_deg``: a necessary condition for (i, j) to be the shortest side of a triangle with every
    angle >= a. With the angles A at i, B at j and C (the smallest) at k, k stands |ij| sin A sin B / sin C off
    the line (law of sines); for a given C, sin A sin B = (cos(A - B) + cos C) / 2 is least at A = C,
    B = 180 - 2C, giving sin 2C, and C lies in [a, 60]. Tested on the convex hull's corners."""
    i, j = pairs[:, 0], pairs[:, 1]
    v = p[j] - p[i]
    dist = np.hypot(v[:, 0], v[:, 1])
    nrm = np.column_stack([-v[:, 1], v[:, 0]]) / np.maximum(dist, 1e-300)[:, None]
    off = nrm @ hull.T - np.einsum("bx,bx->b", nrm, p[i])[:, None]  # signed distances of the corners
    low = min(math.sin(math.radians(2 * a_deg)), math.sin(math.radians(120.0)))
    return np.abs(off).max(axis=1) >= dist * low - 1e-9


def _first_pair(p: NDArray[np.float64], d: NDArray[np.float64], min_angle_deg: float) -> tuple[int, int, int] | None:
    """The triple of the first pair, by decreasing distance, that has a third place making it the shortest side
    with the angle at that place >= ``min_angle_deg``; of several third places the one with the widest angle
    (then the lowest index)."""
    n = len(p)
    iu, ju = np.triu_indices(n, k=1)
    dist = d[iu, ju]
    order = np.lexsort((ju, iu, -dist))  # decreasing distance, ties by index: deterministic
    cos_max = math.cos(math.radians(min_angle_deg - ANGLE_TOL_DEG))
    hull = _hull(p)
    for lo in range(0, len(order), _BLOCK):
        blk = order[lo : lo + _BLOCK]
        if min_angle_deg > 0:  # a pair no place stands far enough off can be no such triangle's shortest side
            blk = blk[_tall_enough(p, hull, np.column_stack([iu[blk], ju[blk]]), min_angle_deg - ANGLE_TOL_DEG)]
            if not blk.size:
                continue
        i, j, dd = iu[blk], ju[blk], dist[blk]
        ok = (d[i] >= dd[:, None]) & (d[j] >= dd[:, None]) & (dd[:, None] > 0)
        ok[np.arange(len(blk)), i] = False
        ok[np.arange(len(blk)), j] = False
        if not ok.any():
            continue
        # cosine of the angle at k between k->i and k->j
        ui = p[i][:, None, :] - p[None, :, :]
        uj = p[j][:, None, :] - p[None, :, :]
        den = d[i] * d[j]
        with np.errstate(invalid="ignore", divide="ignore"):
            cos = np.where(den > 0, np.einsum("bkx,bkx->bk", ui, uj) / np.where(den > 0, den, 1.0), 1.0)
        ok &= cos <= cos_max + 1e-12  # and rounding of the cosine itself (an angle of 0: cos 1 + 2e-16)
        rows = np.flatnonzero(ok.any(axis=1))
        if rows.size:
            r = int(rows[0])
            cand = np.flatnonzero(ok[r])
            k = int(cand[np.argmin(cos[r, cand])])  # the widest angle at k; argmin keeps the lowest index on ties
            return int(i[r]), int(j[r]), k
    return None


def spread_triple(points: NDArray[np.float64], min_angle_deg: float = MIN_ANGLE_DEG) -> tuple[int, ...]:
    """Indices of the spread triple of ``points`` (N x 2) for ``min_angle_deg`` (see the module text; exact,
    deterministic); fewer than three points: all of them."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    if len(p) < 3:
        return tuple(range(len(p)))
    d = np.hypot(*(p[:, None] - p[None]).transpose(2, 0, 1))
    best = _first_pair(p, d, min_angle_deg) if min_angle_deg > 0 else None
    if best is None:
        best = _first_pair(p, d, 0.0)
    if best is None:  # every point on one spot
        best = (0, 1, 2)
    return tuple(sorted(best))


def min_distance(points: NDArray[np.float64]) -> float:
    """The smallest pairwise distance of ``points`` (inf for fewer than two)."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    if len(p) < 2:
        return math.inf
    d = np.hypot(*(p[:, None] - p[None]).transpose(2, 0, 1))
    return float(d[np.triu_indices(len(p), k=1)].min())


def _extent(points: NDArray[np.float64]) -> tuple[float, float]:
    """Width and length (m) of the smallest rotated rectangle round ``points``."""
    rect = shapely.MultiPoint([tuple(q) for q in points]).minimum_rotated_rectangle
    if rect.geom_type != "Polygon":
        return 0.0, float(rect.length)
    xy = np.asarray(rect.exterior.coords)
    a, b = float(np.hypot(*(xy[1] - xy[0]))), float(np.hypot(*(xy[2] - xy[1])))
    return min(a, b), max(a, b)


def spread(points: NDArray[np.float64]) -> Spread:
    """The spread triple of a link's candidate places ``points`` with its geometry and, where it falls short of
    :data:`MIN_SPREAD_M` or :data:`MIN_ANGLE_DEG`, the reason in words (the places' extent)."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    chosen = spread_triple(p)
    if len(chosen) < 2:
        return Spread(chosen, None, None)
    dmin = min_distance(p[list(chosen)])
    angle = float(triangle_angles(p[list(chosen)]).min()) if len(chosen) == 3 else None
    notes = []
    if angle is not None and dmin < MIN_SPREAD_M:
        notes.append(f"targets {dmin:.2f} m apart at most")
    if angle is not None and angle < MIN_ANGLE_DEG - ANGLE_TOL_DEG:
        notes.append(f"no triangle of places with every angle >= {MIN_ANGLE_DEG:g} deg (smallest {angle:.0f} deg)")
    if notes:
        w, length = _extent(p)
        line = " (nearly on one line)" if w <= 0.1 * length else ""
        notes[-1] += f": the {len(p)} places both stations see lie within {w:.1f} m x {length:.1f} m{line}"
    return Spread(chosen, dmin, angle, "; ".join(notes))
