"""Checks and measures of plane polygons given as (n, 2) vertex arrays (no closing repeat)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.core.checks import finite_number
from planner.core.errors import InputError

#: Two vertices closer than this (m) make a zero-length side.
ZERO_LENGTH_M = 1e-9


def read_only(a: NDArray) -> NDArray:
    """``a`` as a contiguous array that cannot be written (arrays shared between objects, never changed)."""
    a = np.ascontiguousarray(a)
    a.flags.writeable = False
    return a


def cross_z(u: NDArray[np.float64], v: NDArray[np.float64]) -> float:
    """z of the 2-D cross product u x v."""
    return float(u[0] * v[1] - u[1] * v[0])


def as_vertices(points: object, *, what: str, zone: str | None = None) -> NDArray[np.float64]:
    """Read a list of [x, y] pairs into an (n, 2) float array, refusing anything non-finite. A closing vertex equal to
    the first is dropped (GeoJSON/DXF write rings closed)."""
    if not isinstance(points, Sequence) or isinstance(points, (str, bytes)):
        raise InputError("must be a list of [x, y] pairs", zone=zone, field=what, value=type(points).__name__)
    rows = []
    for k, p in enumerate(points, start=1):
        if not isinstance(p, Sequence) or isinstance(p, (str, bytes)) or len(p) != 2:
            raise InputError("must be an [x, y] pair", zone=zone, row=f"vertex {k}", field=what, value=p)
        for v in p:
            if not finite_number(v):
                raise InputError(
                    "coordinate must be a finite number", zone=zone, row=f"vertex {k}", field=what, value=v
                )
        rows.append((float(p[0]), float(p[1])))
    xy = np.array(rows, dtype=float).reshape(-1, 2)
    if len(xy) > 3 and np.array_equal(xy[0], xy[-1]):
        xy = xy[:-1]
    return xy


def signed_area(xy: NDArray[np.float64]) -> float:
    """Shoelace area, positive for counter-clockwise vertex order. Coordinates are taken relative to the first vertex so
    that projected coordinates around 10^6 m lose no precision."""
    if len(xy) < 3:  # no area (check_simple_polygon says why)
        return 0.0
    with np.errstate(over="ignore", invalid="ignore"):  # absurd coordinates: check_simple_polygon names them
        d = xy - xy[0]
        x, y = d[:, 0], d[:, 1]
        return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def side_lengths(xy: NDArray[np.float64]) -> NDArray[np.float64]:
    """Length of side i, from vertex i to vertex i+1 (cyclic)."""
    d = np.roll(xy, -1, axis=0) - xy
    return np.asarray(np.hypot(d[:, 0], d[:, 1]), dtype=np.float64)


def ring_key(xy: NDArray[np.float64], decimals: int = 6) -> tuple[tuple[float, float], ...]:
    """The ring as a canonical tuple: counter-clockwise, starting at its lexicographically least vertex,
    coordinates rounded to ``decimals`` (1e-6 m): two rings drawn alike, from any start and in either
    direction, have the same key."""
    pts = np.round(np.asarray(xy, dtype=float).reshape(-1, 2), decimals) + 0.0  # + 0.0: no -0.0
    if signed_area(pts) < 0:
        pts = pts[::-1]
    rows = [(float(p[0]), float(p[1])) for p in pts]
    k = rows.index(min(rows))
    return tuple(rows[k:] + rows[:k])


#: no site coordinate is farther out (projected CRSs stay within +-2e7 m); beyond it sums overflow
MAX_COORDINATE_M = 1e8


def check_simple_polygon(xy: NDArray[np.float64], *, what: str, zone: str | None = None) -> None:
    """Refuse fewer than 3 vertices, zero-length sides, zero area and self-intersection (found with an STRtree over the
    sides, not n^2 pair tests); the message names the two sides (1-based) and where they meet."""
    n, where = len(xy), {"zone": zone, "field": what}
    if n < 3:
        raise InputError("a polygon needs at least 3 vertices", value=n, **where)
    far = np.flatnonzero(~np.all(np.isfinite(xy) & (np.abs(xy) <= MAX_COORDINATE_M), axis=1))
    if far.size:
        k, why = int(far[0]), f"coordinates must be finite and within +-{MAX_COORDINATE_M:g} m"
        raise InputError(why, row=f"vertex {k + 1}", value=tuple(map(float, xy[k])), **where)
    lengths = side_lengths(xy)
    short = np.flatnonzero(lengths <= ZERO_LENGTH_M)
    if short.size:
        k = int(short[0])
        why = "zero-length side (duplicate vertex)"
        raise InputError(why, zone=zone, row=f"side {k + 1}", field="side_length_m", value=float(lengths[k]))
    origin = xy[0]
    local = xy - origin
    if np.linalg.matrix_rank(local, tol=ZERO_LENGTH_M) < 2:
        raise InputError("polygon has zero area (all vertices on one line)", value=0.0, **where)
    segs = shapely.linestrings(np.stack([local, np.roll(local, -1, axis=0)], axis=1))
    tree = shapely.STRtree(segs)
    i, j = tree.query(segs, predicate="intersects")
    keep = i < j
    i, j = i[keep], j[keep]
    adjacent = (j == i + 1) | ((i == 0) & (j == n - 1))
    inter = shapely.intersection(segs[i], segs[j])
    # adjacent sides share their common vertex; anything more (a fold back) is a crossing
    bad = ~adjacent | (shapely.length(inter) > 0)
    if np.any(bad):
        k = int(np.flatnonzero(bad)[0])
        p = shapely.get_coordinates(inter[k])[0] + origin
        why = f"self-intersecting polygon: sides {i[k] + 1} and {j[k] + 1} meet at ({p[0]:.3f}, {p[1]:.3f})"
        raise InputError(why, **where)
    area = signed_area(xy)
    if abs(area) <= ZERO_LENGTH_M:
        raise InputError("polygon has zero area", value=area, **where)
