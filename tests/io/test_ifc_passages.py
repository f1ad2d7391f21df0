"""Passages read from IFC (issue 46, "beyond walls"): unfilled wall openings one walks through, rooms open to
each other with no wall between, and the FZK-Haus's kitchen (open to the living room and the corridor) in the
building's one registration network.

The small model is written here with IfcOpenShell's API, in metres, one storey at elevation 0: rooms ``West``
(0..4 x 0..4) and ``East`` (4.2..8 x 0..4), 2.5 m high, a wall 4.0..4.2 x 0..4 between them; a room ``Nook``
(8..10 x 0..4) touches ``East`` with no wall. In the middle wall: an unfilled opening 1.0..2.0 (y) from the
floor to 2.1 m (its body 3.9..4.3, sticking out of both faces, as exporters write it), a high small one
2.4..2.9 from 1.2 to 1.8 m (a hatch), and a door 3.0..3.8 that fills its opening.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from planner.cli import main
from planner.core.errors import ExitCode
from planner.coverage.openings import PASSABLE, accessible_areas
from planner.io.ifc_in import IfcOptions, read_ifc_site
from planner.io.ifc_passages import MAX_SILL_M, MIN_HEIGHT_M
from tests.conftest import ROOT

FZK = ROOT / "instances" / "external" / "AC20-FZK-Haus.ifc"
Ring = list[tuple[float, float]]


def _box(x0: float, y0: float, x1: float, y1: float) -> Ring:
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def _write(path: Path) -> Path:
    import ifcopenshell.api
    import numpy as np
    from ifcopenshell.util.shape_builder import ShapeBuilder

    run = ifcopenshell.api.run
    f = run("project.create_file", version="IFC4")
    project = run("root.create_entity", f, ifc_class="IfcProject", name="passages")
    run("unit.assign_unit", f, units=[run("unit.add_si_unit", f, unit_type="LENGTHUNIT")])
    model = run("context.add_context", f, context_type="Model")
    body = run(
        "context.add_context",
        f,
        context_type="Model",
        context_identifier="Body",
        target_view="MODEL_VIEW",
        parent=model,
    )
    site = run("root.create_entity", f, ifc_class="IfcSite", name="Site")
    building = run("root.create_entity", f, ifc_class="IfcBuilding", name="B")
    run("aggregate.assign_object", f, products=[site], relating_object=project)
    run("aggregate.assign_object", f, products=[building], relating_object=site)
    storey = run("root.create_entity", f, ifc_class="IfcBuildingStorey", name="Ground")
    storey.Elevation = 0.0
    run("aggregate.assign_object", f, products=[storey], relating_object=building)
    builder = ShapeBuilder(f)

    def product(ifc_class: str, name: str, ring: Ring, height: float, z: float = 0.0) -> Any:
        e = run("root.create_entity", f, ifc_class=ifc_class, name=name)
        rep = builder.get_representation(body, [builder.extrude(builder.polyline(ring, closed=True), height)])
        run("geometry.assign_representation", f, product=e, representation=rep)
        matrix = np.eye(4)
        matrix[2, 3] = z
        run("geometry.edit_object_placement", f, product=e, matrix=matrix, is_si=True)
        return e

    for name, ring in (("West", _box(0, 0, 4, 4)), ("East", _box(4.2, 0, 8, 4)), ("Nook", _box(8, 0, 10, 4))):
        space = product("IfcSpace", name[:2].upper(), ring, 2.5)
        space.LongName = name
        run("aggregate.assign_object", f, products=[space], relating_object=storey)
    wall = product("IfcWall", "mid", _box(4.0, 0, 4.2, 4), 2.5)
    door = product("IfcDoor", "D1", _box(4.05, 3.0, 4.15, 3.8), 2.1)
    run("spatial.assign_container", f, products=[wall, door], relating_structure=storey)
    for name, ring, height, z in (
        ("walk-through", _box(3.9, 1.0, 4.3, 2.0), 2.1, 0.0),
        ("hatch", _box(3.9, 2.4, 4.3, 2.9), 0.6, 1.2),
        ("door-opening", _box(3.9, 3.0, 4.3, 3.8), 2.1, 0.0),
    ):
        opening = product("IfcOpeningElement", name, ring, height, z)
        run("feature.add_feature", f, feature=opening, element=wall)
        if name == "door-opening":
            run("feature.add_filling", f, opening=opening, element=door)
    f.write(str(path))
    return path


@pytest.fixture(scope="module")
def model(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _write(tmp_path_factory.mktemp("ifc") / "passages.ifc")


def _ops(site: Any, zone: str) -> list[tuple[float, float, str, str]]:
    z = site.zone(zone)
    return [(z.walls[o.wall - 1].start, o.s0_m, o.s1_m, o.kind, o.name) for o in z.openings]


def test_unfilled_floor_opening_is_a_passage_of_both_rooms_and_the_door_stays_a_door(model: Path) -> None:
    site = read_ifc_site(model)
    # West's east wall runs (4, 0) -> (4, 4): the walk-through at 1..2, the door at 3..3.8; no hatch
    assert _ops(site, "West") == [
        ((4.0, 0.0), 1.0, 2.0, "passage", "walk-through"),
        ((4.0, 0.0), 3.0, 3.8, "door", "D1"),
    ]
    # East's west wall runs (4.2, 4) -> (4.2, 0): the same two, measured from the other end
    east = [o for o in _ops(site, "East") if o[4] != "open to Nook"]
    assert sorted(east, key=lambda o: o[1]) == [
        ((4.2, 4.0), 0.2, 1.0, "door", "D1"),
        ((4.2, 4.0), 2.0, 3.0, "passage", "walk-through"),
    ]
    assert "passage" in PASSABLE
    assert MAX_SILL_M < 0.6 and MIN_HEIGHT_M == 1.8  # the hatch (1.2 m up, 0.6 m high) fails both


def test_rooms_that_touch_with_no_wall_are_open_to_each_other(model: Path) -> None:
    site = read_ifc_site(model)
    assert [o for o in _ops(site, "East") if o[4] == "open to Nook"] == [
        ((8.0, 0.0), 0.0, 4.0, "passage", "open to Nook")
    ]
    assert _ops(site, "Nook") == [((8.0, 4.0), 0.0, 4.0, "passage", "open to East")]
    areas = accessible_areas(site)
    assert areas[("in", "West")] == areas[("in", "East")] == areas[("in", "Nook")]


def test_the_model_plans_as_one_registration_group(model: Path, tmp_path: Path) -> None:
    assert main(["plan", str(model), "--quiet", "--out", str(tmp_path)]) == ExitCode.OK
    plan = json.loads((tmp_path / "plan.json").read_text())
    assert plan["registration"]["connected"] and len(plan["registration"]["components"]) == 1
    assert plan["verification"]["percent"] == 100.0


@pytest.mark.skipif(not FZK.is_file(), reason="AC20-FZK-Haus.ifc not present (not committed; docs/ifc.md)")
def test_fzk_haus_kitchen_is_open_to_the_living_room_and_the_corridor() -> None:
    site = read_ifc_site(FZK, IfcOptions(storey="all"))
    kitchen = {o.name for o in site.zone("Erdgeschoss/Küche").openings if o.kind == "passage"}
    assert kitchen == {"open to Wohnen", "open to Flur"}
    assert "open to Küche" in {o.name for o in site.zone("Erdgeschoss/Wohnen").openings}
    areas = accessible_areas(site)
    assert len(set(areas.values())) == 1  # the whole building: both storeys (the stair), every room
