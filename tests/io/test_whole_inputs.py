"""Each reader reads a file whole or refuses it in one line naming the file: the damage the fuzz harness
(tests/io/test_fuzz_inputs.py) draws at random, here one case each, as a surveyor meets it (a download cut short, a
line lost in an edit)."""

from __future__ import annotations

import contextlib
import io
import json
import re
from pathlib import Path
from typing import Any

import pytest

from planner.cli.main import main
from planner.core.errors import ExitCode
from tests.conftest import HEADER, INSTANCES

HOUSE = (INSTANCES / "house2.ifc").read_text()


def _refused(*argv: str) -> str:
    """The one line of a command refused with exit 3."""
    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        code = main(list(argv))
    lines = err.getvalue().strip().splitlines()
    assert code == 3 and len(lines) == 1, err.getvalue()
    return lines[0]


def _without(text: str, entity: str) -> str:
    """The IFC text without the instance line ``#N=...``."""
    return "".join(line for line in text.splitlines(keepends=True) if not line.startswith(f"{entity}="))


@pytest.mark.parametrize(
    "name, text, words",
    [
        ("cut.ifc", HOUSE[:10000], "the file ends before its end marker END-ISO-10303-21;"),
        ("noend.ifc", HOUSE.replace("END-ISO-10303-21;", ""), "END-ISO-10303-21;"),
        ("ref.ifc", _without(HOUSE, "#241"), "#247: #241 is referenced but not defined"),
        ("unknown.ifc", HOUSE.replace("=IFCEXTRUDEDAREASOLID(#241", "=IFCEXTRUDEDAREASOLXD(#241"), "could not read 1"),
        ("paren.ifc", HOUSE.replace("(#241,#245,#246,2100.);", "(#241,#245,#246,2100.;"), "#247: text = "),
        ("orphans.ifc", _without(HOUSE, "#289"), "IfcWall = 'W1': stands in no storey"),
        ("shape.ifc", HOUSE.replace("(#71,#75,#76,2700.)", "(#72,#75,#76,2700.)"), "#68: IfcWall = 'W1': IfcOpenShell"),
        ("nodata.ifc", HOUSE.replace("DATA;", "DATA_;", 1), "no HEADER; ... ENDSEC; DATA;"),
        ("quote.ifc", HOUSE.replace("'W1'", "'W1", 1), "not closed"),
    ],
)
def test_a_damaged_ifc_file_is_refused_before_ifcopenshell_reads_part_of_it(tmp_path, name, text, words):
    """IfcOpenShell reads each of these without a word: the entities before the cut or the broken parenthesis, a
    reference to a lost line as null, an unknown entity left out, walls in no storey left out of every room."""
    path = tmp_path / name
    path.write_text(text)
    line = _refused("validate", str(path))
    assert name in line and words in line, line


def _dxf_lines(tmp_path: Path) -> list[str]:
    import ezdxf

    doc = ezdxf.new("R2000")
    doc.header["$INSUNITS"] = 6
    doc.modelspace().add_lwpolyline(
        [(0, 0), (10, 0), (10, 6), (0, 6)], close=True, dxfattribs={"layer": "ZONES", "thickness": 3}
    )
    doc.saveas(tmp_path / "room.dxf")
    return (tmp_path / "room.dxf").read_text().splitlines()


def test_a_damaged_dxf_file_is_refused(tmp_path):
    lines = _dxf_lines(tmp_path)
    first_x = lines.index(" 10", lines.index("LWPOLYLINE"))
    cases = {
        "cut.dxf": (lines[: len(lines) // 2], "end marker (group 0 EOF)"),
        "odd.dxf": (lines[:first_x] + lines[first_x + 1 :], "not a group code"),
        "vertex.dxf": (lines[: first_x + 12] + lines[first_x + 16 :], "LWPOLYLINE has 3 vertices, its count"),
        "x.dxf": (lines[: first_x + 4] + lines[first_x + 6 :], "3 x values (group 10) and 4 y values"),
        "json.dxf": (['{"zones": []}'], "not a DXF file"),
    }
    for name, (text, words) in cases.items():
        (tmp_path / name).write_text("\n".join(text) + "\n")
        line = _refused("validate", str(tmp_path / name))
        assert name in line and "DXF" in line and words in line, line


def test_a_table_cut_mid_row_or_short_of_rows_is_refused(tmp_path):
    rows = [f"A,inside,{i},{length},3,90,3.05" for i, length in enumerate((10, 6, 10, 6), 1)]
    cut = tmp_path / "cut.csv"
    cut.write_text(HEADER + "\n".join(rows)[:-1])  # 3.05 cut to 3.0: a number still, but no line end
    line = _refused("validate", str(cut))
    assert re.search(r"cut\.csv: line 5: text = 'A,inside,4,6,3,90,3\.0': the last row has no line end", line), line
    short = tmp_path / "short.csv"
    short.write_text(HEADER + "\n".join(rows[:3]) + "\n")
    assert "misclosure" in _refused("validate", str(short))
    gap = tmp_path / "gap.csv"
    gap.write_text(HEADER + "\n".join(rows[:1] + rows[2:]) + "\n")
    assert "indices must run 1..3" in _refused("validate", str(gap))


def test_a_cut_json_is_one_line(tmp_path):
    for name in ("polygon_a.json", "courtyard.json"):
        path = tmp_path / name
        path.write_bytes((INSTANCES / name).read_bytes()[:300])
        line = _refused("validate", str(path))
        assert line.startswith(f"planner: error: {path}: line ") and "invalid JSON" in line, line


def test_observation_and_control_entries_of_the_wrong_kind_are_one_line(tmp_path):
    from planner.io.network_files import _observation, read_control

    coords = {"S1": (0.0, 0.0), "S2": (1.0, 0.0)}
    for obs, words in (
        ({"kind": "distance", "at": ["S1"], "to": "S2", "value": 1, "sigma": 0.01}, "at = 'list': must be a point"),
        ({"kind": "x", "at": "S1", "to": "S2", "value": 1, "sigma": 0.01}, "give no 'to'"),
        ({"kind": "x", "at": "S1", "value": 1, "sigma": 0.01, "sd": 1}, "sd = 1: unknown key"),
        ({"kind": ["x"], "at": "S1", "value": 1, "sigma": 0.01}, "kind = 'list': unknown kind"),
    ):
        with pytest.raises(Exception, match=re.escape(words)):
            _observation(obs, 1, coords, "obs.json")
    path = tmp_path / "control.json"
    path.write_text(json.dumps([{"name": {"id": 1}, "x": 1, "y": 2}]))
    with pytest.raises(Exception, match="name = 'dict': must be a text or a whole number"):
        read_control(str(path))


def test_the_ifc_text_check_reads_complex_instances_and_strings_with_semicolons(tmp_path):
    """``#N=(A()B())`` is a whole instance (ISO 10303-21's external mapping); a ; or # inside a text or a comment is
    no structure."""
    from planner.io.ifc_check import spf_instances

    head = "ISO-10303-21;\nHEADER;\nFILE_SCHEMA(('IFC4'));\nENDSEC;\nDATA;\n"
    path = tmp_path / "f.ifc"
    path.write_text(
        head + "#1=IFCWALL('a;b #9 (''',#2);\n#2=(IFCA() IFCB(#1));\n/* #7 ; */\nENDSEC;\nEND-ISO-10303-21;\n"
    )
    assert spf_instances(path) == {1: "IFCWALL", 2: "complex instance"}
    path.write_text(head + "#1=(IFCA() IFCB(#1);\nENDSEC;\nEND-ISO-10303-21;\n")
    with pytest.raises(Exception, match=r"f\.ifc: #1: .*not an entity instance"):
        spf_instances(path)


SOURCES = {
    "csv": INSTANCES / "polygon_b.csv",
    "json": INSTANCES / "polygon_a.json",
    "ifc": INSTANCES / "house2.ifc",
    "pol": INSTANCES.parent / "tests" / "data" / "agplib" / "random-20-1.pol",
}


@pytest.mark.parametrize("given", sorted(SOURCES))
@pytest.mark.parametrize("suffix", [".json", ".csv", ".dxf", ".geojson", ".pol", ".ifc"])
def test_a_file_under_another_format_s_suffix_is_refused_in_one_line(tmp_path, given, suffix):
    """A wrong suffix: the reader of the suffix refuses what it finds, naming the file (never exit 0, 1 or 2)."""
    if "." + given == suffix:
        pytest.skip("the file's own suffix")
    path = tmp_path / f"site{suffix}"
    path.write_bytes(SOURCES[given].read_bytes())
    assert path.name in _refused("validate", str(path))


def test_a_space_in_the_building_but_in_no_storey_is_refused(tmp_path):
    """The reader plans the spaces of storeys: a space aggregated elsewhere was left out of the site without a word."""
    path = tmp_path / "building.ifc"
    path.write_text(re.sub(r"(#17=IFCRELAGGREGATES\(.*?),#14,\(#16", r"\1,#11,(#16", HOUSE))
    line = _refused("validate", str(path))
    assert "building.ifc: #16: IfcSpace = 'Living': the space stands in IfcBuilding" in line, line


def test_a_storey_whose_walls_are_missing_is_refused(tmp_path: Path, capsys: Any) -> None:
    """Spaces with no IfcWall in their storey (walls not exported, or contained in the building only) would read as
    one open plan, every room open to the next: refused, naming the storey."""
    import ifcopenshell
    import ifcopenshell.api

    model = ifcopenshell.open(str(INSTANCES / "house2.ifc"))
    for wall in model.by_type("IfcWall"):
        ifcopenshell.api.run("root.remove_product", model, product=wall)
    path = tmp_path / "no_walls.ifc"
    model.write(str(path))
    assert main(["validate", str(path)]) == ExitCode.INVALID_INPUT
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no_walls.ifc" in err
    assert "storey = 'Ground floor'" in err and "no IfcWall" in err
