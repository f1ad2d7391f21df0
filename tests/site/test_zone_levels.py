"""A zone's floor level and ceiling height (issue 46): defaults that change nothing, the JSON keys, the checks
that name the field and value, and the round trips (validate --json, assemble --out)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from planner.cli import main
from planner.core.errors import InputError
from planner.io.load import load_site
from planner.site.model import Zone
from tests.conftest import square_rows

RECT = ((0.0, 0.0), (10.0, 0.0), (10.0, 6.0), (0.0, 6.0))
ROW = {"wall_height_m": 5, "interior_angle_deg": 90, "vertex_height_m": 5}


def table_zone(zone_id: str, a: float, b: float, **levels: object) -> dict:
    """An inline table zone, a x b, with the level keys given."""
    rows = [dict(ROW, side_length_m=s) for s in (a, b, a, b)]
    return {"id": zone_id, "scan_side": "inside", **levels, "table": rows}


def coordinate_zone(**levels: object) -> dict:
    return {"id": "hall", "scan_side": "inside", "coordinates": [list(v) for v in RECT], "height_m": 5, **levels}


def write(tmp_path: Path, *zones: dict, name: str = "site.json") -> Path:
    path = tmp_path / name
    path.write_text(json.dumps({"zones": list(zones)}))
    return path


def test_defaults_are_a_floor_at_zero_and_no_ceiling(write_csv):
    z = Zone("R", "inside", RECT, (5.0,) * 4)
    assert (z.floor_level_m, z.ceiling_height_m) == (0.0, None)
    site = load_site(write_csv(square_rows()))  # a table CSV: floor at 0, no ceiling
    assert [(z.floor_level_m, z.ceiling_height_m) for z in site.zones] == [(0.0, None)]


def test_json_coordinate_and_inline_table_zones_read_the_levels(tmp_path):
    path = write(
        tmp_path,
        coordinate_zone(floor_level_m=-2.5, ceiling_height_m=4),  # a cellar 2.5 m down, 4 m high
        table_zone("room", 8, 5, ceiling_height_m=3.2),
        table_zone("ruin", 6, 6, ceiling_height_m=None),  # null: no ceiling (an open ruin)
    )
    site = load_site(path)
    assert [(z.floor_level_m, z.ceiling_height_m) for z in site.zones] == [(-2.5, 4.0), (0.0, 3.2), (0.0, None)]


@pytest.mark.parametrize(
    "levels, shown",
    [
        ({"ceiling_height_m": 0}, "ceiling_height_m = 0"),
        ({"ceiling_height_m": -3}, "ceiling_height_m = -3"),
        ({"ceiling_height_m": 1e5}, "ceiling_height_m = 100000"),
        ({"floor_level_m": 2e4}, "floor_level_m = 20000"),
        ({"floor_level_m": "low"}, "floor_level_m"),
    ],
)
def test_a_bad_level_in_json_names_file_zone_field_and_value(tmp_path, levels, shown):
    path = write(tmp_path, coordinate_zone(**levels))
    with pytest.raises(InputError) as err:
        load_site(path)
    line = str(err.value)
    assert "\n" not in line and str(path) in line and "hall" in line and shown in line, line


@pytest.mark.parametrize(
    "field, value",
    [
        ("floor_level_m", math.nan),
        ("floor_level_m", math.inf),
        ("floor_level_m", True),
        ("ceiling_height_m", -0.1),
        ("ceiling_height_m", math.inf),
        ("ceiling_height_m", False),
    ],
)
def test_the_zone_refuses_a_bad_level(field, value):
    with pytest.raises(InputError, match=rf"zone R.*{field}"):
        Zone("R", "inside", RECT, (5.0,) * 4, **{field: value})


def test_unknown_keys_are_still_refused(tmp_path, write_csv):
    with pytest.raises(InputError, match=r"ceiling_m.*unknown key in zones entry"):
        load_site(write(tmp_path, coordinate_zone(ceiling_m=3)))
    csv = write_csv(square_rows())
    entry = {"table_csv": csv.name, "ceiling_height_m": 3}  # a CSV entry takes no levels (its zones: defaults)
    with pytest.raises(InputError, match=r"ceiling_height_m.*unknown key in zones entry"):
        load_site(write(tmp_path, entry))


def test_validate_json_shows_levels_only_where_not_default(tmp_path, capsys):
    path = write(tmp_path, coordinate_zone(floor_level_m=1.25, ceiling_height_m=3), table_zone("room", 8, 5))
    assert main(["validate", str(path), "--json"]) == 0
    zones = {z["id"]: z for z in json.loads(capsys.readouterr().out)["zones"]}
    assert (zones["hall"]["floor_level_m"], zones["hall"]["ceiling_height_m"]) == (1.25, 3.0)
    assert "floor_level_m" not in zones["room"] and "ceiling_height_m" not in zones["room"]


def test_assemble_out_keeps_the_levels(tmp_path, capsys):
    path = write(tmp_path, table_zone("A", 10, 6, floor_level_m=-1.5, ceiling_height_m=4), table_zone("B", 6, 6))
    out = tmp_path / "assembled.json"
    assert main(["assemble", str(path), "--out", str(out)]) == 0
    capsys.readouterr()
    site = load_site(out)
    assert {z.id: (z.floor_level_m, z.ceiling_height_m) for z in site.zones} == {"A": (-1.5, 4.0), "B": (0.0, None)}
    written = json.loads(out.read_text())["zones"]
    assert "floor_level_m" not in written[1] and "ceiling_height_m" not in written[1]  # defaults not written
