"""The report's method comparison plans on the plan's own pool: the greedy and the closed form take the coverage the
plan was chosen from (Plan.coverage), not the site again, and their rows are those of a comparison that builds it."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

import planner.plan.run as run
from planner.engine import plan_site
from planner.plan import PlanOptions, build_problem
from planner.report import compare_methods
from planner.site import ScanSide, Site, Zone

TIMES = ("time_s",)


def _rows(rows):
    return [{k: v for k, v in r.items() if k not in TIMES} for r in rows]


@pytest.fixture(scope="module")
def plan():
    # an L-shaped room, seen inside and out: a few stations, a pool of some hundreds, pricing on
    shape = ((0, 0), (12, 0), (12, 5), (5, 5), (5, 10), (0, 10))
    zones = tuple(Zone(f"L{s.value}", s, shape, (3.0,) * 6) for s in (ScanSide.INSIDE, ScanSide.OUTSIDE))
    return plan_site(Site("ell", zones, instrument="dissertation-tables"), PlanOptions(method="milp"))


def test_the_plan_keeps_the_pool_it_was_chosen_from(plan):
    # the coverage as build_problem makes it, before pricing (which the plan's size counts after)
    assert plan.coverage is not None
    again = build_problem(plan.problem)
    assert plan.coverage.candidates == again.candidates
    assert (plan.coverage.by_candidate != again.by_candidate).nnz == 0
    assert plan.problem_size["candidates"] >= len(plan.coverage.candidates)


def test_the_comparison_builds_no_pool_beside_a_plan(plan, monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("the comparison built the candidate pool again")

    monkeypatch.setattr(run, "build_problem", refuse)
    rows = compare_methods(plan)
    assert [r["method"] for r in rows] == ["closed-form", "greedy", "milp"]
    assert all("failed" not in str(r.get("status")) for r in rows)


def test_the_rows_are_those_of_a_comparison_that_builds_the_pool(plan):
    shared = compare_methods(plan)
    built = compare_methods(replace(plan, coverage=None))  # the path of a plan that kept no coverage
    # the same closed-form and greedy rows; the plan's own row the same but for what it knows of its pool
    assert _rows(shared[:2]) == _rows(built[:2])
    assert {**shared[2], "over": ""} == {**built[2], "over": ""}


def test_each_row_says_what_its_count_is_over(plan):
    rows = {r["method"]: r for r in compare_methods(plan)}
    n = len(plan.coverage.candidates)
    assert "no candidate pool" in rows["closed-form"]["over"]
    assert f"over the candidate pool ({n:,} candidates" in rows["greedy"]["over"]
    assert "greedy" in rows["greedy"]["over"] and rows["greedy"]["connected"] is not None
    assert rows["milp"]["over"].startswith(f"milp over the candidate pool ({n:,} candidates")


@pytest.mark.slow
def test_with_floors_the_greedy_takes_the_plans_floor_columns(tmp_path, monkeypatch):
    zone = {"id": "L", "scan_side": "inside", "coordinates": [[0, 0], [12, 0], [12, 5], [5, 5], [5, 10], [0, 10]]}
    path = tmp_path / "l.json"
    path.write_text(json.dumps({"name": "lroom", "instrument": "leica-p30", "zones": [{**zone, "height_m": 3.0}]}))
    done = plan_site(str(path), PlanOptions(method="milp", surfaces=("walls", "floors")))
    assert done.surface_cover is not None and done.surfaces is not None

    def refuse(*args, **kwargs):
        raise AssertionError("the comparison built the pool or its floor columns again")

    monkeypatch.setattr(run, "build_problem", refuse)
    monkeypatch.setattr(run, "surface_cover", refuse)
    rows = {r["method"]: r for r in compare_methods(done)}
    assert rows["closed-form"]["status"].startswith("failed: ")  # the closed form plans walls only
    assert rows["greedy"]["stations"] and rows["greedy"]["verified_percent"] == 100.0


def test_the_network_check_takes_the_plans_station_coverage(plan):
    # the stations' coverage the plan's pairs were read from: the same network as one built afresh
    from planner.network.check import run_network

    st, reg = list(plan.stations), plan.problem.registration
    given = run_network(plan.problem.sight, st, registration=reg, coverage=plan.stations_cover)
    built = run_network(plan.problem.sight, st, registration=reg)
    assert given.to_dict() == built.to_dict()
    with pytest.raises(ValueError, match="rows for"):
        run_network(plan.problem.sight, st[:-1], registration=reg, coverage=plan.stations_cover)
