"""Accuracy model of docs/method.md section 1, against the dissertation's check values."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.core.errors import InfeasibleError, InputError
from planner.instrument.accuracy import (
    ErrorBudget,
    IncidenceErrorTable,
    RangeAngleSigma,
    combined_sigma,
    instrument_height_tolerance_m,
    max_slant_range_m,
    point_error,
    sigma_instr_m,
    sigma_meas_m,
    tolerance_for_scale_m,
)
from planner.instrument.models import load_instrument

P30 = RangeAngleSigma(range_sigma_const_m=0.0012, range_sigma_ppm=10.0, angle_sigma_arcsec=8.0)
BUDGET = ErrorBudget(0.0005, 0.0005, 0.0005)


def test_sigma_instr_p30_at_10_mm():
    # sqrt(10^2 - 3 * 0.5^2) = sqrt(99.25) = 9.9624 mm (3.2)
    assert sigma_instr_m(0.010, BUDGET) * 1000 == pytest.approx(9.9624, abs=5e-5)


def test_max_slant_range_p30_is_239_55_m():
    # positive root of (3.1) with X = 1.2 mm, Y = 10 ppm, 8": 239.55 m (chapter 4 check value)
    s_max = max_slant_range_m(P30, sigma_instr_m(0.010, BUDGET))
    assert s_max == pytest.approx(239.55, abs=0.005)


def test_sigma_meas_at_s_max_equals_the_budget():
    # (3.1) is sigma_meas(S)^2 = sigma_instr^2 solved for S, so the two must agree at the root
    s_instr = sigma_instr_m(0.010, BUDGET)
    assert float(sigma_meas_m(max_slant_range_m(P30, s_instr), P30)) == pytest.approx(s_instr, rel=1e-12)


def test_no_instrument_budget_left_is_infeasible():
    # sqrt(3 * 0.5^2) = 0.866 mm of non-instrument error; asking for 0.8 mm leaves nothing
    with pytest.raises(InfeasibleError, match="no instrument error budget left"):
        sigma_instr_m(0.0008, BUDGET)


def test_constant_range_error_above_budget_is_infeasible():
    # X = 1.2 mm alone exceeds a 1.0 mm instrument budget: no range works
    with pytest.raises(InfeasibleError):
        max_slant_range_m(P30, 0.0010)


def test_instrument_height_tolerance_is_0_091_m():
    # (3.32): 96/2 * (sqrt(1 - (39.6/96)^2) - sqrt(1 - (40/96)^2)) = 0.0912 m
    assert instrument_height_tolerance_m(40.0, 96.0, 0.0, 0.4) == pytest.approx(0.091, abs=5e-4)


def test_point_error_components():
    # e_x^2 + e_y^2 = e^2 and e_x = e at 90 deg; at S = 0, e = sqrt(0.75 + 1.44) mm
    pe = point_error(np.array([0.0, 50.0]), np.array([0.0, 90.0]), P30, BUDGET)
    assert pe.e_m[0] * 1000 == pytest.approx(math.sqrt(0.75 + 1.44))
    np.testing.assert_allclose(pe.e_x_m**2 + pe.e_y_m**2, pe.e_m**2)
    assert pe.e_x_m[1] == pytest.approx(pe.e_m[1])


def test_seed_002_combined_error_is_4_5_mm():
    # seed 002: sqrt(4^2 + 2^2) = 4.47 mm, printed 4.5 mm
    assert combined_sigma(4.0, 2.0) == pytest.approx(4.5, abs=0.05)
    ss2 = load_instrument("leica-scanstation-2")
    assert combined_sigma(ss2.range_sigma_const_m, ss2.modelling_sigma_m) * 1000 == pytest.approx(4.472, abs=1e-3)


def test_incidence_table_nodes_and_interpolation():
    table = IncidenceErrorTable()
    fx, fy = table.measured_mm([0, 68, 64])
    assert fx[0] == 0.0 and fy[1] == pytest.approx(3.04)
    # halfway between 60 (7.17) and 68 (7.60): 7.385
    assert fx[2] == pytest.approx((7.17 + 7.60) / 2)
    # 68..79 extrapolates the last segment: f_y(76) = 3.04 + 8 * (3.04 - 3.95) / 8 = 2.13
    assert table.measured_mm([76])[1][0] == pytest.approx(2.13)
    with pytest.raises(InputError, match="incidence angle"):
        table.measured_mm([80])


@pytest.mark.parametrize(
    "scale, mm", [("1:50", 5), ("1:100", 20), ("1:200", 50), ("1:500", 300), ("1:10", 2), (20, 2), ("1:75", 5)]
)
def test_drawing_scale_tolerance(scale, mm):
    # table 1.1, upper value of the row; between rows the stricter (1:75 -> the 1:50 row)
    assert tolerance_for_scale_m(scale) == pytest.approx(mm / 1000)


@pytest.mark.parametrize("scale", ["1:1000", "1:0", "fifty", "1:2.5"])
def test_drawing_scale_outside_table_refused(scale):
    with pytest.raises(InputError, match="drawing_scale"):
        tolerance_for_scale_m(scale)


def test_dissertation_preset_s_max_matches_table_3_2():
    # table 3.2 pairs HD = 95.159 m with h = 12 m: sqrt(95.159^2 + 12^2) = 95.913 m
    preset = load_instrument("dissertation-tables")
    assert preset.max_slant_range_m == pytest.approx(math.hypot(95.159, 12.0), abs=5e-4)
