"""The field sheet (issue 35): walking distances, order and bound, time, targets, the files, bad input."""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest
import shapely

from planner.cli import main
from planner.core.errors import InfeasibleError, InputError, UsageError
from planner.field.bound import exact_order, held_karp_bound
from planner.field.order import registration_violations, solve_order
from planner.field.run import FieldOptions, field_plan
from planner.field.sheet import write_sheet
from planner.field.timing import field_time, parse_duration
from planner.field.walking import walk_graph, walk_space
from planner.instrument.field_table import FieldProperties
from planner.io import load_site
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide
from tests.conftest import INSTANCES

ROOMS = {"R1": (5.0, 4.0), "R2": (15.0, 4.0), "R3": (25.0, 4.0)}


def _station(sid: str, zone: str, side: str, x: float, y: float) -> Candidate:
    return Candidate(sid, zone, ScanSide(side), "site", x, y, CandidateKind.GRID)


@pytest.fixture(scope="module")
def house():
    return load_site(INSTANCES / "house_doors.json")


def _house_stations() -> list[Candidate]:
    out = [_station(f"S{z}", z, "inside", *xy) for z, xy in ROOMS.items()]
    return out + [_station("Sfront", "house", "outside", 5.0, -5.0), _station("Sback", "house", "outside", 25.0, 13.0)]


def test_walk_through_doors_not_walls(house):
    # R1 (5, 4) to R2 (15, 4) through the door R1-R2 on x = 10, y 3..4.5: the straight line y = 4 passes
    # through the door, so the walk is 10 m (less the 0.05 m wall clearance keeps it straight)
    space = walk_space(house, "site")
    g = walk_graph(space, [ROOMS["R1"], ROOMS["R2"], (5.0, -5.0)])
    assert g.dist[0, 1] == pytest.approx(10.0, abs=1e-6)
    # R1 (5, 4) to the front (5, -5) through the front door, x 4..5.5 on y = 0: straight down, 9 m
    assert g.dist[0, 2] == pytest.approx(9.0, abs=1e-6)
    # R2 to the front: R2 has no outside door; via door R1-R2 (x = 10, y <= 4.5) and the front door
    assert g.dist[1, 2] > math.dist(ROOMS["R2"], (5.0, -5.0)) + 1.0


def test_every_leg_stays_off_the_walls(house):
    fp = field_plan(house, _house_stations(), FieldOptions(mode="shortest"))
    walls = shapely.MultiLineString([list(w) for w in fp.space.solid_walls])
    for leg in fp.legs:
        if len(leg) > 1:
            line = shapely.LineString(leg)
            assert not line.intersects(walls), leg
    # the route's legs add up to the route length
    total = sum(math.dist(p, q) for leg in fp.legs for p, q in itertools.pairwise(leg))
    assert total == pytest.approx(fp.route_length_m, rel=1e-6)


def test_plant_route_avoids_obstacles_and_walls():
    site = load_site(INSTANCES / "plant_1ha.json")
    pts = [(0.0, 0.0), (50.0, 3.0), (99.0, 50.0), (50.0, 97.0), (2.0, 60.0)]
    space = walk_space(site, "site")
    pts = [p for p in pts if space.contains(p)]
    g = walk_graph(space, pts)
    walls = shapely.MultiLineString([list(w) for w in space.solid_walls])
    for i in range(len(pts)):
        for j in range(i + 1, len(pts)):
            line = shapely.LineString(g.path(i, j))
            assert not line.intersects(walls)
            assert line.intersection(space.blocked).length < 1e-6


def test_bound_matches_exact_on_small_instances():
    rng = np.random.default_rng(7)
    for closed in (False, True):
        p = rng.uniform(0, 50, (9, 2))
        d = np.hypot(*(p[:, None] - p[None]).transpose(2, 0, 1))
        best, order = exact_order(d, closed)
        assert order[0] == 0 and sorted(order) == list(range(9))
        lb = held_karp_bound(d, best * 1.1, closed)
        assert lb <= best + 1e-6
        assert lb >= 0.9 * best  # the 1-tree bound is tight on small Euclidean instances
        r = solve_order(d, closed=closed)
        assert r.length_m == pytest.approx(best, rel=1e-6)  # guided local search finds the optimum here


def test_open_path_on_a_line():
    # points at 0, 1, 2, 3, 10 on a line from node 0 at 0: the shortest open path is 10 m, the tour 20 m
    x = np.array([0.0, 3.0, 1.0, 10.0, 2.0])
    d = np.abs(x[:, None] - x[None])
    assert exact_order(d)[0] == pytest.approx(10.0)
    assert exact_order(d, True)[0] == pytest.approx(20.0)
    assert held_karp_bound(d, 10.0) == pytest.approx(10.0, abs=1e-6)


def test_registration_order_is_honoured():
    # a line of 5 nodes, each related only to its neighbours; start at node 2 (the middle): a registration
    # order must grow from 2 outwards; the shortest goes 2 -> 1 -> 0 -> 3 -> 4 either way
    x = np.array([2.0, 1.0, 0.0, 3.0, 4.0])  # node k at x[k]; the start (node 0) at 2
    d = np.abs(x[:, None] - x[None])
    nbrs = [{1, 3}, {0, 2}, {1}, {0, 4}, {3}]
    r = solve_order(d, "registration", nbrs, [0] * 5, True)
    assert not registration_violations(r.order, nbrs, [0] * 5, True)
    assert r.length_m == pytest.approx(1 + 1 + 3 + 1)  # 2->1->0 (2 m), back to 3 (3 m), 4 (1 m) = 6 m
    assert registration_violations((0, 2, 1, 3, 4), nbrs, [0] * 5, True) == [2]


def test_field_time_and_sessions():
    props = FieldProperties(
        setup_time_s=100,
        walking_speed_m_s=1.0,
        scan_times_s=(("a", 200.0),),
        default_setting="a",
        target_scan_time_s=10,
    )
    t = field_time(["A", "B", "C"], [0.0, 50.0, 100.0], [0, 2, 1], props, session_s=parse_duration("10min"))
    # A: 0 + 100 + 200 = 300 s; B: 50 + 300 + 20 = 370 s; C: 100 + 300 + 10 = 410 s; total 1080 s
    assert [s.total_s for s in t.setups] == [300.0, 370.0, 410.0]
    assert t.total_s == 1080.0
    # sessions of 600 s: A (300) + B (370) = 670 > 600, so B opens session 2; B + C = 780 > 600: C opens 3
    assert [s.setups for s in t.sessions] == [(1,), (2,), (3,)]
    assert parse_duration("1h30min") == 5400.0 and parse_duration("4") == 14400.0
    with pytest.raises(UsageError):
        parse_duration("4 hours")
    with pytest.raises(UsageError):
        field_time(["A"], [0.0], [0], props, session_s=60.0)


def test_targets_across_doors(house):
    fp = field_plan(house, _house_stations(), FieldOptions(mode="registration"))
    assert fp.registration_ok
    # room stations share no wall with each other: their links (through the doors) are weak and get 3 targets
    inner = [lk for lk in fp.links if lk.a.startswith("SR") and lk.b.startswith("SR")]
    assert inner and all(lk.fraction == 0.0 and len(lk.targets) >= 3 and not lk.weak for lk in inner)
    by_id = {t.id: t for t in fp.targets}
    for lk in inner:
        for tid in lk.targets:
            assert {lk.a, lk.b} <= set(by_id[tid].seen_by)


def test_sheet_files(house, tmp_path):
    fp = field_plan(house, _house_stations(), FieldOptions(session_s=1800.0))
    paths = write_sheet(fp, tmp_path)
    data = json.loads((tmp_path / "field.json").read_text())
    for key in ("order", "route_length_m", "lower_bound_m", "gap", "mode", "field_time_s", "sessions", "targets"):
        assert key in data
    assert sorted(data["order"]) == sorted(s.id for s in _house_stations())
    assert data["gap"] == pytest.approx(0.0, abs=1e-9)  # 5 stations: the bound is the exact optimum
    rows = (tmp_path / "field.csv").read_text().splitlines()
    assert len(rows) == 1 + 5
    gj = json.loads((tmp_path / "field.geojson").read_text())
    assert [f["geometry"]["type"] for f in gj["features"]].count("LineString") == 1
    html = paths[0].read_text()
    assert html.count("<tr>") >= 7 and "data:image/png;base64," in html


def test_bad_input(house):
    stations = _house_stations()
    with pytest.raises(InputError, match="stands outside zone R2"):
        field_plan(house, [_station("X", "R2", "inside", 5.0, 4.0)] + stations[:1])
    with pytest.raises(UsageError, match="outside the walkable area"):
        field_plan(house, stations, FieldOptions(start="500,500"))
    # a room without doors: R3 with the door R2-R3 taken away
    from dataclasses import replace

    zones = tuple(replace(z, openings=()) if z.id == "R2" else z for z in house.zones)
    closed = replace(house, zones=zones)
    with pytest.raises(InfeasibleError, match="SR3.*zone R3 \\(inside\\)"):
        field_plan(closed, stations[:3], FieldOptions(start="SR1", strict_walls=True))
    # without --strict-walls the leg into R3 is a straight line through the wall R2-R3, and listed
    fp = field_plan(closed, stations[:3], FieldOptions(start="SR1"))
    assert [(c.start, c.end, c.zones) for c in fp.crossings] == [("SR2", "SR3", ("R2", "R3"))]


def test_cli_exit_codes(tmp_path, capsys):
    plan = tmp_path / "plan.json"
    rows = [{"id": s.id, "zone": s.zone, "side": s.side.value, "x": s.x, "y": s.y} for s in _house_stations()]
    plan.write_text(json.dumps({"source": str(INSTANCES / "house_doors.json"), "stations": rows}))
    assert main(["field", str(plan), "--out", str(tmp_path / "f"), "--quiet"]) == 0
    assert (tmp_path / "f" / "field.html").is_file()
    assert main(["field", str(plan), "--out", str(tmp_path / "f"), "--start", "500,500"]) == 2
    bad = tmp_path / "bad.json"
    bad.write_text(
        json.dumps({"source": str(INSTANCES / "house_doors.json"), "stations": [dict(rows[0], zone="nowhere")]})
    )
    assert main(["field", str(bad), "--out", str(tmp_path / "g")]) == 3
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("planner: error:") and "nowhere" in err[-1]


@pytest.mark.slow
def test_plan_with_field(tmp_path):
    # the plan command's --field with the field keys set on the command line, end to end (a plan, its sheet and
    # its PDF: 3-8 s on 2 cores); the quick tier has the same sheet by the API (registration order, sessions) and
    # the field command's exit codes
    out = tmp_path / "p"
    code = main(
        [
            "plan",
            str(INSTANCES / "house_doors.json"),
            "--method",
            "greedy",
            "--out",
            str(out),
            "--field",
            str(out),
            "--set",
            "field-mode=registration",
            "--set",
            "field-session=1h",
            "--quiet",
        ]
    )
    assert code == 0
    data = json.loads((out / "field.json").read_text())
    assert data["mode"] == "registration" and data["registration_order_honoured"]
    assert all(s["duration_s"] <= 3600.0 for s in data["sessions"])


def test_weak_link_reason():
    from planner.field.targets import _reason

    # 45 m apart with a 20 m target range: 45 > 2 x 20 = 40, so no place is within range of both
    assert "more than twice the 20 m target range" in _reason(45.0, 20.0, 0)
    # 30 m apart: 30 <= 40, a place half-way is 15 m from each; the link is short of places in sight, not range
    assert _reason(30.0, 20.0, 2).startswith("only 2 place(s)")


def test_sheet_lists_why_links_stay_weak(house, tmp_path):
    fp = field_plan(house, _house_stations(), FieldOptions(mode="registration"))
    write_sheet(fp, tmp_path)
    data = json.loads((tmp_path / "field.json").read_text())
    for lk in data["links"]:
        assert lk["apart_m"] > 0
        assert (lk["weak_reason"] != "") == lk["weak"]
    assert data["bound_method"] in data["bounds"] and data["lower_bound_m"] <= data["route_length_m"]
