"""The closed-form formulas (3.3)-(3.27) against docs/method.md's reference values."""

from __future__ import annotations

import math

import pytest

from planner.candidates.formulas import MAX_WALL_STATIONS, horizontal_reach_m, vertex_geometry, wall_plan
from planner.core.errors import InputError

S, THETA, O = 95.913, 68.0, 0.30


def reach(h: float) -> float:
    return horizontal_reach_m(S, h)


def test_interior_vertex_of_a_rectangle():
    # Angle 90: alpha 45, HD = sqrt(95.913^2 - 12^2) = 95.159, gamma = 2 (180 - 135) = 90, L = 2 HD cos 45
    g = vertex_geometry(90.0, reach(12.0), THETA)
    assert (round(g.alpha_deg, 3), round(g.hd_m, 3), round(g.gamma_deg, 3)) == (45.0, 95.159, 90.0)
    assert g.covered_m == pytest.approx(2 * 95.159 * math.cos(math.radians(45)), abs=1e-3)


def test_exterior_vertex_of_a_rectangle():
    # Angle 270: HD = cos 68 * 95.159 / cos 45 = 50.41 m, gamma = 180 - (22 + 135) = 23 (docs/method.md)
    g = vertex_geometry(270.0, reach(12.0), THETA)
    assert g.hd_m == pytest.approx(50.41, abs=0.005) and g.gamma_deg == pytest.approx(23.0)
    # L = HD cos 45 (tan 68 - tan 45) = 35.647 * 1.4751 = 52.58
    assert g.covered_m == pytest.approx(52.58, abs=0.01)


@pytest.mark.parametrize("angle, cancelled", [(44.0, True), (44.001, False), (316.0, True), (315.9, False)])
def test_cancelled_vertices(angle, cancelled):
    # Angle < 180 needs alpha > 90 - 68 = 22; Angle > 180 needs alpha < 90 + 68 = 158
    assert (vertex_geometry(angle, reach(10.0), THETA) is None) == cancelled


def test_interior_wall_1_of_polygon_a():
    # L_W = 500, h_C = 25: HD_0 = 34.687, L_C = 171.71, X = 3 at 167.811 / 251.268 / 334.726, b/2 = 12.246 / 24.492 /
    # 12.246, h = 4.948 / 9.896 / 4.948 (table 3.2)
    l1, l2 = 2 * reach(12) * math.cos(math.pi / 4), 2 * reach(25) * math.cos(math.pi / 4)
    p = wall_plan(500.0, reach(25.0), l1, l2, THETA, O)
    assert p.hd0_m == pytest.approx(34.687, abs=2e-3) and p.covered_m == pytest.approx(171.71, abs=0.01)
    assert p.count == 3
    assert [round(s.x_m, 2) for s in p.stations] == pytest.approx([167.81, 251.27, 334.73], abs=0.01)
    assert [s.half_base_m for s in p.stations] == pytest.approx([12.246, 24.492, 12.246], abs=2e-3)
    assert [s.height_m for s in p.stations] == pytest.approx([4.948, 9.896, 4.948], abs=2e-3)


def test_interior_wall_2_of_polygon_a_has_one_candidate():
    # L_W = 250: X'' = 0.116 -> X = 1 at x = 124.403, b/2 = 53.118, h = 21.461
    l1, l2 = 2 * reach(25) * math.cos(math.pi / 4), 2 * reach(20) * math.cos(math.pi / 4)
    p = wall_plan(250.0, reach(25.0), l1, l2, THETA, O)
    (st,) = p.stations
    assert p.count == 1 and st.x_m == pytest.approx(124.403, abs=2e-3)
    assert st.half_base_m == pytest.approx(53.118, abs=2e-3) and st.height_m == pytest.approx(21.461, abs=2e-3)


def test_overlap_rule_of_polygon_b_outside():
    # side 1: 62.75 + 61.62 - 99 = 25.37 >= 0.3 * 61.62 = 18.5: no K^C
    assert wall_plan(99.0, reach(19.0), 62.75, 61.62, THETA, O).stations == ()
    # side 4: 58.26 + 60.64 - 101.737 = 17.16 < 0.3 * 58.26 = 17.48: one K^C
    assert len(wall_plan(101.737, reach(18.0), 58.26, 60.64, THETA, O).stations) == 1


def test_a_degenerate_theta_max_is_refused_not_planned_for_minutes():
    # theta_max 1e-6 deg: a station covers L_C = 2 HD_0 tan(theta) = 2 x 96 m x 1.7e-8 = 3.3e-6 m of wall, so a 99 m
    # wall would need some 3e7 stations; more than MAX_WALL_STATIONS is refused, naming theta_max
    with pytest.raises(InputError, match=r"theta_max_deg = 1e-06: the closed form would put"):
        wall_plan(99.0, 96.0, 0.0, 0.0, 1e-6, 0.3)
    assert wall_plan(99.0, 96.0, 0.0, 0.0, 68.0, 0.3).count <= MAX_WALL_STATIONS
