"""One registration per run (issue 54): :func:`planner.plan.problem.resolve` decides it once
(:class:`planner.coverage.relation.Registration`), and the plan, the field sheet, the network check and the
report's map all relate the same pairs of stations."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from planner.engine import plan_site
from planner.field.run import FieldOptions, field_plan
from planner.io import load_site
from planner.network.check import run_network
from planner.plan.options import PlanOptions
from planner.plan.outcome import outcome_from_plan
from planner.plan.plan_dict import plan_to_dict
from planner.plan.problem import recorded_problem
from planner.report.site_map import outcome_site_map
from planner.site import ScanSide, Site, Zone
from planner.site.model import Opening
from tests.conftest import INSTANCES, package_calls

ROOT = Path(__file__).resolve().parents[2]
#: the calls that decide a registration, and the modules allowed to make them: the definitions and the home
DECIDERS = {"default_registration", "registration_groups", "rule_of", "planning_rule"}
HOMES = {
    "planner/plan/problem.py",
    "planner/coverage/relation.py",
    "planner/coverage/links.py",
    "planner/coverage/overlap.py",
}
#: the sheet's routing kept small: only its relation is compared
QUICK = FieldOptions(solution_limit=50, node_limit=200)


def _pairs(pairs) -> list[tuple[str, str]]:
    return sorted(tuple(sorted(p)) for p in pairs)


def _everywhere(plan) -> dict[str, list[tuple[str, str]]]:
    """The pairs each consumer relates: the plan's registration, the field sheet, the network check, the map."""
    problem, stations = plan.problem, plan.stations
    g = problem.registration.relation(stations, problem.sight.of_stations(stations))
    fp = field_plan(problem, stations, QUICK)
    network = run_network(problem.sight, list(stations), registration=problem.registration)
    links = outcome_site_map(outcome_from_plan(plan)).links
    return {
        "plan": _pairs((stations[u].id, stations[v].id) for u, v in g.edges()),
        "field": _pairs(fp.pairs),
        "network": _pairs(network.survey.links),
        "map": _pairs((lk.a, lk.b) for lk in links),
    }


@pytest.fixture(scope="module")
def house_zone():
    return plan_site(load_site(INSTANCES / "house_doors.json"), PlanOptions(registration="zone"))


def test_house_doors_zone_every_consumer_relates_the_plans_pairs(house_zone):
    # the site's default is `site` (openings given); under `zone` every consumer relates the plan's own pairs
    got = _everywhere(house_zone)
    assert house_zone.problem.registration.mode == "zone"
    assert len(got["plan"]) == 2
    assert got["field"] == got["network"] == got["map"] == got["plan"]


def test_a_plan_file_rebuilds_the_plans_registration(house_zone):
    meta = plan_to_dict(house_zone)
    again = recorded_problem(house_zone.site, meta)
    assert again.registration == house_zone.problem.registration
    assert meta["resolved"]["registration"] == "zone" and "adjustments" in meta["resolved"]


def _rooms(widths: list[float], doors: list[float]) -> Site:
    """Rooms 4 m deep in a row along x, each with a door 1 m wide in its right wall at ``doors[k]``."""
    zones, x = [], 0.0
    for k, w in enumerate(widths):
        last = k == len(widths) - 1
        openings = () if last else (Opening(2, doors[k], doors[k] + 1.0, "door", f"d{k}"),)
        outline = ((x, 0.0), (x + w, 0.0), (x + w, 4.0), (x, 4.0))
        zones.append(Zone(f"R{k}", ScanSide.INSIDE, outline, (3.0,) * 4, openings=openings))
        x += w
    return Site("rooms", tuple(zones), instrument="dissertation-tables")


@pytest.mark.slow
@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    widths=st.lists(st.sampled_from([3.0, 4.0, 5.0, 6.0]), min_size=2, max_size=3),
    doors=st.lists(st.sampled_from([0.5, 1.5, 2.5]), min_size=2, max_size=2),
    mode=st.sampled_from(["zone", "site"]),
)
def test_every_consumer_relates_the_plans_pairs_on_small_sites(widths, doors, mode):
    plan = plan_site(_rooms(widths, doors), PlanOptions(method="greedy", registration=mode))
    got = _everywhere(plan)
    assert got["field"] == got["network"] == got["map"] == got["plan"]


def test_registration_is_decided_only_where_the_problem_is_resolved():
    # every call of the package (parsed once per session: tests/conftest.py)
    calls = [f"{rel}:{line} {name}" for rel, line, name in package_calls() if name in DECIDERS and rel not in HOMES]
    assert calls == []
