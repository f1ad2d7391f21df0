"""Stations done in one re-plan stay done in the next: the new plan.json records them (``"status": "done"``, at
the position where they stood), and a re-plan of that plan keeps them done (fixed, in the network) without the
edits naming them again; edits that name them done again are accepted, edits that block one are refused (exit 3,
one line). The tiny four-room site of test_replan_tiny (room A's station done, room D closed)."""

from __future__ import annotations

import json

import pytest

import planner
from planner.cli.main import main
from tests.replan.test_replan_tiny import SITE

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def first(tmp_path_factory):
    """The tiny site planned, then re-planned once with room A's station done (moved 0.2 m): the folder and the
    new plan.json's data."""
    d = tmp_path_factory.mktemp("carry")
    (d / "tiny.json").write_text(json.dumps(SITE))
    assert main(["plan", str(d / "tiny.json"), "--out", str(d / "plan"), "--quiet"]) == 0
    a = next(s for s in json.loads((d / "plan" / "plan.json").read_text())["stations"] if s["zone"] == "A")
    edits = {
        "format": "planner-edits/1",
        "stations": [{"station": a["number"], "status": "done", "x": a["x"] + 0.2, "y": a["y"]}],
        "closed_zones": ["D"],
    }
    (d / "edits.json").write_text(json.dumps(edits))
    assert (
        main(["replan", str(d / "plan" / "plan.json"), str(d / "edits.json"), "--out", str(d / "re1"), "--quiet"]) == 0
    )
    return d, a, json.loads((d / "re1" / "plan.json").read_text())


def test_the_new_plan_records_the_done_station_where_it_stood(first):
    _, a, new = first
    done = [s for s in new["stations"] if s.get("status") == "done"]
    assert [s["id"] for s in done] == [a["id"]]
    assert (done[0]["x"], done[0]["y"]) == (pytest.approx(a["x"] + 0.2), pytest.approx(a["y"]))
    assert all("status" not in s for s in new["stations"] if s["id"] != a["id"])


def test_the_next_replan_keeps_it_done_without_being_told(first):
    d, a, new = first
    r = planner.replan(d / "re1" / "plan.json", {"format": "planner-edits/1"})
    assert [s.id for s in r.done] == [a["id"]]
    assert (r.done[0].x, r.done[0].y) == (pytest.approx(a["x"] + 0.2), pytest.approx(a["y"]))
    assert r.connected and r.unexpected_gaps_m == 0.0
    assert a["id"] not in {s.id for s in r.new}  # fixed: not placed again
    assert r.changes.done == (a["id"],) and r.changes.moved == ()
    assert "1 of them done before (plan.json)" in r.edits.lines()[0]
    # named done again (as a surveyor may): no error, the same re-plan
    again = {"format": "planner-edits/1", "stations": [{"station": a["id"], "status": "done"}]}
    r2 = planner.replan(d / "re1" / "plan.json", again)
    assert [s.id for s in r2.done] == [a["id"]] and len(r2.stations) == len(r.stations)


def test_the_command_writes_it_done_again(first, tmp_path):
    d, a, _ = first
    (tmp_path / "none.json").write_text(json.dumps({"format": "planner-edits/1"}))
    out = tmp_path / "re2"
    assert (
        main(["replan", str(d / "re1" / "plan.json"), str(tmp_path / "none.json"), "--out", str(out), "--quiet"]) == 0
    )
    new = json.loads((out / "plan.json").read_text())
    assert [s["id"] for s in new["stations"] if s.get("status") == "done"] == [a["id"]]
    assert new["replan"]["changes"]["done"] == [a["id"]]


def test_blocking_a_done_station_is_refused_in_one_line(first, tmp_path, capsys):
    d, a, _ = first
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"format": "planner-edits/1", "stations": [{"station": a["id"], "status": "blocked"}]}))
    assert main(["replan", str(d / "re1" / "plan.json"), str(bad), "--out", str(tmp_path / "out")]) == 3
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "was done in an earlier re-plan" in err and "stations[1]" in err
