"""IFC input: spaces -> inside zones per storey, blockers cut out, doors as openings, and the failures.

The models are written here with IfcOpenShell's API (scripts/make/make_ifc_house.py, in millimetres):
ground floor an L-shaped living room with a 0.3 m column, a kitchen and a hall with a straight stair (rooms
2.7 m high), upper floor a bedroom, a study and a landing round the stairwell (2.5 m high), walls 0.2 m thick,
seven doors.
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

from planner.core.errors import InputError
from planner.io.ifc_in import IfcOptions, read_ifc_site
from planner.site.model import SITE_FRAME, ScanSide
from tests.conftest import INSTANCES, ROOT
from tests.io.cli import planner_cli

FZK = ROOT / "instances" / "external" / "AC20-FZK-Haus.ifc"


def _builder():
    spec = importlib.util.spec_from_file_location("make_ifc_house", ROOT / "scripts" / "make" / "make_ifc_house.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.build_house


@pytest.fixture(scope="module")
def house(tmp_path_factory) -> Path:
    return _builder()(tmp_path_factory.mktemp("ifc") / "house.ifc")


def _wall_with(zone, start, end):
    return next(w for w in zone.walls if w.start == start and w.end == end)


def test_ground_floor_rooms_heights_column_and_doors(house):
    site = read_ifc_site(house, IfcOptions(storey="Ground floor"))
    assert [z.id for z in site.zones] == ["Hall", "Kitchen", "Living"]  # sorted by long name
    living = site.zone("Living")
    assert living.frame == SITE_FRAME and living.scan_side is ScanSide.INSIDE
    # L-shape 7.7 x 3.8 + 3.8 x 3.8 = 43.70 m^2, less the 0.3 x 0.3 column = 43.61 m^2 (mm file, read as m)
    assert living.area_m2 == pytest.approx(43.61, abs=1e-6)
    assert len(living.vertices) == 6 and set(living.vertex_heights_m) == {2.7}
    assert len(living.holes) == 1 and living.hole_heights_m == ((2.7,) * 4,)  # the column, its own height
    # the living-kitchen door stands in the wall x = 7.9..8.1 at y = 1.5..2.4; Living's wall on x = 7.9 runs
    # from y = 0.2, so the opening is at s = 1.3..2.2 m along it
    wall = _wall_with(living, (7.9, 0.2), (7.9, 4.0))
    ops = [o for o in living.openings if o.wall == wall.index]
    assert [(o.s0_m, o.s1_m, o.kind, o.name) for o in ops] == [(1.3, 2.2, "door", "D-living-kitchen")]
    assert {o.name for o in site.zone("Hall").openings} == {"D-living-hall", "D-kitchen-hall", "D-front"}
    assert site.zone("Kitchen").area_m2 == pytest.approx(3.7 * 3.8)


def test_storeys_by_index_and_all(house):
    upper = read_ifc_site(house, IfcOptions(storey="2"))
    assert [z.id for z in upper.zones] == ["Bedroom", "Landing", "Study"]
    assert all(set(z.vertex_heights_m) == {2.5} for z in upper.zones)
    both = read_ifc_site(house)  # default: every storey with spaces, each in its own frame
    assert [(z.frame, z.id) for z in both.zones] == [
        ("Ground floor", "Ground floor/Hall"),
        ("Ground floor", "Ground floor/Kitchen"),
        ("Ground floor", "Ground floor/Living"),
        ("Upper floor", "Upper floor/Bedroom"),
        ("Upper floor", "Upper floor/Landing"),
        ("Upper floor", "Upper floor/Study"),
    ]
    with pytest.raises(InputError, match=r"no such storey \(the file has: 1 'Ground floor', 2 'Upper floor'\)"):
        read_ifc_site(house, IfcOptions(storey="Roof"))


def test_exterior_outline(house):
    site = read_ifc_site(house, IfcOptions(storey="1", exterior=True))
    ext = site.zone("exterior")
    # the outer walls enclose 12 m x 8 m; storey height 3.0 m (elevations 0 and 3000 mm)
    assert ext.scan_side is ScanSide.OUTSIDE and ext.area_m2 == pytest.approx(96.0)
    assert set(ext.vertex_heights_m) == {3.0}


def test_windows_are_openings_only_with_the_flag(tmp_path, house):
    # the bundled house has no windows: the flag changes nothing there
    assert (
        read_ifc_site(house, IfcOptions(storey="1")).zones
        == read_ifc_site(house, IfcOptions(storey="1", windows=True)).zones
    )
    # a window in the kitchen's outer wall, x = 9.5..10.7 at y = 0..0.2: the kitchen's first wall runs from
    # (8.1, 0.2) to (11.8, 0.2), so the opening is at s = 9.5 - 8.1 = 1.4 .. 10.7 - 8.1 = 2.6 m along it
    glazed = _builder()(tmp_path / "glazed.ifc", windows=True)
    plain, flagged = (
        read_ifc_site(glazed, IfcOptions(storey="1")),
        read_ifc_site(glazed, IfcOptions(storey="1", windows=True)),
    )
    assert plain.zones == read_ifc_site(house, IfcOptions(storey="1")).zones  # a window is no door
    kitchen = flagged.zone("Kitchen")
    wall = _wall_with(kitchen, (8.1, 0.2), (11.8, 0.2))
    assert [(o.wall, o.s0_m, o.s1_m, o.kind, o.name) for o in kitchen.openings if o.kind == "window"] == [
        (wall.index, pytest.approx(1.4), pytest.approx(2.6), "window", "W-kitchen")
    ]
    assert [o.name for o in kitchen.openings if o.kind == "door"] == [o.name for o in plain.zone("Kitchen").openings]


def test_ifc2x3_reads_as_ifc4(tmp_path, house):
    old = _builder()(tmp_path / "house23.ifc", schema="IFC2X3")
    assert "IFC2X3" in old.read_text()[:2000]
    for storey in ("1", "2"):
        a, b = read_ifc_site(house, IfcOptions(storey=storey)), read_ifc_site(old, IfcOptions(storey=storey))
        assert [(z.id, z.vertices, z.vertex_heights_m, z.holes, z.openings) for z in a.zones] == [
            (z.id, z.vertices, z.vertex_heights_m, z.holes, z.openings) for z in b.zones
        ]


def test_failures_are_one_line_errors(tmp_path):
    build = _builder()
    text = tmp_path / "plan.ifc"
    text.write_text("this is not a building model\n")
    with pytest.raises(InputError, match="not an IFC file"):
        read_ifc_site(text)
    with pytest.raises(InputError, match="no IfcSpace in any storey.*define the rooms as spaces"):
        read_ifc_site(build(tmp_path / "empty.ifc", spaces=False))
    with pytest.raises(InputError, match="zone Kitchen.*no body geometry"):
        read_ifc_site(build(tmp_path / "faceless.ifc", faceless_space="Kitchen"), IfcOptions(storey="1"))
    run = planner_cli("validate", str(text))
    assert run.returncode == 3 and run.stderr.count("\n") == 1 and "Traceback" not in run.stderr


@pytest.mark.slow
def test_committed_house_plans_per_storey_and_verifies(tmp_path):
    """instances/house2.ifc (the script's output): each storey planned, verified 100 %."""
    for storey in ("1", "2"):
        out = tmp_path / storey
        run = planner_cli("plan", str(INSTANCES / "house2.ifc"), "--storey", storey, "--out", str(out), "--quiet")
        assert run.returncode == 0, run.stderr
        assert "verification at 0.1 m: 100.000 % covered" in run.stdout
        ver = planner_cli("verify", str(INSTANCES / "house2.ifc"), "--storey", storey, str(out / "plan.json"))
        assert ver.returncode == 0, ver.stderr
        stations = json.loads((out / "plan.json").read_text())["stations"]
        zones = {s["zone"] for s in stations}
        assert zones == ({"Hall", "Kitchen", "Living"} if storey == "1" else {"Bedroom", "Landing", "Study"})


@pytest.mark.skipif(not FZK.is_file(), reason="AC20-FZK-Haus.ifc not present (not committed; docs/ifc.md)")
def test_fzk_haus_ground_floor():
    site = read_ifc_site(FZK, IfcOptions(storey="Erdgeschoss"))
    assert sorted(z.id for z in site.zones) == ["Bad", "Buero", "Flur", "Küche", "Schlafzimmer", "Wohnen"]
    assert all(set(z.vertex_heights_m) == {2.5} for z in site.zones)
    assert {o.name for o in site.zone("Flur").openings} >= {"Haustuer", "Innentuer-1", "Innentuer-2", "Innentuer-3"}


def _edited(house: Path, out: Path, edit) -> Path:
    """A copy of the house with ``edit(model)`` applied."""
    import ifcopenshell

    model = ifcopenshell.open(str(house))
    edit(model)
    model.write(str(out))
    return out


def test_a_model_without_a_length_unit_is_read_as_metres_and_says_so(tmp_path, house):
    # no LENGTHUNIT in the unit assignment: read as metres (as IfcOpenShell does) with no word of it
    # before; now every zone's notes say so, as the DXF reader notes $INSUNITS = 0
    def drop_length_unit(model) -> None:
        units = model.by_type("IfcUnitAssignment")[0]
        angle = model.create_entity("IfcSIUnit", UnitType="PLANEANGLEUNIT", Name="RADIAN")
        units.Units = [u for u in units.Units if u.UnitType != "LENGTHUNIT"] + [angle]

    site = read_ifc_site(_edited(house, tmp_path / "unitless.ifc", drop_length_unit), IfcOptions(storey="1"))
    note = "no length unit in the model's IfcUnitAssignment: read as metres"
    assert all(note in z.notes for z in site.zones)
    assert not any(note in z.notes for z in read_ifc_site(house, IfcOptions(storey="1")).zones)


def test_a_zone_refused_by_the_site_model_names_the_file(tmp_path, house):
    # a space placed 7.9e15 m out: the zone's coordinate check named the zone and the vertex but not the file
    def move_living_room(model) -> None:
        space = next(s for s in model.by_type("IfcSpace") if "Living" in (s.LongName or s.Name))
        far = model.create_entity("IfcCartesianPoint", Coordinates=(7.9e18, 0.0, 0.0))  # millimetres
        space.ObjectPlacement.RelativePlacement.Location = far

    path = _edited(house, tmp_path / "far.ifc", move_living_room)
    with pytest.raises(
        InputError,
        match=r"far\.ifc: zone Living vertex 1: polygon = \(79\d{14}\.\d, .*"
        r"within \+-1e\+08 m",
    ):
        read_ifc_site(path, IfcOptions(storey="1"))
