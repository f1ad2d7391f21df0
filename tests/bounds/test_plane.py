"""Optimal over every position in the plane: whole-zone-side candidates and geometric pricing.

A w x h rectangle (w >= h) is covered from its middle exactly when w / h <= tan(theta_max); with theta_max = 68 deg, tan
= 2.475, so aspects 1, 2 and 2.4 need one station and 2.6 and 4 need two (for 2.6 no single position sees both short
walls' far corners within 68 deg). A comb with k teeth (theta_max 89 deg, range unlimited) needs k: the far wall of each
tooth is seen only from inside it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.engine import plan_site
from planner.io.load import load_site
from planner.plan import PlanOptions
from planner.site.model import ScanSide, Site, Zone
from planner.site.params import Parameters
from planner.solve.milp import MilpOptions
from planner.solve.pricing import cover_lp
from tests.conftest import INSTANCES

UNLIMITED = dict(max_slant_range_m=1e4, overlap=0.0)
PLAIN_MILP = PlanOptions(method="milp", precision=False, milp=MilpOptions(overlap=None))


def rectangle(aspect: float, angle_deg: float = 0.0, shift: tuple[float, float] = (0.0, 0.0)) -> Site:
    h = 4.0
    xy = np.array([(0, 0), (aspect * h, 0), (aspect * h, h), (0, h)], float)
    c, s = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))
    xy = xy @ np.array([[c, s], [-s, c]]) + shift
    zone = Zone("R", ScanSide.INSIDE, tuple(map(tuple, xy)), (4.2,) * 4)
    return Site(f"rect {aspect}", (zone,), parameters=Parameters(theta_max_deg=68.0, **UNLIMITED))


def comb(k: int, tooth_m: float = 1.0, gap_m: float = 1.5, depth_m: float = 4.0, base_m: float = 2.0) -> Site:
    right = k * tooth_m + (k - 1) * gap_m
    poly = [(0.0, 0.0), (right, 0.0)]
    for i in reversed(range(k)):
        x0 = i * (tooth_m + gap_m)
        poly += [(x0 + tooth_m, base_m), (x0 + tooth_m, base_m + depth_m), (x0, base_m + depth_m), (x0, base_m)]
    poly = list(dict.fromkeys(poly))
    return Site(
        f"comb {k}",
        (Zone("C", ScanSide.INSIDE, tuple(poly), (3.0,) * len(poly)),),
        parameters=Parameters(theta_max_deg=89.0, **UNLIMITED),
    )


@pytest.mark.parametrize(("aspect", "stations"), [(1.0, 1), (2.0, 1), (2.4, 1), (2.6, 2), (4.0, 2)])
def test_rectangles_are_proven_over_the_plane(aspect: float, stations: int) -> None:
    plan = plan_site(rectangle(aspect), PLAIN_MILP)
    info = plan.result.info
    assert len(plan.stations) == stations
    assert plan.result.status.value == "optimal"
    assert info["bound_scope"] == "plane" and info["plane_bound"] == stations
    assert info["pricing"]["converged"] and info["pricing"]["plane_bound"] == stations
    assert plan.verification.percent == pytest.approx(100.0)


def test_rotation_and_translation_change_nothing() -> None:
    a = plan_site(rectangle(2.6), PLAIN_MILP)
    b = plan_site(rectangle(2.6, angle_deg=37.0, shift=(512.3, -88.1)), PLAIN_MILP)
    assert (len(a.stations), a.result.info["bound_scope"]) == (len(b.stations), b.result.info["bound_scope"])


@pytest.mark.parametrize("k", [2, 3, pytest.param(5, marks=pytest.mark.slow)])
def test_comb_needs_one_station_per_tooth(k: int) -> None:
    plan = plan_site(comb(k), PLAIN_MILP)
    assert len(plan.stations) == k
    assert plan.result.info["bound_scope"] == "plane"
    assert plan.verification.percent == pytest.approx(100.0)


def test_lp_duals_are_feasible_and_tight() -> None:
    """Three pieces, candidates {0,1}, {1,2}, {0,2}: LP x = 1/2 each, value 3/2 = sum of duals (1/2 each)."""
    import scipy.sparse as sp

    by_target = sp.csr_matrix(np.array([[1, 0, 1], [1, 1, 0], [0, 1, 1]], dtype=bool))
    lp = cover_lp(by_target)
    assert lp.value == pytest.approx(1.5)
    assert lp.y.sum() == pytest.approx(1.5)
    assert np.all(by_target.T.astype(float) @ lp.y <= 1 + 1e-9)  # dual feasible: no column prices out


@pytest.mark.slow
def test_building_gets_one_station_per_room_that_allows_it() -> None:
    """building27: every room with aspect <= 2.4 (< tan 68 deg = 2.475, margin for the 1 m pieces) gets exactly one
    station; rooms above 2.6 get two. Never more stations than the pool without regions."""
    site = load_site(INSTANCES / "building27.json")
    options = PlanOptions(method="milp", milp=MilpOptions(overlap=None))
    plan = plan_site(site, options)
    old = plan_site(site, PlanOptions(method="milp", regions=False, pricing=False, milp=MilpOptions(overlap=None)))
    per_zone: dict[str, int] = {}
    for s in plan.stations:
        per_zone[s.zone] = per_zone.get(s.zone, 0) + 1
    checked, twos = 0, 0
    for zone in site.zones:
        if zone.scan_side is not ScanSide.INSIDE:
            continue
        w, h = np.ptp(zone.xy, axis=0)
        aspect = max(w / h, h / w)
        if aspect <= 2.4:
            assert per_zone.get(zone.id) == 1, zone.id
            checked += 1
        elif aspect >= 2.6:
            assert per_zone.get(zone.id) == 2, zone.id
            twos += 1
    # building27's inside rooms (scripts/make/make_building.py): 22 of aspect <= 2.4, 2 of >= 2.6, and 3 between 2.4 and
    # 2.6, where 1 m pieces may or may not let one station do (not checked)
    assert (checked, twos) == (22, 2)
    assert len(plan.stations) <= len(old.stations)
    assert plan.result.info["bound_scope"] == "plane"
    assert plan.verification.percent == pytest.approx(100.0)


def test_same_seed_same_plan() -> None:
    site = comb(3)
    a, b = plan_site(site, PLAIN_MILP), plan_site(site, PLAIN_MILP)
    assert [(s.x, s.y) for s in a.stations] == [(s.x, s.y) for s in b.stations]
    assert a.result.info["pricing"]["columns_added"] == b.result.info["pricing"]["columns_added"]
