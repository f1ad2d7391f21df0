"""A field sheet for every site (issue 45 step 4): where the model has no opening between rooms the legs cross the
walls (a straight line), are listed and said once; ``--strict-walls`` refuses as before (exit 4); a site file
given to ``planner field`` is a usage error that says so (exit 2)."""

from __future__ import annotations

import json
import math

import pytest
import shapely

from planner.cli import main
from planner.core.errors import ExitCode
from planner.field.walking import walk_space
from planner.io import load_site
from tests.conftest import INSTANCES

BAALBEK = INSTANCES / "baalbek_site.json"
# four stations of a greedy plan of baalbek_site.json: rooms Z1, Z2, Z5 and the open ground; no openings in the model
STATIONS = [
    ("Z1-in-C", "Z1", "inside", 154.393, 34.865),
    ("Z2-in-G23", "Z2", "inside", 46.797, 34.432),
    ("Z5-in-C", "Z5", "inside", 5.547, 5.428),
    ("outline-out-V1", "outline", "outside", -36.101, -35.327),
]
FILES = ("field.html", "field.csv", "field.geojson", "field.json", "field.pdf")


def _plan(tmp_path, site=BAALBEK, stations=STATIONS):
    plan = tmp_path / "plan.json"
    rows = [{"id": i, "zone": z, "side": s, "x": x, "y": y} for i, z, s, x, y in stations]
    plan.write_text(json.dumps({"source": str(site), "stations": rows}))
    return plan


def test_rooms_without_openings_get_legs_through_walls(tmp_path, capsys):
    plan = _plan(tmp_path)
    out = tmp_path / "f"
    assert main(["field", str(plan), "--out", str(out), "--quiet"]) == ExitCode.OK
    for name in FILES:
        assert (out / name).is_file(), name
    said = capsys.readouterr().out
    line = [s for s in said.splitlines() if s.startswith("no opening in the model")]
    assert len(line) == 1  # said once
    assert "rooms Z1, Z2, Z5 and the open ground" in line[0] and "docs/site.md#2-openings" in line[0]
    data = json.loads((out / "field.json").read_text())
    legs = data["legs_crossing_walls"]
    assert len(legs) == 3  # four parts, each a part of its own: three legs join them
    for c in legs:
        leg = data["legs"][c["leg"]]
        assert len(leg) == 2  # a straight line
        assert c["length_m"] == pytest.approx(math.dist(*leg))
        assert set(c["zones"]) & {"Z1", "Z2", "Z5"}  # it crosses the walls of a room it leaves or enters
    assert sorted(data["no_opening_between"]) == sorted(["Z1", "Z2", "Z5", "the open ground"])
    # the route still adds up: walks and straight legs
    total = sum(math.dist(p, q) for leg in data["legs"] for p, q in zip(leg, leg[1:]))
    assert total == pytest.approx(data["route_length_m"], rel=1e-6)
    html = (out / "field.html").read_text()
    assert "Legs that cross a wall" in html and "no opening in the model between rooms" in html
    # the site map draws each of them in the route layer, in the dash of a leg through a wall
    assert html.count('<polyline class="sm-route sm-through"') == len(legs)


def test_strict_walls_refuses_as_before(tmp_path, capsys):
    plan = _plan(tmp_path)
    code = main(["field", str(plan), "--out", str(tmp_path / "f"), "--strict-walls", "--quiet"])
    assert code == ExitCode.INFEASIBLE
    err = capsys.readouterr().err
    assert "cannot be reached on foot from the start" in err and "which no door or gate joins" in err
    assert not (tmp_path / "f").exists()


def test_a_site_file_is_not_a_plan(tmp_path, capsys):
    for site in (BAALBEK, INSTANCES / "baalbek.csv"):
        assert main(["field", str(site), "--out", str(tmp_path / "f")]) == ExitCode.USAGE
        err = capsys.readouterr().err.strip().splitlines()[-1]
        assert f"{site} is a site file; planner field expects a plan.json written by `planner plan --out DIR`" in err
    assert not (tmp_path / "f").exists()


@pytest.mark.slow  # two planner runs; tests/field/test_field.py::test_bad_input refuses and lists the legs quickly
def test_plan_field_strict_walls(tmp_path):
    # house_doors without its doors: three rooms no walk joins
    site = json.loads((INSTANCES / "house_doors.json").read_text())
    site["openings"] = []
    path = tmp_path / "house_closed.json"
    path.write_text(json.dumps(site))
    base = ["plan", str(path), "--method", "greedy", "--quiet"]
    assert main([*base, "--field", str(tmp_path / "a"), "--set", "field-strict-walls"]) == ExitCode.INFEASIBLE
    assert main([*base, "--field", str(tmp_path / "b")]) == ExitCode.OK
    data = json.loads((tmp_path / "b" / "field.json").read_text())
    assert data["legs_crossing_walls"] and "no opening in the model between rooms" in data["walls_advice"]
    walls = shapely.MultiLineString([list(w) for w in walk_space(load_site(path), "site").solid_walls])
    for k, leg in enumerate(data["legs"]):  # every leg that touches a wall is listed as crossing one
        if len(leg) > 1 and shapely.LineString(leg).intersects(walls):
            assert k in {c["leg"] for c in data["legs_crossing_walls"]}


def test_open_house_has_no_legs_through_walls(tmp_path):
    stations = [
        ("SR1", "R1", "inside", 5.0, 4.0),
        ("SR2", "R2", "inside", 15.0, 4.0),
        ("Sf", "house", "outside", 5, -5),
    ]
    plan = _plan(tmp_path, INSTANCES / "house_doors.json", stations)
    assert main(["field", str(plan), "--out", str(tmp_path / "f"), "--quiet"]) == ExitCode.OK
    data = json.loads((tmp_path / "f" / "field.json").read_text())
    assert data["legs_crossing_walls"] == [] and data["walls_advice"] == ""


@pytest.mark.slow
def test_baalbek_greedy_plan_gets_its_sheet(tmp_path, capsys):
    # the brief's command: a greedy plan of baalbek_site.json with its field sheet, then planner field on it
    out = tmp_path / "p"
    args = ["plan", str(BAALBEK), "--method", "greedy", "--out", str(out), "--field", str(out), "--quiet"]
    assert main(args) == ExitCode.OK
    for name in FILES:
        assert (out / name).is_file(), name
    said = capsys.readouterr().out
    assert said.count("no opening in the model between rooms") == 1
    line = next(s for s in said.splitlines() if s.startswith("no opening"))
    for room in ("Z1", "Z5", "Z11"):
        assert f" {room}," in line or f" {room} " in line
    assert main(["field", str(out / "plan.json"), "--quiet"]) == ExitCode.OK
    assert main(["field", str(out / "plan.json"), "--strict-walls", "--quiet"]) == ExitCode.INFEASIBLE
