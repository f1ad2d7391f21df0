"""The JSON instance reader: every feature, units, and its refusals."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from planner.core.errors import ClosureError, InputError
from planner.io import load_site
from tests.conftest import INSTANCES


def write(tmp_path: Path, inst: dict, name: str = "i.json") -> Path:
    p = tmp_path / name
    p.write_text(json.dumps(inst))
    return p


def square(zid="S", side="inside", **extra):
    return {"id": zid, "scan_side": side, "coordinates": [[0, 0], [10, 0], [10, 10], [0, 10]], "height_m": 5, **extra}


def test_courtyard_example_loads_every_feature():
    site = load_site(INSTANCES / "courtyard.json")
    assert [z.id for z in site.zones] == ["court", "hall", "room"]
    assert site.zone("court").frame == "site" and site.zone("room").frame == "room"
    assert site.zone("court").walls[1].h_end_m == 14 and site.zone("court").walls[1].printed_height_m == 14
    assert len(site.obstacles) == 1 and site.obstacles[0].height_m == 6
    assert len(site.no_go_areas) == 1 and site.boundary is not None
    assert [c.name for c in site.control_points] == ["RP1", "RP2", "RP3"]
    assert site.control_points[0].sigma_x_m == pytest.approx(0.002) and site.control_points[1].z is None
    # drawing scale 1:50 -> 5 mm (table 1.1)
    assert site.parameters.sigma_req_m == pytest.approx(0.005) and site.parameters.drawing_scale == 50
    assert site.parameters.instrument_height_m == 1.6


def test_mm_and_m_parameters_are_the_same(tmp_path):
    a = load_site(write(tmp_path, {"zones": [square()], "parameters": {"sigma_req_mm": 7, "sigma_0_mm": 1}}, "a.json"))
    b = load_site(
        write(tmp_path, {"zones": [square()], "parameters": {"sigma_req_m": 0.007, "sigma_0_m": 0.001}}, "b.json")
    )
    assert a.parameters == b.parameters


def test_both_units_given_is_refused(tmp_path):
    with pytest.raises(InputError, match="sigma_req: given twice"):
        load_site(write(tmp_path, {"zones": [square()], "parameters": {"sigma_req_mm": 7, "sigma_req_m": 0.007}}))


def test_clockwise_coordinates_are_stored_counter_clockwise(tmp_path):
    cw = {
        "id": "S",
        "scan_side": "inside",
        "coordinates": [[0, 0], [0, 10], [10, 10], [10, 0]],
        "vertex_heights_m": [1, 2, 3, 4],
        "wall_heights_m": [2, 3, 4, 4],
    }
    z = load_site(write(tmp_path, {"zones": [cw]})).zone("S")
    assert z.area_m2 == pytest.approx(100.0) and z.xy[0].tolist() == [0, 0]
    assert "clockwise" in z.notes[0]
    # every wall keeps its own heights: the wall (0,0)-(0,10) had vertex heights 1..2, printed 2
    w = next(w for w in z.walls if {w.start, w.end} == {(0.0, 0.0), (0.0, 10.0)})
    assert {w.h_start_m, w.h_end_m} == {1.0, 2.0} and w.printed_height_m == 2.0
    assert all(w.height_check_ok for w in z.walls)


def test_inline_table_zone(tmp_path):
    rows = [{"side_length_m": 10, "wall_height_m": 5, "interior_angle_deg": 90, "vertex_height_m": 5}] * 4
    z = load_site(write(tmp_path, {"zones": [{"id": "T", "scan_side": "outside", "table": rows}]})).zone("T")
    assert z.area_m2 == pytest.approx(100.0) and z.closure.linear_misclosure_m < 1e-12


def test_correction_must_match_the_printed_value(tmp_path):
    (tmp_path / "t.csv").write_text((INSTANCES / "baalbek.csv").read_text())
    inst = json.loads((INSTANCES / "baalbek.json").read_text())
    inst["zones"] = [{"table_csv": "t.csv"}]
    inst["corrections"][1]["printed"] = 128.0
    with pytest.raises(
        InputError,
        match=r"zone Z3 row 6: interior_angle_deg = 128: correction says printed 128 but the table holds 128.929",
    ):
        load_site(write(tmp_path, inst))


@pytest.mark.parametrize(
    "zone, field, message",
    [
        ("S", "side_length_m", "a vertex correction changes one of interior_angle_deg, vertex_height_m"),
        ("Q", "vertex_height_m", "zone Q: corrections: correction names no table zone"),
    ],
)
def test_correction_of_a_wrong_field_or_an_unknown_zone_is_refused(tmp_path, zone, field, message):
    fix = {"zone": zone, "vertex": 1, "field": field, "printed": 1, "corrected": 2, "reason": "x"}
    with pytest.raises(InputError, match=message):
        load_site(write(tmp_path, {"zones": [square()], "corrections": [fix]}))


def test_stale_acceptance_is_refused(tmp_path):
    (tmp_path / "t.csv").write_text((INSTANCES / "baalbek.csv").read_text())
    inst = json.loads((INSTANCES / "baalbek.json").read_text())
    inst["zones"] = [{"table_csv": "t.csv"}]
    inst["accepted_misclosures"][0]["linear_misclosure_m"] = 0.5
    with pytest.raises(ClosureError, match="zone Z6: accepted misclosure .* does not match the data"):
        load_site(write(tmp_path, inst))


@pytest.mark.parametrize(
    "inst, fragment",
    [
        ({"zones": [square()], "colour": "red"}, "colour: unknown key in instance"),
        ({"zones": []}, "zones = 0: an instance needs at least one zone"),
        ({"zones": [square(), square()]}, "zone S: id = 'S': duplicate zone id"),
        ({"zones": [square(side="up")]}, "zone S: scan_side = 'up'"),
        ({"zones": [square(height_m=-1)]}, "zone S: height_m = -1: must be a height > 0"),  # named as written
        # an opening reversed names its zone (it named the opening's own name as the zone before)
        (
            {"zones": [square()], "openings": [{"zone": "S", "wall": 1, "s0_m": 5, "s1_m": 2, "name": "d"}]},
            "zone S openings[1]: s0_m..s1_m = '5..2': needs 0 <= s0_m < s1_m",
        ),
        # a table_csv that is a folder names the instance's entry (it named the folder as the file before)
        ({"zones": [{"table_csv": "."}]}, "zones[1]: table_csv = '.': names no file beside the instance"),
        ({"zones": [square()], "parameters": {"overlap": 1.5}}, "overlap = 1.5"),
        ({"zones": [square()], "parameters": {"sigma_req_mm": 5, "drawing_scale": "1:50"}}, "not both"),
        (
            {"zones": [{**square(), "coordinates": [[0, 0], [1, 0], [1, 0], [0, 1]]}]},
            "zone S side 2: side_length_m = 0: zero-length side",
        ),
        (
            {"zones": [{**square(), "coordinates": [[0, 0], [1, "x"], [0, 1]]}]},
            "zone S vertex 2: coordinates = 'x': coordinate must be a finite number",
        ),
        (
            {"zones": [square()], "obstacles": [{"polygon": [[0, 0], [1, 0], [0, 1]], "height_m": 0}]},
            "obstacle 1: height_m = 0",
        ),
        ({"format": "other/9", "zones": [square()]}, "format = 'other/9': unsupported format"),
    ],
)
def test_refusals_name_file_and_value(tmp_path, inst, fragment):
    with pytest.raises(InputError) as exc:
        load_site(write(tmp_path, inst))
    msg = str(exc.value)
    assert "i.json" in msg and fragment in msg and "\n" not in msg


def test_invalid_json_names_line(tmp_path):
    p = tmp_path / "broken.json"
    p.write_text('{"zones": [\n  {"id": "S",,}\n]}')
    with pytest.raises(InputError, match=r"broken.json: line 2 column 14: invalid JSON"):
        load_site(p)


def test_nan_in_json_refused(tmp_path):
    p = tmp_path / "nan.json"
    p.write_text('{"zones": [{"id": "S", "scan_side": "inside", "coordinates": [[0,0],[1,0],[1,1]], "height_m": NaN}]}')
    with pytest.raises(InputError, match="height_m = nan: must be finite"):
        load_site(p)


def test_oversized_file_refused_before_reading(tmp_path, monkeypatch):
    import planner.core.fileio as fileio

    monkeypatch.setattr(fileio, "MAX_INPUT_BYTES", 100)
    p = write(tmp_path, {"zones": [square()], "description": "x" * 200})
    with pytest.raises(InputError, match="file too large"):
        load_site(p)
