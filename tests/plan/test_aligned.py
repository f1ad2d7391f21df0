"""A plan at the plane bound linked through openings (planner/plan/aligned.py): found, or left to the whole pool."""

from __future__ import annotations

import json

import pytest

from planner.engine import plan_site
from planner.io.load import load_site
from tests.conftest import INSTANCES, ROOT

DATA = ROOT / "tests" / "data"


def _two_rooms(tmp_path, door: tuple[float, float]):
    """tests/data/two_rooms_door.json with its door at ``door`` (s0, s1) metres up the wall between the rooms. One
    station sees a whole 10 x 6 m room only within about 2 m of its middle line (y 2.02..3.98 m: the far ends of the
    long walls within 68 deg), so the two rooms' stations see each other through a door that reaches that band
    (1.8..2.8 m: two stations) and not through one below it (0.5..1.5 m: three)."""
    site = json.loads((DATA / "two_rooms_door.json").read_text())
    site["openings"][0].update(s0_m=door[0], s1_m=door[1])
    path = tmp_path / "two.json"
    path.write_text(json.dumps(site))
    return load_site(path)


def _line(plan) -> str:
    return next(line for line in plan.log if line.startswith("aligned through openings"))


def test_two_rooms_seen_through_the_door_at_the_plane_bound(tmp_path):
    plan = plan_site(_two_rooms(tmp_path, (1.8, 2.8)))
    assert len(plan.stations) == 2
    assert plan.result.info["bound_scope"] == "plane" and plan.result.info["plane_bound"] == 2
    assert plan.connected and plan.verification.percent == pytest.approx(100.0)
    assert "a registered plan of 2 among them" in _line(plan)
    r1, r2 = sorted(plan.stations, key=lambda s: s.zone)
    assert (r1.zone, r2.zone) == ("R1", "R2")
    # their sight line crosses the wall x = 10 within the door
    y = r1.y + (r2.y - r1.y) * (10.0 - r1.x) / (r2.x - r1.x)
    assert 1.8 <= y <= 2.8


def test_a_door_no_pair_of_whole_room_stations_sees_through_leaves_the_pool_to_plan(tmp_path):
    plan = plan_site(_two_rooms(tmp_path, (0.5, 1.5)))
    assert "so the whole pool is solved" in _line(plan)
    assert len(plan.stations) == 3 and plan.connected
    assert plan.result.info["bound_scope"] == "pool"


def test_not_tried_without_openings():
    plan = plan_site(INSTANCES / "polygon_b.json")
    assert not any(line.startswith("aligned through openings") for line in plan.log)


@pytest.mark.slow
def test_the_temple_with_its_doors_at_its_plane_bound():
    # 22 stations over the pool before (bound 21), 20 over a plane bound of 20 now: 13 inside, 7 outside
    plan = plan_site(INSTANCES / "baalbek_site_doors.json")
    assert len(plan.stations) == 20 and plan.count_by_side() == {"inside": 13, "outside": 7}
    assert plan.result.info["bound_scope"] == "plane" and plan.connected
    assert plan.verification.percent == pytest.approx(100.0)
