"""Random small sites for the plane property tests (hypothesis strategies) and the brute-force oracles.

Shapes: rectangles of any aspect, L, T and U rooms, corridors, rooms with a free-standing block; each turned by a random
angle and moved by a random offset (a count never depends on either).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
import shapely
from hypothesis import strategies as st

from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Site, Zone
from planner.site.params import Parameters


def _place(
    xy: list[tuple[float, float]], angle_deg: float, shift: tuple[float, float]
) -> tuple[tuple[float, float], ...]:
    c, s = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))
    pts = np.round(np.asarray(xy, float) @ np.array([[c, s], [-s, c]]) + np.asarray(shift), 9)  # to 1 nm, as drawn
    return tuple((float(x), float(y)) for x, y in pts)


def outline(kind: str, w: float, h: float, a: float, b: float) -> list[tuple[float, float]]:
    """A room of ``kind`` in a w x h box; ``a`` and ``b`` (shares 0.2..0.8) set its arms."""
    if kind == "L":
        return [(0, 0), (w, 0), (w, b * h), (a * w, b * h), (a * w, h), (0, h)]
    if kind == "T":
        x0, x1 = a * w * 0.5, a * w * 0.5 + max(0.3, 1 - a) * w * 0.5 + 1.5
        return [(0, 0), (w, 0), (w, b * h), (x1, b * h), (x1, h), (x0, h), (x0, b * h), (0, b * h)]
    if kind == "U":
        arm = max(1.5, a * w * 0.4)
        return [(0, 0), (w, 0), (w, h), (w - arm, h), (w - arm, b * h), (arm, b * h), (arm, h), (0, h)]
    return [(0, 0), (w, 0), (w, h), (0, h)]


@st.composite
def rooms(draw: st.DrawFn, max_size_m: float = 20.0, blocks: bool = True) -> Site:
    """A random inside room (rectangle, L, T, U, possibly with a block), random theta_max and range."""
    kind = draw(st.sampled_from(["rect", "rect", "L", "T", "U"]))
    w = draw(st.floats(1.5, max_size_m))
    h = draw(st.floats(1.5, max_size_m))
    if kind != "rect":
        w, h = max(w, 5.0), max(h, 5.0)
    a, b = draw(st.floats(0.3, 0.7)), draw(st.floats(0.3, 0.7))
    xy = outline(kind, w, h, a, b)
    if not shapely.Polygon(xy).is_valid:
        kind, xy = "rect", outline("rect", w, h, a, b)
    height = draw(st.floats(2.0, 5.0))
    holes: tuple = ()
    if blocks and kind == "rect" and min(w, h) > 5.0 and draw(st.booleans()):
        s = draw(st.floats(0.5, min(w, h) / 4))
        cx, cy = w / 2, h / 2
        holes = ([(cx - s, cy - s), (cx - s, cy + s), (cx + s, cy + s), (cx + s, cy - s)],)
    angle, shift = draw(st.floats(0, 360)), (draw(st.floats(-1e3, 1e3)), draw(st.floats(-1e3, 1e3)))
    zone = Zone(
        "R",
        ScanSide.INSIDE,
        _place(xy, angle, shift),
        (height,) * len(xy),
        holes=tuple(_place(list(hole), angle, shift) for hole in holes),
        hole_heights_m=tuple((height,) * 4 for _ in holes),
    )
    params = Parameters(
        theta_max_deg=draw(st.floats(30.0, 85.0)), max_slant_range_m=draw(st.floats(height + 1.0, 60.0)), overlap=0.0
    )
    return Site(f"{kind} {w:.2f} x {h:.2f}", (zone,), parameters=params)


def positions(zone: Zone, step_m: float) -> list[Candidate]:
    """Every point of a ``step_m`` grid (anchored at the zone's first corner, along its first wall) inside it."""
    poly = shapely.Polygon(zone.vertices, holes=list(zone.holes))
    v = np.asarray(zone.vertices, float)
    ux = (v[1] - v[0]) / np.hypot(*(v[1] - v[0]))
    uy = np.array([-ux[1], ux[0]])
    r = float(np.max(np.hypot(*(v - v[0]).T)))
    k = np.arange(-math.ceil(r / step_m), math.ceil(r / step_m) + 1) * step_m
    gx, gy = np.meshgrid(k, k)
    pts = v[0] + np.outer(gx.ravel(), ux) + np.outer(gy.ravel(), uy)
    pts = pts[shapely.contains_xy(poly, pts[:, 0], pts[:, 1])]
    return as_candidates(zone, pts)


def as_candidates(zone: Zone, pts: np.ndarray, tag: str = "Q") -> list[Candidate]:
    return [
        Candidate(f"{tag}{k}", zone.id, zone.scan_side.sides[0], zone.frame, float(x), float(y), CandidateKind.GRID)
        for k, (x, y) in enumerate(np.asarray(pts, float).reshape(-1, 2))
    ]


def min_cover(by_candidate: sp.csr_matrix) -> float:
    """The exact minimum number of rows of ``by_candidate`` that cover every column (HiGHS MILP); inf if none."""
    from scipy.optimize import Bounds, LinearConstraint, milp

    a = by_candidate.astype(float).T.tocsr()
    if np.any(np.diff(a.indptr) == 0):
        return math.inf
    n = a.shape[1]
    res = milp(
        np.ones(n),
        constraints=LinearConstraint(a, lb=np.ones(a.shape[0])),
        integrality=np.ones(n),
        bounds=Bounds(0, 1),
        options={"disp": False},
    )
    assert res.status == 0, res.message
    return float(round(res.fun))
