"""Least-squares adjustment: the dissertation's worked example, hand-derived networks, invariants."""

from __future__ import annotations

import math

import pytest

from planner.core.errors import InputError
from planner.network.adjustment import Obs, adjust
from planner.network.montecarlo import monte_carlo

# section 2.1.2, table 2.1: points 1 and 2 observed (as coordinates) from ST1 and ST2
L = [1007.4065, 1035.5835, 1048.4105, 1037.5990, 1007.4069, 1035.5860, 1048.4093, 1037.5963]
P = [113360.4, 33532.9, 97933.3, 32039.9, 141893.2, 66455.9, 170106.5, 72053.01]


def test_worked_example_2_1_2():
    # each coordinate is observed twice, so X = weighted mean: x1 = (1007.4065 * 113360.4 +
    # 1007.4069 * 141893.2) / 255253.6 = 1007.40672
    names = [("1", "x"), ("1", "y"), ("2", "x"), ("2", "y")] * 2
    obs = [Obs(k, n, None, v, 1 / math.sqrt(p)) for (n, k), v, p in zip(names, L, P)]
    adj = adjust({"1": (1007.4, 1035.6), "2": (1048.4, 1037.6)}, [], obs, observed=True)
    got = adj.point("1"), adj.point("2")
    assert (round(got[0].x, 4), round(got[0].y, 4), round(got[1].x, 4), round(got[1].y, 4)) == (
        1007.4067,
        1035.5852,
        1048.4097,
        1037.5971,
    )
    # sigma of a weighted mean of two: 1 / sqrt(p1 + p2) (a priori, m0 scaling aside)
    design = adjust({"1": (1007.4, 1035.6), "2": (1048.4, 1037.6)}, [], obs)
    assert design.point("1").sigma_x == pytest.approx(1 / math.sqrt(113360.4 + 141893.2))


def trilateration(sigma: float = 0.002):
    # P at (50, 50) from fixed A (0, 0) and B (100, 0): the unit vectors (0.707, 0.707) and (-0.707, 0.707)
    # are orthogonal, so N = I / sigma^2 and sigma_x = sigma_y = sigma exactly
    coords = {"A": (0.0, 0.0), "B": (100.0, 0.0), "P": (50.0, 50.0)}
    obs = [Obs("distance", "A", "P", math.hypot(50, 50), sigma), Obs("distance", "B", "P", math.hypot(50, 50), sigma)]
    return coords, obs


def test_trilateration_by_hand():
    coords, obs = trilateration()
    p = adjust(coords, ["A", "B"], obs).point("P")
    assert p.sigma_x == pytest.approx(0.002) and p.sigma_y == pytest.approx(0.002)
    assert p.ellipse_a == pytest.approx(0.002) and p.position_error == pytest.approx(0.002 * math.sqrt(2))


def traverse():
    coords = {"A": (0.0, 0.0), "B": (100.0, 0.0), "C": (60.0, 70.0), "D": (20.0, 60.0)}
    obs = []
    for s in ("A", "B"):
        for t in ("C", "D"):
            az = math.atan2(coords[t][1] - coords[s][1], coords[t][0] - coords[s][0])
            obs += [
                Obs("direction", s, t, math.degrees(az), 5 / 3600),
                Obs("distance", s, t, math.dist(coords[s], coords[t]), 0.002),
            ]
        other = "B" if s == "A" else "A"
        obs.append(
            Obs(
                "direction",
                s,
                other,
                math.degrees(math.atan2(coords[other][1] - coords[s][1], coords[other][0] - coords[s][0])),
                5 / 3600,
            )
        )
    obs.append(Obs("distance", "C", "D", math.dist(coords["C"], coords["D"]), 0.002))
    return coords, obs


def test_normal_equations_and_qr_agree():
    coords, obs = traverse()
    noisy = [
        Obs(o.kind, o.at, o.to, o.value + (0.003 if o.kind == "distance" else 2 / 3600) * ((-1) ** k), o.sigma)
        for k, o in enumerate(obs)
    ]
    a = adjust(
        coords, ["A", "B"], [Obs(o.kind, o.at, o.to, o.value, o.sigma) for o in noisy], observed=True, angle_unit="deg"
    )
    b = adjust(coords, ["A", "B"], noisy, observed=True, angle_unit="deg", method="qr")
    for n in ("C", "D"):
        assert abs(a.point(n).x - b.point(n).x) < 1e-9 and abs(a.point(n).y - b.point(n).y) < 1e-9
        assert abs(a.point(n).sigma_x - b.point(n).sigma_x) < 1e-9


def test_degrees_gons_metres_millimetres_agree():
    coords, obs = traverse()
    deg = adjust(coords, ["A", "B"], obs, angle_unit="deg")

    def scaled(angle: float, length: float) -> list[Obs]:
        """The observations with directions times ``angle`` and lengths times ``length``."""
        k = {True: angle, False: length}
        return [
            Obs(o.kind, o.at, o.to, o.value * k[o.kind == "direction"], o.sigma * k[o.kind == "direction"]) for o in obs
        ]

    gon = adjust(coords, ["A", "B"], scaled(400 / 360, 1.0), angle_unit="gon")
    mm_coords = {k: (x * 1000, y * 1000) for k, (x, y) in coords.items()}
    mm = adjust(mm_coords, ["A", "B"], scaled(1.0, 1000.0), angle_unit="deg", length_unit="mm")
    for n in ("C", "D"):
        assert gon.point(n).sigma_x == pytest.approx(deg.point(n).sigma_x, rel=1e-9)
        assert mm.point(n).sigma_y == pytest.approx(deg.point(n).sigma_y * 1000, rel=1e-9)


def test_blunder_is_flagged_and_chi_square_fails():
    coords, obs = traverse()
    bad = list(obs)
    bad[1] = Obs(bad[1].kind, bad[1].at, bad[1].to, bad[1].value + 0.05, bad[1].sigma)  # 5 cm on A-C
    adj = adjust(coords, ["A", "B"], bad, observed=True, angle_unit="deg")
    # the 5 cm blunder is 25 sigma: the global test fails and the largest standardised residual
    # (Baarda's w, flagged beyond 3.29) points at the blundered observation itself
    k, w = adj.worst_residual()
    assert adj.chi2_pass is False and k == 1 and abs(w) > 3.29


def test_datum_defect_is_reported():
    coords, obs = trilateration()
    with pytest.raises(InputError, match="datum defect"):
        adjust(coords, [], obs)


def test_registration_chain_is_weakest_in_the_middle():
    # 5 stations on a line between fixed control points C0 and C6, links of sigma s each way:
    # in x the chain is a 1-D adjustment of 6 equal links; point k has variance s^2 k (6 - k) / 6
    s = 0.01
    names = ["C0"] + [f"S{k}" for k in range(1, 6)] + ["C6"]
    coords = {n: (20.0 * k, 0.0) for k, n in enumerate(names)}
    obs = [
        Obs(kind, names[k], names[k + 1], 20.0 if kind == "dx" else 0.0, s) for k in range(6) for kind in ("dx", "dy")
    ]
    adj = adjust(coords, ["C0", "C6"], obs)
    sx = [adj.point(f"S{k}").sigma_x for k in range(1, 6)]
    assert sx == pytest.approx([s * math.sqrt(k * (6 - k) / 6) for k in range(1, 6)])
    assert max(sx) == sx[2]


@pytest.mark.slow
def test_monte_carlo_agrees_with_the_covariance():
    coords, obs = traverse()
    mc = monte_carlo(coords, ["A", "B"], obs, runs=300, seed=11, angle_unit="deg")
    design = adjust(coords, ["A", "B"], obs, angle_unit="deg")
    for n in ("C", "D"):
        # truncating at 3 sigma keeps 97.3 % of the variance: expect 0.986 of the a priori error;
        # with 300 runs the RMS itself scatters by about 1 / sqrt(2 * 300) = 4 %
        ratio = mc.rms[n] / design.point(n).position_error
        assert 0.86 < ratio < 1.10, (n, ratio)
    assert mc.runs == 300


def test_levelling_line_between_two_benchmarks():
    # heights along a line B0 - P1 - P2 - B3 with equal sigma s per height difference: as for the
    # chain, P_k has variance s^2 k (3 - k) / 3, so sigma(P1) = sigma(P2) = s sqrt(2/3)
    from planner.network.heights import HeightObs, adjust_heights, dh_sigma_m

    s = 0.002
    obs = [HeightObs(a, b, 0.0, s) for a, b in (("B0", "P1"), ("P1", "P2"), ("P2", "B3"))]
    res = adjust_heights({"P1": 10.0, "P2": 10.0}, {"B0": 10.0, "B3": 10.0}, obs)
    assert res.sigma_m["P1"] == pytest.approx(s * math.sqrt(2 / 3))
    assert res.sigma_m["P2"] == pytest.approx(s * math.sqrt(2 / 3))
    # a level sight of 100 m with 5": sigma_dh = 100 * 5 / 206265 = 2.42 mm
    assert dh_sigma_m(100.0, 90.0, 0.002, 5.0) == pytest.approx(100 * 5 / 206264.806, rel=1e-6)


@pytest.mark.slow
def test_monte_carlo_same_seed_same_result():
    # seeded draws: the same seed gives the same RMS per point, another seed other draws
    coords, obs = traverse()
    a = monte_carlo(coords, ["A", "B"], obs, runs=100, seed=5, angle_unit="deg")
    b = monte_carlo(coords, ["A", "B"], obs, runs=100, seed=5, angle_unit="deg")
    c = monte_carlo(coords, ["A", "B"], obs, runs=100, seed=6, angle_unit="deg")
    assert a.rms == b.rms and a.rms != c.rms
