"""Tripod discs contain their stations, stop at a stated resolution, carry the height tolerance (3.32);
a solver that finds no plan exits 4 with the reason."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from planner.cli import main
from planner.coverage.targets import make_targets
from planner.engine import plan_site
from planner.io import load_site
from planner.plan import PlanOptions
from planner.plan.tripod import MIN_RADIUS_M
from planner.site import ScanSide
from planner.site.model import Site, Zone
from tests.conftest import INSTANCES, square_rows


@pytest.mark.slow
def test_every_tripod_disc_contains_its_station_and_recentring_moves_them():
    site = load_site(INSTANCES / "polygon_b.json")
    plain = plan_site(site, PlanOptions(method="greedy", tripod=True))
    moved = plan_site(site, PlanOptions(method="greedy", tripod=True, recentre=True))
    for plan in (plain, moved):
        assert plan.verification.complete and len(plan.tripods) == len(plan.stations)
        for s, d in zip(plan.stations, plan.tripods):
            assert d.station == s.id and math.dist(s.xy, d.centre) <= d.radius_m + 1e-9
            assert d.radius_m == 0.0 or d.radius_m >= MIN_RADIUS_M
    # by default the disc is centred on the planned station; recentred (same plan: same stations, same
    # order), each station stands at the centre of the largest disc found anywhere (the SOCP), and at least
    # one of them moves, i.e. the two modes differ
    assert [s.id for s in plain.stations] == [s.id for s in moved.stations]
    for plan in (plain, moved):
        assert all(s.xy == pytest.approx(d.centre) for s, d in zip(plan.stations, plan.tripods))
    assert max(math.dist(p0.xy, s.xy) for p0, s in zip(plain.stations, moved.stations)) > 0.1
    assert "(centred on the planned stations)" in plain.summary() and "(stations recentred)" in moved.summary()


def test_height_tolerance_is_the_dissertation_check_value():
    # a 30 x 30 m room with 40 m walls, S_max = 96 m, tripod IH 0..0.4 m: (3.32) gives
    # 96/2 * [sqrt(1 - (39.6/96)^2) - sqrt(1 - (40/96)^2)] = 48 * (0.910961 - 0.909059) = 0.091 m (docs/method.md)
    z = Zone("T", ScanSide.INSIDE, ((0, 0), (30, 0), (30, 30), (0, 30)), (40.0,) * 4)
    site = Site("temple", (z,), instrument="dissertation-tables")
    site = replace(site, parameters=replace(site.parameters, max_slant_range_m=96.0))
    plan = plan_site(site, PlanOptions(method="greedy", tripod=True))
    assert plan.tripods and all(d.height_tolerance_m == pytest.approx(0.091, abs=5e-4) for d in plan.tripods)
    assert "instrument-height tolerance (3.32, IH 0..0.4 m)" in plan.summary()


def test_a_milp_with_no_plan_exits_4_with_the_reason(write_csv, capsys):
    # no piece of a 10 x 10 m room is seen by 400 candidates: the MILP stops before solving and counts them all.
    # Its four 10-m walls in equal pieces of at most 1 m are 4 x 10 = 40 pieces (polygon B's 770 told the same at
    # ten times the cost)
    path = write_csv(square_rows())
    assert len(make_targets(load_site(path), 1.0)) == 40
    code = main(["plan", str(path), "--method", "milp", "--k", "400", "--quiet"])
    err = capsys.readouterr().err
    assert code == 4
    assert "milp found no plan: 40 target(s) seen by fewer than k = 400 candidates" in err


def test_recentring_disc_reads_no_uninitialised_memory(monkeypatch):
    # cvxpy's cp.sum(..., axis=1) checks its shape by summing np.empty(shape), whose bytes may be inf and -inf
    # (numpy then warns "invalid value encountered in reduce"). With every np.empty holding inf and -inf the SOCP
    # disc must still build and solve without a warning. Square room 10 m, station at its centre (5, 5), walls'
    # ends at distance 5..7.07 m: the disc is positive and its centre stays in the room.
    import warnings

    import numpy as np

    from planner.plan.tripod import _socp_disc

    real_empty = np.empty

    def poisoned(shape, *args, **kwargs):
        out = real_empty(shape, *args, **kwargs)
        if out.dtype.kind == "f" and out.size:
            out.reshape(-1)[::2], out.reshape(-1)[1::2] = np.inf, -np.inf
        return out

    monkeypatch.setattr(np, "empty", poisoned)
    ends = np.array([[0, 0], [10, 0], [10, 0], [10, 10], [10, 10], [0, 10], [0, 10], [0, 0]], dtype=float)
    normals = np.array([[0, 1], [0, 1], [-1, 0], [-1, 0], [0, -1], [0, -1], [1, 0], [1, 0]], dtype=float)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        centre, radius = _socp_disc(np.array([5.0, 5.0]), ends, normals, np.full(8, 50.0), 70.0)
    assert 0 < radius and 0 < centre[0] < 10 and 0 < centre[1] < 10
