"""Registration-chain accuracy against hand computation (seed 003: error grows along the chain, ties hold it)."""

from __future__ import annotations

import math

import pytest

from planner.network.chain import (
    chain_accuracy,
    control_count,
    place_ties,
    registration_sigma_m,
    target_centre_sigma_m,
    target_scan_sigma_m,
    tie_sigma_m,
)

# five stations 20 m apart on a line, registered one to the next
XY = {f"S{k}": (20.0 * (k - 1), 0.0) for k in range(1, 6)}
LINKS = [(f"S{k}", f"S{k + 1}") for k in range(1, 5)]
S = 6.8e-5 * 20 + 0.0081  # m_reg of a 20 m link = 9.46 mm (seed 003)
T = 0.002  # a tie of 2 mm


def test_link_and_target_formulas_of_seed_003():
    assert registration_sigma_m(20.0) == pytest.approx(S)
    # formula 4 at R = 20 m, gamma = 1'1.88" (3 mm at 10 m): 0.22 e^0.6 e^(5.9 * 20^0.615 * 0.017189) = 0.76 mm
    gamma = 1 / 60 + 1.88 / 3600
    assert target_scan_sigma_m(20.0, gamma) * 1000 == pytest.approx(0.76, abs=0.005)
    # formula 3 with m_P = 0, D = 20 m, 5", 2 mm: sqrt(2^2 + 2 (20000 * 5 / 206265)^2) = 2.11 mm ("not over 2 mm")
    assert target_centre_sigma_m(0.0, 20.0, 0.002, 5.0) * 1000 == pytest.approx(
        math.sqrt(4 + 2 * (1e5 / 206264.806) ** 2)
    )
    # formula 6: k = 4 equal targets -> sqrt(4 m^2) / 4 = m / 2
    m = math.hypot(0.002, target_scan_sigma_m(15.0, gamma))
    assert tie_sigma_m([15.0] * 4, gamma, 0.002) == pytest.approx(m / 2)


def test_error_grows_with_links_from_control():
    r = chain_accuracy(XY, LINKS, {"S1": T})
    for k in range(1, 6):
        # per axis the variances add along the chain: t^2 + (k-1) s^2; position error = sqrt(2) x that
        hand = math.sqrt(2 * (T**2 + (k - 1) * S**2))
        assert r.sigma_m[f"S{k}"] == pytest.approx(hand, rel=1e-9)
        assert r.links_from_control[f"S{k}"] == k
    assert r.worst[0] == "S5" and r.weakest_chain == ("S1", "S2", "S3", "S4", "S5")
    assert all(r.sigma_m[f"S{k}"] < r.sigma_m[f"S{k + 1}"] for k in range(1, 5))


def _held_at(j: int, k: int) -> float:
    """Position error of station k with ties at S1 and Sj (series-parallel, per axis, then x sqrt 2)."""
    if k <= j:
        a, b = T**2 + (k - 1) * S**2, T**2 + (j - k) * S**2
        var = a * b / (a + b)
    else:
        r_j = T**2 * (T**2 + (j - 1) * S**2) / (2 * T**2 + (j - 1) * S**2)
        var = r_j + (k - j) * S**2
    return math.sqrt(2 * var)


def test_a_tie_at_the_far_end_halves_the_chain_and_is_where_it_helps_most():
    one = chain_accuracy(XY, LINKS, {"S1": T})
    two = chain_accuracy(XY, LINKS, {"S1": T, "S5": T})
    for k in range(1, 6):
        assert two.sigma_m[f"S{k}"] == pytest.approx(_held_at(5, k), rel=1e-9)
        assert two.sigma_m[f"S{k}"] <= one.sigma_m[f"S{k}"]
    # between two ties the weakest station is the middle one: sqrt(t^2 + 2 s^2) = 13.53 mm (from 26.91 mm at S5)
    assert two.worst == ("S3", pytest.approx(math.sqrt(T**2 + 2 * S**2)))
    worst_by_tie = {j: max(_held_at(j, k) for k in range(1, 6)) for j in range(2, 6)}
    assert one.best_tie == f"S{min(worst_by_tie, key=worst_by_tie.get)}"
    assert one.worst_after_tie_m == pytest.approx(min(worst_by_tie.values()))


def test_untied_parts_are_reported_not_adjusted():
    xy = dict(XY, Q=(500.0, 0.0))
    r = chain_accuracy(xy, LINKS, {"S1": T})
    assert r.untied == ("Q",) and "Q" not in r.sigma_m


def test_control_count_and_placement_follow_the_field_rules():
    assert control_count(40.0) == 3 and control_count(260.0) == 6  # at least 3; one per 50 m of chain
    xy = {f"S{k}": (20.0 * k, 0.0) for k in range(11)}
    links = [(f"S{k}", f"S{k + 1}") for k in range(10)]
    ties = place_ties(xy, links, T, 3)
    # first the middle, then the two ends where the error is largest
    assert set(ties) == {"S5", "S0", "S10"}
