"""Optimal plans on the bundled instances: backends agree, plans verify and are connected."""

from __future__ import annotations

import json
import math

import pytest

from planner.cli import main
from planner.coverage.overlap import OverlapRule
from planner.coverage.relation import Registration
from planner.coverage.sight import Sight
from planner.engine import plan_site
from planner.io import load_site
from planner.plan import PlanOptions, build_problem
from planner.plan.tripod import tripod_discs
from planner.plan.verify import verify_stations
from planner.site import ScanSide, Site, Zone
from planner.solve.backends import BACKENDS
from planner.solve.greedy import connected_greedy_plan, greedy_cover
from planner.solve.instance import cover_instance
from planner.solve.milp import MilpOptions, solve
from tests.conftest import INSTANCES

NAMES = ("polygon_a", "polygon_b", "polygon_c", "baalbek")


class _Problems(dict):
    """An instance's site and planning problem, built when a test first reads them (the quick tier reads B only)."""

    def __missing__(self, n: str) -> tuple:
        self[n] = (load_site(INSTANCES / f"{n}.json"), build_problem(load_site(INSTANCES / f"{n}.json"), PlanOptions()))
        return self[n]


@pytest.fixture(scope="module")
def problems():
    return _Problems()


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n != "polygon_b" else n for n in NAMES])
def test_plain_cover_backends_agree_and_beat_greedy(problems, name):
    site, problem = problems[name]
    inst = cover_instance(problem)
    results = {b: solve(inst, MilpOptions(backend=b, overlap=None, time_limit_s=60)) for b in BACKENDS}
    assert {r.status.value for r in results.values()} == {"optimal"}
    assert len({r.objective for r in results.values()}) == 1
    best = results["cpsat"]
    assert greedy_cover(problem.by_candidate).objective >= best.objective
    assert (inst.coverage_count(best.selected) >= 1).all()


def registration_check(site, problem, selected):
    """Each zone-side's components of ``selected`` under a 30 % rule, checked afresh with networkx."""
    return Registration.of(Sight.of_site(site), "zone", OverlapRule(0.3)).check(problem, selected)


@pytest.fixture(scope="module")
def polygon_b_connected(problems):
    """Polygon B's connected optimum by CP-SAT, the reference every backend must meet."""
    site, problem = problems["polygon_b"]
    return solve(cover_instance(problem), MilpOptions(backend="cpsat"))


@pytest.fixture(scope="module")
def polygon_b_plain(problems):
    """Polygon B's plain cover optimum by CP-SAT (no overlap rule), solved once for the module."""
    return solve(cover_instance(problems["polygon_b"][1]), MilpOptions(backend="cpsat", overlap=None))


@pytest.fixture(scope="module")
def polygon_b_greedy_connected(problems):
    """Polygon B's connected greedy plan under a 30 % rule (the MILP's warm start), made once for the module."""
    return connected_greedy_plan(cover_instance(problems["polygon_b"][1]), OverlapRule(0.3))


@pytest.mark.parametrize("backend", BACKENDS)
def test_connected_plan_of_polygon_b_on_every_backend(
    problems, polygon_b_connected, polygon_b_plain, polygon_b_greedy_connected, backend
):
    site, problem = problems["polygon_b"]
    r = solve(cover_instance(problem), MilpOptions(backend=backend))
    assert r.status.value == polygon_b_connected.status.value == "optimal"
    comps, _ = registration_check(site, problem, r.selected)
    assert set(comps.values()) == {1}  # each zone-side one registration bundle, checked with networkx
    stations = [problem.candidates[i] for i in r.selected]
    assert verify_stations(Sight.of_site(site), stations).complete
    # every backend proves the same optimum, between the plain cover's optimum (a connected plan is a
    # cover) and the connected greedy (a connected plan; the MILP's warm start)
    assert r.objective == polygon_b_connected.objective
    assert polygon_b_plain.objective <= r.objective <= polygon_b_greedy_connected.objective


@pytest.fixture(scope="module")
def baalbek_connected_optimum(problems):
    """CP-SAT proves Baalbek's connected optimum in seconds: the reference the other backend must meet."""
    site, problem = problems["baalbek"]
    r = solve(cover_instance(problem), MilpOptions(backend="cpsat", time_limit_s=300))
    plain = solve(cover_instance(problem), MilpOptions(backend="cpsat", overlap=None, time_limit_s=300))
    assert r.status.value == "optimal" and plain.status.value == "optimal"
    return r.objective, plain.objective


@pytest.mark.slow
@pytest.mark.parametrize("backend", ["cpsat", "scip"])
def test_connected_plan_of_baalbek(problems, baalbek_connected_optimum, backend):
    site, problem = problems["baalbek"]
    connected, plain = baalbek_connected_optimum
    assert connected >= plain  # a connected plan is a cover
    # SCIP's cut loop re-solves each round (~40 s unloaded here): where it proves, it must agree; where its
    # time runs out, its plan must still be connected and no better than the proven optimum
    r = solve(cover_instance(problem), MilpOptions(backend=backend, time_limit_s=120))
    assert r.objective == connected if r.status.value == "optimal" else r.objective >= connected
    comps, _ = registration_check(site, problem, r.selected)
    assert set(comps.values()) == {1} and len(comps) == 12


@pytest.mark.slow
def test_same_seed_same_milp_plan():
    site = load_site(INSTANCES / "polygon_b.json")
    opts = PlanOptions(method="milp", milp=MilpOptions(seed=3))
    a, b = plan_site(site, opts), plan_site(site, opts)
    assert [s.id for s in a.stations] == [s.id for s in b.stations] and a.connected and a.verification.complete


def test_tripod_disc_in_a_square_room():
    # one station at the centre of a 20 x 20 room relies on it for every wall. Wall y = 0, end (0, 0):
    # (|p - e| + r) cos 68 + r <= p_y  ->  r <= (10 - 14.142 cos 68) / (1 + cos 68) = 3.421 m
    z = Zone("R", ScanSide.INSIDE, ((0, 0), (20, 0), (20, 20), (0, 20)), (3.0,) * 4)
    site = Site("room", (z,), instrument="dissertation-tables")
    problem = build_problem(site, PlanOptions())
    centre = next(i for i, c in enumerate(problem.candidates) if abs(c.x - 10) < 1e-6 and abs(c.y - 10) < 1e-6)
    (disc,) = tripod_discs(site, problem, [centre], problem.limits)
    c68 = math.cos(math.radians(68))
    assert disc.radius_m == pytest.approx((10 - math.hypot(10, 10) * c68) / (1 + c68), abs=2e-3)
    assert disc.centre == pytest.approx((10.0, 10.0), abs=1e-3)


@pytest.mark.slow
def test_cli_milp_plan_json(tmp_path, capsys):
    out = tmp_path / "b"
    assert main(["plan", str(INSTANCES / "polygon_b.json"), "--method", "milp", "--out", str(out), "--recentre"]) == 0
    data = json.loads((out / "plan.json").read_text())
    # pricing only adds candidates to the pool of test_connected_plan_of_polygon_b (optimum 7 there), so the
    # connected optimum over the priced pool is at most 7, and the plane bound (connectivity ignored) is below it;
    # the connected plane bound (1 inside + the outside ring walk over patches, 5) meets the plan: scope plane
    assert data["status"] == "optimal" and data["objective"] == data["bound"] <= 7 and data["gap"] == 0
    assert data["plane_bound"] == 5 < data["objective"] == data["connected_plane_bound"] == 6
    assert data["bound_scope"] == "plane" and data["pool_bound"] == 6
    assert data["backend"] == "cpsat" and data["presolve"]["candidates_in"] > data["presolve"]["candidates_out"]
    assert data["registration"]["connected"] and all("tripod_radius_m" in s for s in data["stations"])
    # recentred stations stand at their disc centres and still verify
    assert all(s["x"] == s["tripod_centre"][0] for s in data["stations"])
    assert data["verification"]["complete"]


def test_export_orlib_roundtrip(polygon_b_plain, tmp_path, capsys):
    from planner.solve.orlib import read_orlib

    assert (
        main(["export", str(INSTANCES / "polygon_b.json"), "--format", "orlib", "--out", str(tmp_path / "b.txt")]) == 0
    )
    inst = read_orlib(tmp_path / "b.txt")
    # the plain optimum of the same build (made once for the module), by the same solver
    assert solve(inst, MilpOptions(overlap=None)).objective == polygon_b_plain.objective
