"""Floors and ceilings from IFC spaces (issue 46): each space zone's floor level and ceiling, and the house
planned with its floors and ceilings.

The expected numbers come by hand from scripts/make/make_ifc_house.py, which wrote instances/house2.ifc:
``GROUND`` has elevation 0.0 m and rooms extruded 2.7 m, ``UPPER`` elevation 3.0 m (3000 mm: the file is in
millimetres) and rooms extruded 2.5 m; each space's solid stands at its storey's elevation (its placement's z),
so its base offset is 0 and its floor is at the elevation. The storeys have no placement of their own.
Floor areas (so verification points at 0.1 m, one per 0.01 m2): Hall 7.6 x 3.6 = 27.36 m2 less the stair
4.2 x 1.0 = 23.16 m2, Kitchen 3.7 x 3.8 = 14.06 m2, Living 43.61 m2 (the L less the 0.3 m column, which reaches
the ceiling), Bedroom 5.7 x 7.6 = 43.32 m2, Study 5.7 x 4.8 = 27.36 m2, Landing 5.7 x 2.6 less the stairwell
4.2 x 1.0 = 10.62 m2.
"""

from __future__ import annotations

import json
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest

from planner.cli import main
from planner.core.errors import ExitCode
from planner.engine import plan_site
from planner.io.ifc_in import IfcOptions, floor_level, read_ifc_site
from planner.site.model import SITE_FRAME, ScanSide
from tests.conftest import INSTANCES

HOUSE = INSTANCES / "house2.ifc"
#: storey -> (elevation m, room height m), from the generator's GROUND and UPPER
LEVELS = {"Ground floor": (0.0, 2.7), "Upper floor": (3.0, 2.5)}
#: floor (and ceiling) verification points at 0.1 m: area / 0.01 m2
POINTS = {
    "Ground floor/Hall": 2316,
    "Ground floor/Kitchen": 1406,
    "Ground floor/Living": 4361,
    "Upper floor/Bedroom": 4332,
    "Upper floor/Landing": 1062,
    "Upper floor/Study": 2736,
}


def test_every_space_has_its_storey_elevation_as_floor_and_its_height_as_ceiling() -> None:
    site = read_ifc_site(HOUSE, IfcOptions(storey="all", exterior=True))
    inside = [z for z in site.zones if z.scan_side is ScanSide.INSIDE]
    assert sorted(z.id for z in inside) == sorted(POINTS)
    for zone in inside:
        elevation, height = LEVELS[zone.frame]
        assert zone.id.startswith(zone.frame + "/")  # several storeys: one frame each
        assert zone.floor_level_m == pytest.approx(elevation, abs=1e-9), zone.id
        assert zone.ceiling_height_m == pytest.approx(height, abs=1e-9), zone.id
        assert set(zone.vertex_heights_m) == {height}  # the walls as before: the same height above the floor
    for name, (elevation, _) in LEVELS.items():
        ext = site.zone(f"{name}/exterior")
        assert ext.scan_side is ScanSide.OUTSIDE and ext.ceiling_height_m is None
        assert ext.floor_level_m == pytest.approx(elevation, abs=1e-9)


def test_one_storey_reads_into_the_site_frame_at_its_elevation() -> None:
    upper = read_ifc_site(HOUSE, IfcOptions(storey="Upper floor"))
    assert {(z.frame, z.floor_level_m, z.ceiling_height_m) for z in upper.zones} == {(SITE_FRAME, 3.0, 2.5)}
    ground = read_ifc_site(HOUSE, IfcOptions(storey="1"))
    assert {(z.frame, z.floor_level_m, z.ceiling_height_m) for z in ground.zones} == {(SITE_FRAME, 0.0, 2.7)}


def test_floor_level_adds_the_space_base_offset_to_the_storey_elevation() -> None:
    # storey at 3.0 m placed at 3.0 m: a space whose solid starts at 3.3 m stands 0.3 m higher
    assert floor_level(3.0, 3.0, 3.3) == 3.3
    # a storey placed at 0 whose spaces are modelled at 0: the elevation lifts them
    assert floor_level(3.0, 0.0, 0.0) == 3.0
    # a cellar: elevation -2.8 m, the space 0.15 m below its storey's base
    assert floor_level(-2.8, -2.8, -2.95) == pytest.approx(-2.95)


def _edited(out: Path, edit: Any) -> Path:
    import ifcopenshell

    model = ifcopenshell.open(str(HOUSE))
    edit(model)
    model.write(str(out))
    return out


def test_a_raised_space_and_a_placed_storey(tmp_path: Path) -> None:
    # the upper storey given a placement at 3000 mm (its spaces stay placed absolutely at 3000 mm: offset 0),
    # and the bedroom's solid raised by 300 mm: its floor at 3.3 m, its ceiling still 2.5 m above it
    def edit(model: Any) -> None:
        storey = next(s for s in model.by_type("IfcBuildingStorey") if s.Name == "Upper floor")
        point = model.create_entity("IfcCartesianPoint", Coordinates=(0.0, 0.0, 3000.0))
        axes = model.create_entity("IfcAxis2Placement3D", Location=point)
        storey.ObjectPlacement = model.create_entity("IfcLocalPlacement", RelativePlacement=axes)
        bed = next(s for s in model.by_type("IfcSpace") if s.LongName == "Bedroom")
        bed.ObjectPlacement.RelativePlacement.Location = model.create_entity(
            "IfcCartesianPoint", Coordinates=(0.0, 0.0, 3300.0)
        )

    site = read_ifc_site(_edited(tmp_path / "raised.ifc", edit), IfcOptions(storey="Upper floor"))
    assert site.zone("Bedroom").floor_level_m == pytest.approx(3.3)
    assert site.zone("Bedroom").ceiling_height_m == pytest.approx(2.5)
    assert site.zone("Study").floor_level_m == pytest.approx(3.0)


@pytest.mark.slow
def test_levels_leave_the_walls_only_plan_as_it_was() -> None:
    # the same site with the defaults (floor 0, no ceiling) plans the same stations: walls ignore the levels
    site = read_ifc_site(HOUSE, IfcOptions(storey="all"))
    flat = replace(site, zones=tuple(replace(z, floor_level_m=0.0, ceiling_height_m=None) for z in site.zones))
    a, b = plan_site(site), plan_site(flat)
    assert [(s.id, s.x, s.y) for s in a.stations] == [(s.id, s.x, s.y) for s in b.stations]
    assert a.verification.percent == b.verification.percent == 100.0


def _plan(args: list[str], out: Path) -> dict[str, Any]:
    assert main(["plan", str(HOUSE), "--storey", "all", *args, "--quiet", "--out", str(out)]) == ExitCode.OK
    return dict(json.loads((out / "plan.json").read_text()))


@pytest.mark.slow
def test_house_planned_with_floors_and_ceilings_verified_complete(tmp_path: Path, capsys: Any) -> None:
    walls = _plan([], tmp_path / "walls")
    t0 = time.perf_counter()
    full = _plan(["--surfaces", "walls,floors,ceilings", "--instrument-height", "1.5"], tmp_path / "full")
    took = time.perf_counter() - t0
    surf = full["surfaces"]
    assert surf["types"] == ["walls", "floors", "ceilings"] and surf["instrument_height_m"] == 1.5
    ver = surf["verification"]
    # patches no candidate sees are left out of the plan and counted NOT covered: complete only without them
    left = ver.get("left_out", {"count": 0, "area_m2": 0.0, "zones": []})
    assert ver["complete"] == (left["count"] == 0) == (ver["percent"] == 100.0)
    rows = {(r["zone"], r["type"]): r for r in ver["zones"]}
    assert set(rows) == {(z, t) for z in POINTS for t in ("floor", "ceiling")}
    for (zone, kind), row in rows.items():
        assert row["points"] == POINTS[zone], (zone, row)
        assert row["covered"] == row["points"] or f"{zone}/{kind}" in left["zones"], (zone, row)
    assert len(full["stations"]) >= len(walls["stations"])
    assert full["verification"]["percent"] == 100.0  # the walls too
    with capsys.disabled():  # measured, not asserted (docs/ifc.md)
        print(
            f"\nhouse2.ifc --storey all: walls {len(walls['stations'])} stations; walls, floors, ceilings "
            f"{len(full['stations'])} stations, {took:.1f} s, unseen patches {surf['unseen_patches']}"
        )
