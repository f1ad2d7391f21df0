"""e(S, theta): the incidence effect on a view's point error, and theta_max derived from sigma_req."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from planner.core.errors import InputError
from planner.instrument.accuracy import (
    ErrorBudget,
    RangeAngleSigma,
    combined_error_m,
    derive_theta_max_deg,
    incidence_factor,
    max_slant_range_m,
    point_error,
    precision_ok,
    sigma_instr_m,
    view_error_m,
)
from planner.instrument.models import load_instrument
from planner.io import load_site
from planner.site.params import Parameters, resolve_theta_limit
from planner.site.validate import validate_site
from tests.conftest import square_rows

P30 = RangeAngleSigma(range_sigma_const_m=0.0012, range_sigma_ppm=10.0, angle_sigma_arcsec=8.0)
BUDGET = ErrorBudget(0.0005, 0.0005, 0.0005)
NO_BUDGET = ErrorBudget(0.0, 0.0, 0.0)


def test_60_deg_view_is_worse_than_0_deg_by_the_table_ratio():
    # table 2.3: at 0 deg the error is f_y(0) = 8.22 mm across the wall; at 60 deg an along-wall
    # f_x(60) = 7.17 mm appears: ratio sqrt(67.568 + 51.409) / 8.22 = sqrt(118.977) / 8.22 = 10.9077 / 8.22 = 1.3270
    ratio = math.sqrt(8.22**2 + 7.17**2) / 8.22
    e0, e60 = view_error_m([50.0, 50.0], [0.0, 60.0], P30, NO_BUDGET, "table")
    assert e60 > e0
    assert e60 / e0 == pytest.approx(ratio, rel=1e-12)
    assert ratio == pytest.approx(1.3270, abs=1e-4)
    # with the station, centring and graphical terms the ratio is smaller but still > 1
    f0, f60 = view_error_m([50.0, 50.0], [0.0, 60.0], P30, BUDGET, "table")
    assert 1.0 < f60 / f0 < ratio


def test_no_incidence_model_is_2_13_as_printed():
    s, th = np.array([10.0, 95.913, 200.0]), np.array([0.0, 40.0, 68.0])
    assert view_error_m(s, th, P30, BUDGET, "none") == pytest.approx(point_error(s, th, P30, BUDGET).e_m)
    # and at normal incidence every model reduces to it
    for model in ("table", "soudarissanane"):
        assert view_error_m(s, 0.0, P30, BUDGET, model) == pytest.approx(point_error(s, 0.0, P30, BUDGET).e_m)


def test_soudarissanane_scales_the_range_term_by_1_over_cos():
    # at 60 deg the range term doubles (1 / cos 60 = 2), the angular term stays:
    # S = 50 m: sigma_S = 1.2 + 0.5 = 1.7 mm -> 3.4 mm; angular 8" * 50 m = 1.939 mm
    angular = 8.0 / (180 * 3600 / math.pi) * 50.0
    expected = math.sqrt(0.0034**2 + angular**2)
    assert view_error_m(50.0, 60.0, P30, NO_BUDGET, "soudarissanane") == pytest.approx(expected, rel=1e-12)
    assert incidence_factor(60.0, "soudarissanane") == pytest.approx(2.0)


def test_theta_max_derived_for_the_p30_at_10_mm_matches_the_hand_computation():
    # S = 200 m: sigma_S = 1.2 + 10 * 0.2 = 3.2 mm; angular = 8 / 206264.8 * 200000 mm = 7.7570 mm;
    # sigma_meas^2 = 3.2^2 + 7.7570^2 = 10.24 + 60.172 = 70.412 mm^2; budget 3 * 0.5^2 = 0.75 mm^2.
    # e <= 10 mm  <=>  k^2 <= (100 - 0.75) / 70.412 = 1.40956  <=>  f_x <= 8.22 * sqrt(0.40956) = 5.2606 mm,
    # between 30 deg (4.43) and 40 deg (5.6): theta = 30 + 10 * (5.2606 - 4.43) / (5.6 - 4.43) = 37.10 deg
    theta = derive_theta_max_deg(200.0, P30, BUDGET, 0.010, "table")
    assert theta == pytest.approx(37.10, abs=0.01)
    # the view at that incidence meets the budget exactly
    assert view_error_m(200.0, theta, P30, BUDGET, "table") == pytest.approx(0.010, abs=1e-8)
    # at 95.913 m the error stays under 10 mm up to the table's limit (79 deg), and at the
    # precision range of (3.1), 239.55 m, not even a perpendicular view is left any margin
    assert derive_theta_max_deg(95.913, P30, BUDGET, 0.010, "table") == 79.0
    s_max = max_slant_range_m(P30, sigma_instr_m(0.010, BUDGET))
    assert derive_theta_max_deg(s_max + 0.01, P30, BUDGET, 0.010, "table") == 0.0


def test_derived_theta_is_printed_by_validation(write_csv):
    site = load_site(write_csv(square_rows()))
    site = replace(site, parameters=replace(site.parameters, derive_theta_max=True, incidence_model="table"))
    text = validate_site(site).summary()
    assert "theta_max derived" in text and "37.1 deg at 200 m" in text


def test_derive_switches_the_table_model_on():
    p = Parameters(derive_theta_max=True)
    assert p.incidence_model == "table"
    limit = resolve_theta_limit(p, load_instrument("leica-p30"), 239.55)
    assert limit.theta_max_deg == 79.0 and dict(limit.by_range)[200.0] == pytest.approx(37.10, abs=0.01)
    with pytest.raises(InputError):
        Parameters(incidence_model="cosine")


def test_precision_ok_and_combined_error():
    assert precision_ok(95.913, 68.0, P30, BUDGET, 0.010, "table")
    assert not precision_ok(200.0, 40.0, P30, BUDGET, 0.010, "table")
    # two equal views of 10 mm combine to 10 / sqrt(2) = 7.071 mm; none: infinite
    assert combined_error_m([0.010, 0.010]) == pytest.approx(0.010 / math.sqrt(2))
    assert combined_error_m([]) == math.inf


def test_coverage_refuses_a_view_by_its_incidence_only_with_an_incidence_model():
    from planner.coverage.targets import Targets
    from planner.coverage.visibility import PrecisionRule, SightLimits, geometric_pairs

    # a 1 m piece on the x axis facing +y, one candidate 200 m away at about 45 deg incidence:
    # (3.1) alone allows it (200 < 239.55 m), the table model does not (theta_max(200 m) = 37.1 deg)
    a, b = np.array([[0.0, 0.0]]), np.array([[1.0, 0.0]])
    cand = np.array([[142.0, 141.0]])
    one, zero = np.ones(1), np.zeros(1)
    zone, side = np.zeros(1, np.int32), np.zeros(1, np.int8)  # zone 0, an inside face
    piece = Targets(
        zone=zone,
        frame=zone,
        frames=("site",),
        zone_ids=("Z",),
        side=side,
        wall=one,
        s0_m=zero,
        s1_m=one,
        a=a,
        b=b,
        ha_m=zero,
        hb_m=zero,
        normal=np.array([[0.0, 1.0]]),
    )
    args = (cand, np.ones((1, 1), bool), piece, np.arange(1))
    s_prec = max_slant_range_m(P30, sigma_instr_m(0.010, BUDGET))
    for model, seen in (("none", 1), ("table", 0)):
        rule = PrecisionRule(P30, BUDGET, 0.010, model)
        pairs = geometric_pairs(*args, SightLimits(300.0, 79.0, precision_range_m=s_prec, precision=rule))
        assert len(pairs.cand) == seen
    # in combined mode no single view is refused for precision: verification sums them instead
    rule = PrecisionRule(P30, BUDGET, 0.010, "table", combined=True)
    assert len(geometric_pairs(*args, SightLimits(300.0, 79.0, precision=rule)).cand) == 1


def test_max_slant_for_view_is_where_the_view_error_reaches_sigma_req():
    from planner.instrument.accuracy import max_slant_for_view_m

    # at normal incidence every model gives (3.1): 239.55 m for the P30 at 10 mm with 0.5 mm terms
    s_max = max_slant_range_m(P30, sigma_instr_m(0.010, BUDGET))
    for model in ("none", "table", "soudarissanane"):
        assert max_slant_for_view_m(0.0, P30, BUDGET, 0.010, model)[0] == pytest.approx(s_max, rel=1e-12)
    # table, 37.10 deg: the hand computation of the theta_max test read backwards gives 200 m
    assert max_slant_for_view_m(37.10, P30, BUDGET, 0.010, "table")[0] == pytest.approx(200.0, abs=0.05)
    # and at every angle e(S_lim, theta) = sigma_req
    th = np.array([5.0, 30.0, 60.0, 75.0])
    for model in ("table", "soudarissanane"):
        s = max_slant_for_view_m(th, P30, BUDGET, 0.010, model)
        assert view_error_m(s, th, P30, BUDGET, model) == pytest.approx(np.full(4, 0.010), rel=1e-9)
    # Soudarissanane at 85 deg: the range term alone, 1.2 mm / cos 85 = 13.8 mm, exceeds 10 mm at S = 0
    assert max_slant_for_view_m(85.0, P30, BUDGET, 0.010, "soudarissanane")[0] == 0.0
