"""A re-plan on a tiny hand-checkable site (four 6 x 5 m rooms A-D in a row, doors between them, one station per
room): room A's station done, room B's blocked (1 m), room D closed, the crew at A's station. The re-plan keeps A's
station, places nothing within the blocked disc or in D, covers B and C (one station each), verifies every wall
still reachable, loses D's walls (22 m of wall less its 1 m door), registers as one network, and is no larger than a
fresh plan of the same constrained problem built here independently (done station forced, D and the disc no-go),
its bound no higher than that fresh plan's count."""

from __future__ import annotations

import json
import math
import shutil
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
import shapely

import planner
from planner.cli.main import main
from planner.coverage.matrix import merge_problems
from planner.io.load import load_site
from planner.io.plan_json import read_plan_stations
from planner.plan.methods import with_columns
from planner.plan.options import PlanOptions
from planner.plan.problem import resolve
from planner.plan.run import coverage_problem
from planner.site.features import NoGoArea
from planner.solve.instance import cover_instance
from planner.solve.milp import MilpOptions, solve

pytestmark = pytest.mark.slow

SITE = {
    "format": "tls-planner/1",
    "name": "tiny_rooms",
    "instrument": "leica-p30",
    "parameters": {"theta_max_deg": 68, "overlap": 0.3, "sigma_req_mm": 10, "instrument_height_m": 1.6},
    "zones": [
        {"id": z, "scan_side": "inside", "coordinates": [[x, 0], [x + 6, 0], [x + 6, 5], [x, 5]], "height_m": 3}
        for z, x in (("A", 0), ("B", 6), ("C", 12), ("D", 18))
    ],
    "openings": [
        {"zone": z, "wall": 2, "s0_m": 2.0, "s1_m": 3.0, "kind": "door", "name": f"{z}-{n}"}
        for z, n in (("A", "B"), ("B", "C"), ("C", "D"))
    ],
}
BLOCK_M = 1.0


@pytest.fixture(scope="module")
def planned(tmp_path_factory):
    """The tiny site planned with its sheet and replan.npz; the edits (as data) and the stations by zone."""
    d = tmp_path_factory.mktemp("tiny")
    site = d / "tiny.json"
    site.write_text(json.dumps(SITE))
    assert main(["plan", str(site), "--out", str(d / "plan"), "--field", str(d / "plan"), "--quiet"]) == 0
    meta = json.loads((d / "plan" / "plan.json").read_text())
    by_zone = {s["zone"]: s for s in meta["stations"]}
    assert sorted(by_zone) == ["A", "B", "C", "D"] and len(meta["stations"]) == 4  # one per room
    edits = {
        "format": "planner-edits/1",
        "stations": [
            {"station": by_zone["A"]["number"], "status": "done"},
            {"station": by_zone["B"]["label"], "status": "blocked", "radius_m": BLOCK_M},
        ],
        "closed_zones": ["D"],
        "crew": {"station": by_zone["A"]["number"]},
        "time_left_h": 2,
    }
    (d / "edits.json").write_text(json.dumps(edits))
    return d, site, edits, by_zone


@pytest.fixture(scope="module")
def replanned(planned):
    d, _, edits, _ = planned
    return planner.replan(d / "plan" / "plan.json", edits)


def test_keeps_the_done_station_and_avoids_the_edits(planned, replanned):
    _, _, _, by_zone = planned
    a, b = by_zone["A"], by_zone["B"]
    assert [s.id for s in replanned.done] == [a["id"]] and replanned.stations[0].xy == (a["x"], a["y"])
    zone_d = shapely.Polygon([(18, 0), (24, 0), (24, 5), (18, 5)])
    for s in replanned.new:
        assert math.dist(s.xy, (b["x"], b["y"])) > BLOCK_M
        assert not zone_d.intersects(shapely.Point(s.xy)), s
    assert sorted(s.zone for s in replanned.new) == ["B", "C"]  # B and C left, one station each
    assert replanned.solution.rest_count == 2 and replanned.solution.rest_bound == 2


def test_verified_one_network_and_d_lost_with_its_length(replanned):
    assert replanned.unexpected_gaps_m == 0.0
    assert replanned.rest.lost.by_zone.keys() == {"D/inside"}
    assert replanned.rest.lost.by_zone["D/inside"] == pytest.approx(21.0)  # 6 + 5 + 6 + 5, less the 1 m door
    assert replanned.connected
    gaps = {g.zone for g in replanned.verification.gaps}
    assert gaps == {"D"}
    assert replanned.sheet is not None and replanned.sheet.start_xy == replanned.done[0].xy


def test_no_larger_than_a_fresh_plan_of_the_same_constrained_problem(planned, replanned):
    d, site_path, _, by_zone = planned
    site = load_site(site_path)
    b = by_zone["B"]
    disc = [
        (b["x"] + 1.05 * BLOCK_M * math.cos(t), b["y"] + 1.05 * BLOCK_M * math.sin(t))
        for t in np.linspace(0, 2 * math.pi, 33)[:-1]
    ]
    no_go = (
        NoGoArea("blocked", tuple(disc)),
        NoGoArea("closed D", ((18.0, 0.0), (24.0, 0.0), (24.0, 5.0), (18.0, 5.0))),
    )
    problem = resolve(replace(site, no_go_areas=no_go), PlanOptions())
    pool, unseen, _ = coverage_problem(problem)
    done = [s for s in read_plan_stations(d / "plan" / "plan.json", site) if s.zone == "A"]
    cov = merge_problems(pool, problem.sight.coverage(done, problem.targets))
    need = np.setdiff1d(np.arange(cov.shape[1]), unseen)
    groups, links = problem.registration.groups(cov.candidates)
    inst = cover_instance(cov, groups=groups, links=links)
    inst = replace(inst, by_candidate=inst.by_candidate[:, need].tocsr(), target_length_m=inst.lengths_m[need])
    force = sp.csr_matrix(([True], ([cov.shape[0] - 1], [0])), shape=(cov.shape[0], 1))
    fresh = solve(with_columns(inst, force), MilpOptions(overlap=problem.rule))
    fresh_rest = len(fresh.selected) - 1
    assert cov.shape[0] - 1 in fresh.selected
    assert replanned.solution.rest_count <= fresh_rest
    assert replanned.solution.rest_bound is not None and replanned.solution.rest_bound <= fresh_rest


def test_command_writes_the_history_and_a_fallback_says_so(planned, tmp_path, capsys):
    d, _, _, _ = planned
    out = tmp_path / "re"
    assert main(["replan", str(d / "plan" / "plan.json"), str(d / "edits.json"), "--out", str(out), "--quiet"]) == 0
    names = {p.name for p in out.iterdir()}
    assert {"plan.json", "plan.0.json", "plan.1.json", "edits.1.json", "replan.npz", "sheet"} <= names
    new = json.loads((out / "plan.json").read_text())
    assert new["replan"]["walls_lost"]["by_zone"] == {"D/inside": pytest.approx(21.0)}
    assert new["replan"]["one_network"] and new["replan"]["reachable_uncovered_m"] == 0
    assert len(new["stations"]) == 3 and (out / "sheet" / "field.html").is_file()
    # a second re-plan from the new plan, into the same folder: the next index, the first plan kept
    first = (out / "plan.0.json").read_text()
    second = {"format": "planner-edits/1", "stations": [{"station": 1, "status": "done"}], "crew": {"station": 1}}
    (tmp_path / "second.json").write_text(json.dumps(second))
    assert main(["replan", str(out / "plan.json"), str(tmp_path / "second.json"), "--out", str(out), "--quiet"]) == 0
    assert (out / "plan.2.json").is_file() and (out / "edits.2.json").is_file()
    assert (out / "plan.0.json").read_text() == first
    # a plan without replan.npz: the pool is built again, and said so on standard error
    bare = tmp_path / "bare"
    bare.mkdir()
    shutil.copy(d / "plan" / "plan.json", bare / "plan.json")
    capsys.readouterr()
    assert (
        main(["replan", str(bare / "plan.json"), str(d / "edits.json"), "--out", str(tmp_path / "re2"), "--quiet"]) == 0
    )
    err = capsys.readouterr().err
    assert "built again" in err and "no replan.npz" in err
    again = json.loads((tmp_path / "re2" / "plan.json").read_text())
    assert again["replan"]["rest"]["stations"] == new["replan"]["rest"]["stations"]


def test_a_replan_in_the_plans_own_folder_moves_its_sheet_aside(planned, tmp_path, capsys):
    """The field workflow writes the sheet into the plan's folder, and ``planner replan`` writes there by default:
    the earlier plan's sheet moves to superseded.1 with the plan it lists, the new plan names the history file it
    came from, and the next re-plan there (nothing left to move) names the one after."""
    d, _, _, _ = planned
    here = tmp_path / "plan"
    shutil.copytree(d / "plan", here)
    earlier = json.loads((here / "plan.json").read_text())
    assert main(["replan", str(here / "plan.json"), str(d / "edits.json"), "--quiet"]) == 0
    assert "superseded.1" in capsys.readouterr().err
    sheet = json.loads((here / "superseded.1" / "field.json").read_text())
    assert json.loads((here / "superseded.1" / "plan.json").read_text()) == earlier
    assert {s["station"] for s in sheet["setups"]} == {s["label"] for s in earlier["stations"]}
    assert not (here / "field.json").exists() and (here / "sheet" / "field.json").is_file()
    new = json.loads((here / "plan.json").read_text())
    assert new["replan"]["from_plan"] == str(here / "plan.0.json")
    assert json.loads((here / "plan.0.json").read_text()) == earlier
    second = {"format": "planner-edits/1", "stations": [{"station": 1, "status": "done"}], "crew": {"station": 1}}
    (tmp_path / "second.json").write_text(json.dumps(second))
    assert main(["replan", str(here / "plan.json"), str(tmp_path / "second.json"), "--quiet"]) == 0
    assert json.loads((here / "plan.json").read_text())["replan"]["from_plan"] == str(here / "plan.1.json")
    assert not (here / "superseded.2").exists()  # the sheet in sheet/ is rewritten, nothing else was left


def test_an_obstacle_hides_and_the_plan_still_verifies(planned):
    d, _, edits, _ = planned
    wall = {"kind": "obstacle", "polygon": [[13.5, 1.0], [14.0, 1.0], [14.0, 4.0], [13.5, 4.0]], "note": "scaffold"}
    r = planner.replan(d / "plan" / "plan.json", {**edits, "areas": [wall]})
    assert r.rest.hidden_pairs > 0 and r.rest.removed["obstacle"] > 0
    assert r.unexpected_gaps_m == 0.0 and r.connected
    box = shapely.Polygon(wall["polygon"])
    assert all(not box.intersects(shapely.Point(s.xy)) for s in r.new)


def test_path_of_plan_json_recorded(replanned):
    assert Path(replanned.source.path).name == "plan.json"


def test_bad_edits_exit_3_in_one_line_and_write_nothing(planned, tmp_path, capsys):
    d, site, _, _ = planned
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"format": "planner-edits/1", "stations": [{"station": 9, "status": "done"}]}))
    out = tmp_path / "out"
    assert main(["replan", str(d / "plan" / "plan.json"), str(bad), "--out", str(out)]) == 3
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "stations[1]: station = 9: not a station of the plan" in err
    assert not out.exists()
    assert main(["replan", str(site), str(bad)]) == 2  # a site where the plan belongs
