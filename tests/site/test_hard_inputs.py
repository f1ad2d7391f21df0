"""The catalogue of hard inputs (docs/hard-inputs.md): each gives a correct result or a one-line error
with its exit code. DXF cases are in tests/io/test_dxf_import.py."""

from __future__ import annotations

import json
import math
import re
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import planner
from planner.cli import main
from tests.cli.test_cli import assert_one_line_error
from tests.conftest import INSTANCES, ROOT, square_rows


def instance(tmp_path: Path, zones: list[dict], name: str = "site.json", **extra) -> Path:
    data = {
        "format": "tls-planner/1",
        "name": "hard",
        "parameters": {"max_slant_range_m": 60.0},
        "zones": zones,
        **extra,
    }
    path = tmp_path / name
    path.write_text(json.dumps(data))
    return path


def cli(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def plan_ok(path: Path, method: str = "greedy") -> planner.Plan:
    plan = planner.plan_site(planner.load_site(path), planner.PlanOptions(method=method))
    assert plan.verification.complete, plan.verification.summary()
    return plan


def test_touching_zones_share_a_wall(tmp_path):
    # two 10 x 10 rooms side by side; the shared wall x = 10 is scanned from both rooms
    path = instance(
        tmp_path,
        [
            {"id": "a", "scan_side": "inside", "coordinates": [[0, 0], [10, 0], [10, 10], [0, 10]], "height_m": 4},
            {"id": "b", "scan_side": "inside", "coordinates": [[10, 0], [20, 0], [20, 10], [10, 10]], "height_m": 4},
        ],
    )
    plan = plan_ok(path)
    zones = {s.zone for s in plan.stations}
    assert zones == {"a", "b"}
    for s in plan.stations:  # each station stands in its own room, not on the shared wall
        assert (s.x < 10) if s.zone == "a" else (s.x > 10)


def test_collinear_walls_are_planned(tmp_path):
    # a 20 x 10 hall drawn with an extra vertex in the middle of its south wall (180 deg there).
    # From the centre (10, 5) the worst incidence is at the corners: atan(10 / 5) = 63.4 deg <= 68,
    # at most 11.2 m away, so one station is optimal, and the closed form's circle candidate is there.
    path = instance(
        tmp_path,
        [
            {
                "id": "h",
                "scan_side": "inside",
                "coordinates": [[0, 0], [10, 0], [20, 0], [20, 10], [0, 10]],
                "height_m": 5,
            }
        ],
    )
    site = planner.load_site(path)
    assert len(site.zones[0].walls) == 5 and site.zones[0].area_m2 == pytest.approx(200.0)
    plan = plan_ok(path, "milp")
    assert len(plan.stations) == 1 and plan.result.status is planner.Status.OPTIMAL


def test_duplicate_vertex_is_a_one_line_error(tmp_path, capsys):
    path = instance(
        tmp_path,
        [
            {
                "id": "d",
                "scan_side": "inside",
                "coordinates": [[0, 0], [10, 0], [10, 0], [10, 10], [0, 10]],
                "height_m": 5,
            }
        ],
    )
    code, _, err = cli(capsys, "validate", str(path))
    assert code == 3
    assert_one_line_error(err, "site.json", "zone d", "side 2", "zero-length side (duplicate vertex)")


def test_zero_length_side_in_a_table_is_a_one_line_error(write_csv, capsys):
    rows = square_rows("Z")
    rows[2] = ("Z", "inside", 3, 0, 5.0, 90, 5.0)
    code, _, err = cli(capsys, "validate", str(write_csv(rows)))
    assert code == 3
    assert_one_line_error(err, "site.csv", "zone Z", "side_length_m = 0")


def court_with_block(tmp_path: Path, block: list[list[float]]) -> Path:
    ring = [[0, 0], [40, 0], [40, 30], [0, 30], [0, 0]]
    fc = {
        "type": "FeatureCollection",
        "features": [
            {
                "type": "Feature",
                "properties": {"id": "court", "height_m": 6},
                "geometry": {"type": "Polygon", "coordinates": [ring, block + [block[0]]]},
            }
        ],
    }
    path = tmp_path / "court.geojson"
    path.write_text(json.dumps(fc))
    return path


def test_hole_touching_the_outline_along_a_side_is_refused(tmp_path, capsys):
    # the block's south side lies on the court's south wall from x = 15 to 25
    code, _, err = cli(capsys, "validate", str(court_with_block(tmp_path, [[15, 0], [15, 10], [25, 10], [25, 0]])))
    assert code == 3
    assert_one_line_error(err, "court.geojson", "zone court", "holes and outline do not form a valid polygon")


def test_hole_touching_the_outline_at_a_point_is_planned(tmp_path):
    # a diamond block whose south tip touches the south wall at (20, 0): valid (OGC), walls on both sides of it
    plan = plan_ok(court_with_block(tmp_path, [[20, 0], [15, 8], [20, 16], [25, 8]]))
    assert len(plan.site.zones[0].walls) == 8  # 4 outline walls + 4 block walls


@pytest.mark.slow
def test_free_standing_block_walls_are_covered(tmp_path):
    plan = plan_ok(court_with_block(tmp_path, [[15, 10], [15, 20], [25, 20], [25, 10]]), "milp")
    assert plan.verification.percent == 100.0
    assert len(plan.stations) >= 2  # one station cannot see all four faces of the block


@pytest.mark.slow
def test_5000_vertex_outline(tmp_path):
    # a round apse drawn with 5,000 vertices on a 50 m circle: perimeter 2 n r sin(pi/n) = 314.1592 m,
    # area n r^2 sin(2 pi/n) / 2 = 7853.98 m2; from the centre every wall is seen at 0 deg, 50 m away
    n, r = 5000, 50.0
    t = np.arange(n) * 2 * math.pi / n
    coords = np.column_stack([r * np.cos(t), r * np.sin(t)]).round(9).tolist()
    path = instance(tmp_path, [{"id": "apse", "scan_side": "inside", "coordinates": coords, "height_m": 10}])
    site = planner.load_site(path)
    z = site.zones[0]
    assert z.perimeter_m == pytest.approx(2 * n * r * math.sin(math.pi / n), rel=1e-9)
    assert z.area_m2 == pytest.approx(n * r * r * math.sin(2 * math.pi / n) / 2, rel=1e-9)
    plan = plan_ok(path, "milp")
    assert len(plan.stations) == 1 and plan.result.status is planner.Status.OPTIMAL


@pytest.mark.slow
def test_projected_coordinates_around_a_million_metres_change_no_count():
    base = planner.load_site(INSTANCES / "polygon_b.json")
    shift = np.array([612345.678, 5543210.123])  # UTM-like easting / northing
    zones = tuple(
        planner.Zone(z.id, z.scan_side, tuple(map(tuple, (z.xy + shift).tolist())), z.vertex_heights_m, frame=z.frame)
        for z in base.zones
    )
    far = planner.Site("far", zones, base.parameters, base.instrument)
    a, b = (planner.plan_site(s, planner.PlanOptions(method="milp")) for s in (base, far))
    assert len(a.stations) == len(b.stations)
    assert b.verification.complete
    np.testing.assert_allclose([s.xy for s in b.stations], [np.add(s.xy, shift) for s in a.stations], atol=1e-6)


def test_wall_piece_seen_by_no_candidate_exits_4(tmp_path, capsys):
    # a pier 1 m wide stands flush against the south wall from x = 5 to 6: that metre of wall is hidden
    path = instance(
        tmp_path,
        [{"id": "r", "scan_side": "inside", "coordinates": [[0, 0], [20, 0], [20, 10], [0, 10]], "height_m": 5}],
        obstacles=[{"name": "pier", "polygon": [[5, 0], [6, 0], [6, 1], [5, 1]], "height_m": 5}],
    )
    code, _, err = cli(capsys, "plan", str(path), "--method", "greedy")
    assert code == 4
    assert_one_line_error(
        err, "site.json", "seen from no position", "r/inside/wall 1 5.00-6.00 m", "hidden behind walls"
    )


@pytest.mark.parametrize("suffix", [".json", ".csv", ".geojson", ".dxf", ".pol"])
def test_a_100_mb_file_is_refused_without_reading_it(tmp_path, capsys, suffix):
    path = tmp_path / f"huge{suffix}"
    with path.open("wb") as f:  # a sparse file: 100 MB on paper, nothing on disk
        f.truncate(100 * 1024 * 1024)
    cli(capsys, "validate", str(path))  # first call: the command's modules load (lazily), which is no reading
    tracemalloc.start()
    code, _, err = cli(capsys, "validate", str(path))
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert code == 3
    assert_one_line_error(err, f"huge{suffix}", "file too large (104,857,600 bytes")
    assert peak < 5 * 1024 * 1024  # the content was never loaded


@pytest.mark.parametrize(
    "name, text, fragment",
    [
        ("cut.json", '{"format": "tls-planner/1", "zones": [', "invalid JSON"),
        ("cut.geojson", '{"type": "FeatureCollection", "features": [{"type": "Feature"', "invalid JSON"),
        ("cols.csv", "zone,side\nA,inside\n", "column"),
        (
            "word.csv",
            "zone,scan_side,index,side_length_m,wall_height_m,interior_angle_deg,vertex_height_m\n"
            "A,inside,1,ten,5,90,5\n",
            "side_length_m = 'ten'",
        ),
        ("bad.pol", "4 0/1 0/1 1/1 0/1 1/1 1/0 0/1 1/1", "not a number p/q"),
        ("short.pol", "5 0 0 1 0 1 1", "promises 5 vertices"),
        ("empty.pol", "0", "the outline needs at least 3 vertices"),
        ("hole0.pol", "4 0 0 10 0 10 10 0 10 1 0", "the hole 1 needs at least 3 vertices"),
        # absurd numbers are refused, not carried into sums that overflow (1e308 gave an infinite perimeter)
        (
            "far.json",
            '{"zones": [{"id": "hall", "scan_side": "inside", "height_m": 9, '
            '"coordinates": [[0, 0], [1e308, 0], [20, 10], [0, 10]]}]}',
            "coordinates must be finite and within +-1e+08 m",
        ),
        (
            "tall.json",
            '{"zones": [{"id": "hall", "scan_side": "inside", "height_m": 1e308, '
            '"coordinates": [[0, 0], [20, 0], [20, 10], [0, 10]]}]}',
            "height_m = 1e+308: must be a height > 0 and <= 10000 m",
        ),
        (
            "both.geojson",
            '{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Polygon", '
            '"coordinates": [[[0, 0], [20, 0], [20, 10], [0, 10], [0, 0]]]}, "properties": {"id": "A", '
            '"height_m": 5, "height": 7}}]}',
            "give height_m or height, not both",
        ),
        (
            "typo.geojson",
            '{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Polygon", '
            '"coordinates": [[[0, 0], [20, 0], [20, 10], [0, 10], [0, 0]]]}, "properties": {"id": "A", '
            '"height_m": 5}}, {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[5, 5], '
            '[7, 5], [7, 7], [5, 7], [5, 5]]]}, "properties": {"name": "p", "height_m": 5, "role": "obstacel"}}]}',
            "role = 'obstacel': unknown role",
        ),
        (
            "both.json",
            '{"zones": [{"id": "hall", "scan_side": "inside", "height_m": 5, "vertex_heights_m": [5, 5, 5, 5], '
            '"coordinates": [[0, 0], [20, 0], [20, 10], [0, 10]]}]}',
            "give vertex_heights_m or height_m, not both",
        ),
        # Python's digit grouping is no number in a survey table (6_0 read as 60 before)
        (
            "grouped.csv",
            "zone,scan_side,index,side_length_m,wall_height_m,interior_angle_deg,vertex_height_m\n"
            "A,inside,1,6_0,5,90,5\n",
            "side_length_m = '6_0': not a number",
        ),
        # JSON has numbers: a number in quotes is refused, not converted ("9_0" became 90 m walls before)
        (
            "quoted.json",
            '{"zones": [{"id": "hall", "scan_side": "inside", "height_m": "9_0", '
            '"coordinates": [[0, 0], [20, 0], [20, 10], [0, 10]]}]}',
            "height_m = '9_0': must be a number, not text",
        ),
        (
            "overlap.json",
            '{"parameters": {"overlap": "0.3"}, "zones": [{"id": "hall", "scan_side": "inside", "height_m": 9, '
            '"coordinates": [[0, 0], [20, 0], [20, 10], [0, 10]]}]}',
            "overlap = '0.3': must be a number, not text",
        ),
        # GeoJSON members of the wrong JSON kind crashed (AttributeError, TypeError: unhashable; exit 1)
        (
            "props.geojson",
            '{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Polygon", '
            '"coordinates": [[[0, 0], [20, 0], [20, 10], [0, 10], [0, 0]]]}, "properties": ["zone"]}]}',
            "features[1]: properties = 'list': must be an object",
        ),
        (
            "geom.geojson",
            '{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": "Polygon", '
            '"properties": {"id": "A", "height_m": 5}}]}',
            "features[1]: geometry = 'str': must be an object",
        ),
        (
            "side.geojson",
            '{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Polygon", '
            '"coordinates": [[[0, 0], [20, 0], [20, 10], [0, 10], [0, 0]]]}, "properties": {"id": "A", '
            '"height_m": 5, "scan_side": ["inside"]}}]}',
            "zone A features[1]: scan_side = 'list': unknown scan side",
        ),
        # two heights for one GeoJSON zone: height_m was dropped silently (the JSON instance refuses it)
        (
            "vboth.geojson",
            '{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Polygon", '
            '"coordinates": [[[0, 0], [20, 0], [20, 10], [0, 10], [0, 0]]]}, "properties": {"id": "A", '
            '"height_m": 50, "vertex_heights_m": [5, 5, 5, 5]}}]}',
            "zone A features[1]: height_m = 50: give vertex_heights_m or height_m, not both",
        ),
        # .pol numbers beyond a float (OverflowError) and a non-ASCII digit (int() ValueError): exit 3, token and value
        ("huge.pol", "4 0 0 1e400 0 1e400 1e400 0 1e400", "token 4: number = '1e400': number out of range"),
        ("digits.pol", "3 0 0 " + "9" * 400 + " 0 1 1", "token 4: number = '" + "9" * 37 + "...': number out of range"),
        ("grouped.pol", "3 0 0 1_0 0 0 10", "token 4: number = '1_0': not a number p/q"),  # Fraction read it as 10
        (
            "super.pol",
            "\u00b2 0 0 10 0 10 10",
            "token 1: count = '\u00b2': expected the number of vertices of the outline",
        ),
    ],
)
def test_malformed_files_give_one_line_errors(tmp_path, capsys, name, text, fragment):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    code, _, err = cli(capsys, "validate", str(path))
    assert code == 3
    assert_one_line_error(err, name, fragment)


def test_loaders_never_evaluate_code(tmp_path, capsys):
    marker = tmp_path / "pwned"
    payload = f"__import__('pathlib').Path({str(marker)!r}).touch()"
    path = instance(
        tmp_path, [{"id": "x", "scan_side": "inside", "coordinates": [[0, 0], [payload, 0], [10, 10]], "height_m": 3}]
    )
    pol = tmp_path / "x.pol"
    pol.write_text(f"3 0 0 {payload} 0 1 1")
    for p in (path, pol):
        code, _, err = cli(capsys, "validate", str(p))
        assert code == 3 and not marker.exists()
    # and no reader in the package can: no builtin eval/exec/compile (a method such as re.compile is not one),
    # pickle, yaml or __import__ anywhere in planner/
    source = "\n".join(p.read_text() for p in (ROOT / "planner").rglob("*.py"))
    assert not re.search(r"(?<![.\w])(eval|exec|compile)\(|\bpickle\b|\byaml\b|__import__", source)


def test_json_zone_with_a_hole_matches_the_geojson_one(tmp_path):
    # the same 40 x 30 court with a 10 x 10 block, once as a JSON instance (hole given counter-clockwise,
    # stored clockwise) and once as GeoJSON: same walls, same area 1200 - 100 = 1100 m2
    path = instance(
        tmp_path,
        [
            {
                "id": "court",
                "scan_side": "inside",
                "coordinates": [[0, 0], [40, 0], [40, 30], [0, 30]],
                "height_m": 6,
                "holes": [{"coordinates": [[15, 10], [25, 10], [25, 20], [15, 20]], "height_m": 6}],
            }
        ],
    )
    a = planner.load_site(path).zones[0]
    b = planner.load_site(court_with_block(tmp_path, [[15, 10], [15, 20], [25, 20], [25, 10]])).zones[0]
    assert a.area_m2 == pytest.approx(1100.0) == b.area_m2
    assert {(w.start, w.end) for w in a.walls} == {(w.start, w.end) for w in b.walls}  # same directed walls


def test_hole_walls_are_numbered_after_the_outline():
    # outline 4 walls (1-4), first hole 3 walls (5-7), second hole 4 walls (8-11)
    z = planner.Zone(
        "z",
        planner.ScanSide.INSIDE,
        ((0, 0), (30, 0), (30, 20), (0, 20)),
        (5.0,) * 4,
        holes=(((5, 5), (7, 9), (9, 5)), ((15, 5), (15, 9), (19, 9), (19, 5))),
        hole_heights_m=((4.0,) * 3, (4.0,) * 4),
    )
    assert [w.index for w in z.walls] == list(range(1, 12))
    assert z.walls[4].start == (5, 5) and z.walls[7].start == (15, 5)


def test_a_control_point_name_used_twice_is_refused(tmp_path, capsys):
    # the network keys points by name: a second RP1 would merge into the first (5 nodes for 6 points)
    data = json.loads((INSTANCES / "courtyard.json").read_text())
    data["control_points"].append(dict(data["control_points"][0]))
    path = tmp_path / "cp.json"
    path.write_text(json.dumps(data))
    code, _, err = cli(capsys, "validate", str(path))
    name = data["control_points"][0]["name"]
    assert code == 3
    assert_one_line_error(
        err, "cp.json", f"control_points[{len(data['control_points'])}]", f"name = '{name}'", "used twice"
    )
    # and in a --control file
    control = tmp_path / "control.json"
    control.write_text(json.dumps([{"name": "C1", "x": 0, "y": 0}, {"name": "C1", "x": 5, "y": 0}]))
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"stations": [{"id": "S", "zone": "B", "side": "inside", "x": 50, "y": 40}]}))
    code, _, err = cli(capsys, "network", str(INSTANCES / "polygon_b.json"), str(plan), "--control", str(control))
    assert code == 3
    assert_one_line_error(err, "control.json", "control[2]", "name = 'C1'", "used twice")
    # an unknown key in a --control entry is refused too (a typo such as sigma_x_m dropped the value)
    control.write_text(json.dumps([{"name": "C1", "x": 0, "y": 0, "sigma_x_m": 2}]))
    code, _, err = cli(capsys, "network", str(INSTANCES / "polygon_b.json"), str(plan), "--control", str(control))
    assert code == 3
    assert_one_line_error(err, "control.json", "control[1]", "sigma_x_m = 2", "unknown key")


def test_two_table_rooms_alike_in_their_own_frames_are_two_zones(write_csv):
    # each table zone lives in its own frame with vertex 1 at 0,0: two 10 x 10 rooms have the same coordinates
    # there but are different rooms, so they are not "drawn twice" (2 x 4 walls)
    site = planner.load_site(write_csv(square_rows("T1") + square_rows("T2")))
    assert [z.frame for z in site.zones] == ["T1", "T2"] and site.zones[0].vertices == site.zones[1].vertices
    assert len(site.walls) == 8


def test_a_zone_drawn_twice_is_refused_but_inside_and_outside_of_one_outline_are_two_zones(tmp_path, capsys):
    # zone b is zone a's square from another start vertex, clockwise: the same outline, walls counted twice
    square = [[0, 0], [10, 0], [10, 10], [0, 10]]
    twice = [[10, 10], [10, 0], [0, 0], [0, 10]]
    path = instance(
        tmp_path,
        [
            {"id": "a", "scan_side": "inside", "coordinates": square, "height_m": 4},
            {"id": "b", "scan_side": "inside", "coordinates": twice, "height_m": 4},
        ],
    )
    code, _, err = cli(capsys, "validate", str(path))
    assert code == 3
    assert_one_line_error(
        err, "site.json", "zone b", "drawn twice: the same outline as zone 'a', both scanned from inside"
    )
    # a zone scanned from both sides repeats the inside one on its outline (its inside walls counted twice)
    path = instance(
        tmp_path,
        [
            {"id": "a", "scan_side": "both", "coordinates": square, "height_m": 4},
            {"id": "b", "scan_side": "inside", "coordinates": twice, "height_m": 4},
        ],
        "both.json",
    )
    code, _, err = cli(capsys, "validate", str(path))
    assert code == 3
    assert_one_line_error(err, "both.json", "zone b", "the same outline as zone 'a', both scanned from inside")
    # the room scanned from inside and its facade from outside: 4 + 4 walls, both kept
    path = instance(
        tmp_path,
        [
            {"id": "a", "scan_side": "inside", "coordinates": square, "height_m": 4},
            {"id": "b", "scan_side": "outside", "coordinates": twice, "height_m": 4},
        ],
        "two.json",
    )
    assert len(planner.load_site(path).walls) == 8
    # an obstacle drawn twice (a column's lower and upper parts on one footprint) blocks sight once either way:
    # accepted, and the plan is the one without the copy
    post = [[4, 4], [5, 4], [5, 5], [4, 5]]
    one = instance(
        tmp_path,
        [{"id": "a", "scan_side": "inside", "coordinates": square, "height_m": 4}],
        "ob1.json",
        obstacles=[{"name": "p1", "polygon": post, "height_m": 3}],
    )
    two = instance(
        tmp_path,
        [{"id": "a", "scan_side": "inside", "coordinates": square, "height_m": 4}],
        "ob2.json",
        obstacles=[{"name": "p1", "polygon": post, "height_m": 3}, {"name": "p2", "polygon": post, "height_m": 1}],
    )
    assert [(s.x, s.y) for s in plan_ok(two).stations] == [(s.x, s.y) for s in plan_ok(one).stations]
