"""The closed-form station geometry of chapter 3 of seed 000 (docs/method.md section 2), as pure formulas.

Angles in degrees, lengths in metres. Nothing here knows about coordinates: :mod:`planner.candidates.closed_form` places
the results on a zone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from planner.core.errors import InputError


def _cos(deg: float) -> float:
    return math.cos(math.radians(deg))


def _tan(deg: float) -> float:
    return math.tan(math.radians(deg))


def horizontal_reach_m(max_slant_range_m: float, height_m: float, instrument_height_m: float = 0.0) -> float:
    """sqrt(S_max^2 - (h - IH)^2): the horizontal distance at which the top of a wall of height h is at S_max. 0 when
    the top is out of reach altogether."""
    dz = height_m - instrument_height_m
    return math.sqrt(max_slant_range_m**2 - dz**2) if abs(dz) < max_slant_range_m else 0.0


@dataclass(frozen=True)
class VertexGeometry:
    """A vertex candidate K^B: half-angle alpha, distance HD from the vertex, scanning angle gamma, and L, the wall
    length it covers on each side of the corner (3.3-3.10)."""

    angle_deg: float  # polygon angle on the scanning side
    alpha_deg: float
    hd_m: float
    gamma_deg: float
    covered_m: float

    @property
    def reflex(self) -> bool:
        return self.angle_deg >= 180.0


def vertex_geometry(angle_deg: float, reach_m: float, theta_max_deg: float) -> VertexGeometry | None:
    """K^B for a vertex whose angle on the scanning side is ``angle_deg``; None when cancelled. ``reach_m`` is
    sqrt(S_max^2 - h_V^2). Angle < 180 (3.3-3.5) exists only if alpha > 90 - theta_max; Angle >= 180 (3.6-3.10) only if
    alpha < 90 + theta_max. (A straight vertex, Angle = 180, takes the second case: a wall station.)"""
    alpha = angle_deg / 2.0
    if reach_m <= 0.0:
        return None
    if angle_deg < 180.0:
        if alpha <= 90.0 - theta_max_deg:
            return None
        hd = reach_m
        gamma = 2.0 * (180.0 - (90.0 + alpha))
        covered = 2.0 * hd * _cos(alpha)
    else:
        if alpha >= 90.0 + theta_max_deg:
            return None
        hd = _cos(theta_max_deg) * reach_m / _cos(alpha - 90.0)
        gamma = 180.0 - ((90.0 - theta_max_deg) + alpha)
        covered = hd * _cos(alpha - 90.0) * (_tan(theta_max_deg) - _tan(alpha - 90.0))
    return VertexGeometry(angle_deg, alpha, hd, gamma, covered)


@dataclass(frozen=True)
class WallStation:
    """One wall candidate K^C in the wall's frame (x along the wall from its first vertex, y into the scanning side)
    with its movement field, an isosceles triangle of base b and height h whose base lies at y and apex at y - h."""

    x_m: float
    y_m: float
    half_base_m: float
    height_m: float


@dataclass(frozen=True)
class WallPlan:
    """The wall candidates of one wall (3.11-3.27) and the figures that decided them."""

    hd0_m: float  # HD_0, perpendicular stand-off
    covered_m: float  # L_C
    reduced_m: float  # L_W''
    x_raw: float  # X''
    count: int  # X (as computed; <= 0 possible)
    vertex_overlap_m: float  # l1 + l2 - L_W, the shared length of the two K^B
    stations: tuple[WallStation, ...]


#: more closed-form stations than this on one wall means a degenerate theta_max, not a plan
MAX_WALL_STATIONS = 10_000


def wall_plan(
    wall_length_m: float, reach_m: float, l1_m: float, l2_m: float, theta_max_deg: float, overlap: float
) -> WallPlan:
    """Wall candidates for a wall of length L_W whose ends' K^B cover l1 and l2 (0 if cancelled). ``reach_m`` is
    sqrt(S_max^2 - h_C^2). Cases (3.19-3.27): X <= 0 with the two K^B sharing at least O% of the shorter of l1, l2: no
    candidate; X <= 0 without it, or X = 1: one candidate; X > 1: X candidates."""
    o = overlap
    hd0 = reach_m * _cos(theta_max_deg)
    l_c = 2.0 * hd0 * _tan(theta_max_deg)
    l_o = l_c * o
    reduced = wall_length_m + l1_m * (o - 1.0) + l2_m * (o - 1.0)
    x_raw = (reduced - l_o) / (l_c - l_o) if l_c > l_o else math.inf
    count = math.ceil(x_raw) if math.isfinite(x_raw) else 0
    if count > MAX_WALL_STATIONS:  # a tiny theta_max: each station covers almost nothing (1e-6 deg ran for minutes)
        raise InputError(
            f"the closed form would put {count:,} stations on one {wall_length_m:g} m wall (each covers "
            f"{l_c:.3g} m); theta_max is too small for this site",
            field="theta_max_deg",
            value=theta_max_deg,
        )
    shared = l1_m + l2_m - wall_length_m
    cot = _tan(90.0 - theta_max_deg)
    stations: tuple[WallStation, ...]
    if l_c <= 0.0:
        stations = ()
    elif count <= 0 and shared >= o * min(l1_m, l2_m):
        stations = ()
    elif count <= 1:
        x = (wall_length_m + l1_m * (1.0 - o) - l2_m * (1.0 - o)) / 2.0
        b = l_c - reduced
        stations = (WallStation(x, hd0, b / 2.0, b / 2.0 * cot),)
    else:
        l_no = (reduced - count * l_c) / (1.0 - count)
        m = l_no - l_c * o
        out = []
        for k in range(1, count + 1):
            first, last = k == 1, k == count
            delta = -m / 4.0 if first else (m / 4.0 if last else 0.0)
            b = m / 2.0 if (first or last) else m
            x = l1_m * (1.0 - o) + l_c / 2.0 + (k - 1) * (l_c - l_no) + delta
            out.append(WallStation(x, hd0, b / 2.0, b / 2.0 * cot))
        stations = tuple(out)
    return WallPlan(hd0, l_c, reduced, x_raw, count, shared, stations)
