"""Traverse reconstruction, closure and compass-rule adjustment."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from planner.core.errors import ClosureError
from planner.io import load_site
from planner.site.geometry import side_lengths, signed_area
from planner.site.params import ClosureTolerance
from planner.site.traverse import AcceptedMisclosure, TableRow, ZoneTable, reconstruct, table_from_polygon
from tests.conftest import INSTANCES


def _table(lengths, angles, heights=None) -> ZoneTable:
    heights = heights or [5.0] * len(lengths)
    rows = tuple(TableRow(i + 1, l, h, a, h) for i, (l, a, h) in enumerate(zip(lengths, angles, heights)))
    return ZoneTable("T", "inside", rows)


@pytest.mark.parametrize(
    "name, zone, limit_mm", [("polygon_a", "A", 1e-6), ("polygon_b", "B", 1.0), ("polygon_c", "C", 2.5)]
)
def test_closures_of_table_3_1(name, zone, limit_mm):
    # docs/method.md section 3: A and B close exactly (B to 0.4 mm from 3-decimal rounding), C within 2 mm
    z = load_site(INSTANCES / f"{name}.json").zone(zone)
    assert abs(z.closure.angular_misclosure_deg) < 1e-9
    assert z.closure.linear_misclosure_m * 1000 < limit_mm


def test_polygon_a_is_the_500_by_250_rectangle():
    z = load_site(INSTANCES / "polygon_a.csv").zone("A")
    np.testing.assert_allclose(z.xy, [[0, 0], [500, 0], [500, 250], [0, 250]], atol=1e-9)
    assert z.area_m2 == pytest.approx(125000.0) and z.perimeter_m == pytest.approx(1500.0)


def test_wall_top_is_linear_between_vertex_heights():
    # polygon A wall 1 runs from vertex 1 (12 m) to vertex 2 (25 m); printed wall height 25 = max
    w = load_site(INSTANCES / "polygon_a.csv").zone("A").walls[0]
    assert (w.h_start_m, w.h_end_m, w.printed_height_m) == (12.0, 25.0, 25.0)
    assert float(w.height_at(0.5)) == pytest.approx(18.5) and w.height_check_ok


def test_bowditch_closes_and_moves_vertices_in_proportion():
    # a 10 x 10 square with side 3 printed 10.04: the walk ends at (-0.04, 0), 40.04 / 0.04 = 1:1001 < 1:2000
    table = _table([10, 10, 10.04, 10], [90] * 4)
    with pytest.raises(ClosureError, match=r"zone T: linear misclosure 0.040 m.*1:1001"):
        reconstruct(table, ClosureTolerance())
    xy, report = reconstruct(table, ClosureTolerance(min_relative_precision=500))
    # vertex k moves by -misclosure * walked / perimeter: vertex 4 (walked 30.04 of 40.04) by 0.04*30.04/40.04
    assert report.misclosure_dx_m == pytest.approx(-0.04)
    # vertex 4 was walked to (-0.04, 10) and moves by +0.04 * 30.04 / 40.04 in x; vertex 1 stays
    assert xy[3, 0] == pytest.approx(-0.04 + 0.04 * 30.04 / 40.04)
    assert xy[0].tolist() == [0.0, 0.0] and xy[1, 0] == pytest.approx(10 + 0.04 * 10 / 40.04)


def test_angular_misclosure_names_zone_and_sum():
    table = _table([10, 10, 10, 10], [90, 90, 90, 89])
    with pytest.raises(ClosureError, match=r"zone T: angular misclosure -1.000 deg \(sum 359.000 vs 360"):
        reconstruct(table, ClosureTolerance())


def test_acceptance_must_match_the_figures():
    table = _table([10, 10, 10, 10], [90, 90, 90, 89])
    xy, report = reconstruct(table, ClosureTolerance(), AcceptedMisclosure("T", -1.0, report_lin(table), "test"))
    assert report.accepted_reason == "test"
    with pytest.raises(ClosureError, match="does not match the data"):
        reconstruct(table, ClosureTolerance(), AcceptedMisclosure("T", -2.0, 0.0, "stale"))


def report_lin(table: ZoneTable) -> float:
    """Linear misclosure after spreading the angular one, computed with a loose tolerance."""
    return reconstruct(table, ClosureTolerance(angular_deg=10, min_relative_precision=1e-9))[1].linear_misclosure_m


# --- property tests: a polygon rebuilt from its own sides and angles is the polygon --------------


def _frame(xy: np.ndarray) -> np.ndarray:
    """Move vertex 1 to the origin and turn side 1 onto +x (the table frame)."""
    d = xy - xy[0]
    a = math.atan2(d[1, 1], d[1, 0])
    rot = np.array([[math.cos(-a), -math.sin(-a)], [math.sin(-a), math.cos(-a)]])
    return d @ rot.T


@st.composite
def convex_polygons(draw) -> np.ndarray:
    n = draw(st.integers(3, 12))
    angles = sorted(draw(st.lists(st.floats(0, 2 * math.pi, exclude_max=True), min_size=n, max_size=n, unique=True)))
    gaps = np.diff(np.r_[angles, angles[0] + 2 * math.pi])
    assume(gaps.min() > 0.05 and gaps.max() < math.pi - 0.05)  # no near-collinear or degenerate shapes
    r = draw(st.floats(5, 500))
    return r * np.stack([np.cos(angles), np.sin(angles)], axis=1)


@st.composite
def orthogonal_polygons(draw) -> np.ndarray:
    """A staircase: an orthogonal (rectilinear) polygon with 2k+2 vertices."""
    k = draw(st.integers(1, 6))
    widths = draw(st.lists(st.floats(1, 50), min_size=k, max_size=k))
    heights = draw(st.lists(st.floats(1, 50), min_size=k, max_size=k))
    pts = [(0.0, 0.0)]
    x = sum(widths)
    pts.append((x, 0.0))
    y = 0.0
    for w, h in zip(widths[::-1], heights):
        y += h
        pts.append((x, y))
        x -= w
        pts.append((x, y))
    return np.array(pts)


def _roundtrip(xy: np.ndarray) -> None:
    lengths, angles = table_from_polygon(xy)
    rebuilt, report = reconstruct(_table(list(lengths), list(angles)), ClosureTolerance())
    np.testing.assert_allclose(rebuilt, _frame(xy), atol=1e-6 * max(1.0, float(lengths.sum())))
    assert report.linear_misclosure_m < 1e-6


@settings(max_examples=60, deadline=None)
@given(convex_polygons())
def test_convex_polygon_roundtrip(xy):
    _roundtrip(xy)


@settings(max_examples=60, deadline=None)
@given(orthogonal_polygons())
def test_orthogonal_polygon_roundtrip(xy):
    _roundtrip(xy)


@settings(max_examples=40, deadline=None)
@given(orthogonal_polygons(), st.floats(0, 360), st.floats(-1e6, 1e6), st.floats(-1e6, 1e6))
def test_rotation_and_translation_change_no_figure(xy, angle_deg, tx, ty):
    a = math.radians(angle_deg)
    rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    moved = xy @ rot.T + [tx, ty]
    l0, a0 = table_from_polygon(xy)
    l1, a1 = table_from_polygon(moved)
    np.testing.assert_allclose(l1, l0, atol=1e-6)
    np.testing.assert_allclose(a1, a0, atol=1e-6)
    assert signed_area(moved) == pytest.approx(signed_area(xy), rel=1e-9)
    assert side_lengths(moved).sum() == pytest.approx(side_lengths(xy).sum(), rel=1e-9)
    r0 = reconstruct(_table(list(l0), list(a0)), ClosureTolerance())[1]
    r1 = reconstruct(_table(list(l1), list(a1)), ClosureTolerance())[1]
    assert r1.linear_misclosure_m == pytest.approx(r0.linear_misclosure_m, abs=1e-6)
    assert r1.angular_misclosure_deg == pytest.approx(r0.angular_misclosure_deg, abs=1e-6)
