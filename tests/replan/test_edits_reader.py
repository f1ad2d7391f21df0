"""The edits reader (planner-edits/1): every bad entry kind refused in one line naming the file, the entry and the
bad value; a good file read whole."""

from __future__ import annotations

import json

import pytest

from planner.core.errors import InputError
from planner.io.edits import MIN_BLOCKED_RADIUS_M, edits_from_dict, read_edits

META = {
    "instance": "tiny",
    "pool": {"fingerprint": "abc123"},
    "stations": [
        {"id": "R1-in-a", "label": "R1-in-a", "number": 2, "x": 1.0, "y": 2.0, "tripod_radius_m": 0.0},
        {"id": "R2-in-b", "label": "R2-in-b", "number": 1, "x": 7.0, "y": 2.0, "tripod_radius_m": 0.8},
    ],
}
ZONES = ("R1", "R2")


def edits(**more):
    return {"format": "planner-edits/1", **more}


def refused(data) -> str:
    with pytest.raises(InputError) as err:
        edits_from_dict(data, "e.json", META, ZONES)
    line = str(err.value)
    assert "\n" not in line and line.startswith("e.json")
    return line


def test_a_good_file_is_read_whole(tmp_path):
    data = edits(
        plan={"instance": "tiny", "fingerprint": "abc123"},
        stations=[
            {"station": 1, "status": "done", "x": 7.5, "y": 2.25},
            {"station": "R1-in-a", "status": "blocked"},
        ],
        areas=[{"kind": "obstacle", "polygon": [[3, 3], [4, 3], [4, 4]], "note": "van"}],
        closed_zones=["R2"],
        crew={"station": 1},
        time_left_h=2.5,
    )
    path = tmp_path / "e.json"
    path.write_text(json.dumps(data))
    e = read_edits(path, META, ZONES)
    (done,), (blocked,) = e.done, e.blocked
    assert done.station.id == "R2-in-b" and done.moved and done.xy == (7.5, 2.25)
    assert blocked.station.number == 2 and blocked.radius_m == MIN_BLOCKED_RADIUS_M  # plan's disc 0: the least
    assert e.areas[0].kind == "obstacle" and e.closed_zones == ("R2",) and e.time_left_h == 2.5
    assert e.crew_xy == (7.0, 2.0)


@pytest.mark.parametrize(
    ("data", "words"),
    [
        ({"format": "planner-edits/9"}, ["format = 'planner-edits/9'"]),
        (edits(extra=1), ["extra", "unknown key"]),
        (edits(stations=[{"station": 9, "status": "done"}]), ["stations[1]", "station = 9", "not a station"]),
        (edits(stations=[{"station": "nope", "status": "done"}]), ["stations[1]", "'nope'"]),
        (edits(stations=[{"station": 1, "status": "gone"}]), ["stations[1]", "status = 'gone'"]),
        (edits(stations=[{"station": 1, "status": "blocked", "radius_m": -1}]), ["stations[1]", "radius_m = -1"]),
        (edits(stations=[{"station": 1, "status": "done", "x": 1}]), ["stations[1]", "x = 1", "both x and y"]),
        (edits(stations=[{"station": 1, "status": "done", "colour": "red"}]), ["stations[1]", "colour"]),
        (
            edits(stations=[{"station": 1, "status": "done"}, {"station": "R2-in-b", "status": "blocked"}]),
            ["stations[2]", "marked twice"],
        ),
        (edits(areas=[{"kind": "closed", "polygon": [[0, 0], [1, 1]]}]), ["areas[1]", "at least 3 vertices"]),
        (edits(areas=[{"kind": "closed", "polygon": [[0, 0], [1, "a"], [2, 0]]}]), ["areas[1]", "vertex 2"]),
        (edits(areas=[{"kind": "wall", "polygon": [[0, 0], [1, 0], [0, 1]]}]), ["areas[1]", "kind = 'wall'"]),
        (edits(closed_zones=["Z7"]), ["closed_zones[1]", "'Z7'", "not a zone"]),
        (edits(crew={"station": 5}), ["crew", "station = 5"]),
        (edits(crew={"x": 1.0}), ["crew", "x and y"]),
        (edits(time_left_h=-2), ["time_left_h = -2"]),
        (edits(plan={"instance": "other"}), ["plan.instance = 'other'", "another plan"]),
    ],
)
def test_each_bad_entry_is_refused_in_one_line(data, words):
    line = refused(data)
    for w in words:
        assert w in line, (w, line)
