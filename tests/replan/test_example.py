"""The shipped example (instances/baalbek_site_doors.edits.json) under the issue's "done when": after `planner plan
instances/baalbek_site_doors.json --out DIR --field DIR`, `planner replan DIR/plan.json EDITS --out DIR2` keeps the
5 done stations, places no station within the blocked radii or in the closed zone Z5, verifies every wall still
reachable, lists Z5's walls as lost with their length, keeps one registration network with the done stations and
writes a field sheet that starts at station 5 (the crew's); it is no larger than a fresh plan of the same constrained
problem (tests/replan/fresh.py), its bound no higher. Plans the site first (about a minute): heavy."""

from __future__ import annotations

import json
import math

import pytest
import shapely

import planner
from planner.cli.main import main
from planner.io.edits import MIN_BLOCKED_RADIUS_M
from tests.conftest import INSTANCES
from tests.replan.fresh import fresh_rest_count

pytestmark = [pytest.mark.slow, pytest.mark.heavy]

EDITS = INSTANCES / "baalbek_site_doors.edits.json"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    d = tmp_path_factory.mktemp("baalbek")
    plan = d / "plan"
    site = str(INSTANCES / "baalbek_site_doors.json")
    assert main(["plan", site, "--out", str(plan), "--field", str(plan), "--quiet"]) == 0
    assert (plan / "replan.npz").is_file()
    assert main(["replan", str(plan / "plan.json"), str(EDITS), "--out", str(d / "re"), "--quiet"]) == 0
    old = json.loads((plan / "plan.json").read_text())
    new = json.loads((d / "re" / "plan.json").read_text())
    return old, new, planner.replan(plan / "plan.json", EDITS)


def test_keeps_the_five_done_stations(run):
    old, new, r = run
    first = {s["number"]: s for s in old["stations"] if s["number"] <= 5}
    assert [s.id for s in r.done] == [first[n]["id"] for n in range(1, 6)]
    at = {s["id"]: (s["x"], s["y"]) for s in new["stations"]}
    assert all(at[first[n]["id"]] == (first[n]["x"], first[n]["y"]) for n in range(1, 6))
    assert new["replan"]["done"] == [first[n]["id"] for n in range(1, 6)]


def test_nothing_within_the_blocked_radii_nor_in_the_closed_zone(run):
    old, _, r = run
    edits = json.loads(EDITS.read_text())
    by_number = {s["number"]: s for s in old["stations"]}
    zone = r.source.site.zone("Z5").polygon
    for e in (e for e in edits["stations"] if e["status"] == "blocked"):
        s = by_number[e["station"]]
        radius = e.get("radius_m", max(s["tripod_radius_m"], MIN_BLOCKED_RADIUS_M))
        assert all(math.dist(x.xy, (s["x"], s["y"])) > radius for x in r.new)
    assert not any(zone.intersects(shapely.Point(x.xy)) for x in r.new)


def test_verified_lost_walls_listed_one_network_sheet_from_station_five(run):
    old, new, r = run
    assert r.unexpected_gaps_m == 0.0 and new["replan"]["reachable_uncovered_m"] == 0
    lost = new["replan"]["walls_lost"]
    assert set(lost["by_zone"]) == {"Z5/inside"} and lost["by_zone"]["Z5/inside"] > 30.0
    assert {g.zone for g in r.verification.gaps} == {"Z5"}
    assert r.connected and new["replan"]["one_network"]
    five = next(s for s in old["stations"] if s["number"] == 5)
    assert r.sheet is not None and r.sheet.start_xy == (five["x"], five["y"])
    assert new["replan"]["start"]["xy"] == [five["x"], five["y"]]
    assert r.solution.rest_bound is not None and r.solution.rest_bound <= r.solution.rest_count


def test_no_larger_than_a_fresh_plan_of_the_same_constrained_problem(run):
    # measured: the re-plan 18 to go (bound 15), the fresh plan 19
    _, _, r = run
    fresh = fresh_rest_count(r)
    assert r.solution.rest_count <= fresh and r.solution.rest_bound <= fresh
