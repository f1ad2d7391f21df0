"""A file of another kind than the command reads there: one line naming the file, what it is and what was expected,
exit 2 (a missing file: exit 3), before any reader runs; and what :func:`planner.io.file_kind.file_kind` tells."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from planner.cli import main
from planner.core.errors import ExitCode, InputError
from planner.io import file_kind as fk
from planner.io.file_kind import EXPECTED, KINDS, file_kind
from tests.conftest import INSTANCES

SITE = INSTANCES / "polygon_b.json"
SITE_WORDS = "expects a site file"
PLAN_WORDS = "expects a plan.json written by `planner plan --out DIR`"


@pytest.fixture
def files(tmp_path: Path) -> dict[str, Path]:
    """One small file of each kind the commands read (a plan by its keys: none of these is planned)."""
    made = {
        "plan.json": {"instance": "polygon_b", "method": "greedy", "zones": [], "stations": []},
        "network.json": {"nodes": [], "edges": [], "stations": {}, "network_rms_m": 0.0},
        "field.json": {"instance": "polygon_b", "mode": "registration", "order": [], "route_length_m": 0.0},
        "control.json": [{"name": "P1", "x": 0, "y": 0}],
        "observations.json": {"angle_unit": "deg", "observations": []},
        "traverse.json": {"points": [], "legs": []},
    }
    out = {}
    for name, data in made.items():
        out[name] = tmp_path / name
        out[name].write_text(json.dumps(data))
    return out


def _refused(capsys, argv: list[str], code: int = ExitCode.USAGE) -> str:
    assert main([*argv, "--quiet"] if argv[0] != "assemble" else argv) == code, argv
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


def test_a_plan_where_a_site_belongs(capsys, files):
    plan = str(files["plan.json"])
    for argv in (
        ["validate", plan],
        ["plan", plan],
        ["export", plan],
        ["verify", plan, plan],
        ["network", plan, plan],
        ["chain", plan, plan],
        ["assemble", plan],
        ["report", plan, "--site", plan],
        ["field", plan, "--site", plan],
    ):
        line = _refused(capsys, argv)
        assert f"{plan} is a plan; planner {argv[0]}" in line and SITE_WORDS in line, line
    line = _refused(capsys, ["verify", plan, str(SITE)])  # the two swapped
    assert "the site comes first: planner verify SITE PLAN" in line


def test_a_site_where_a_plan_belongs(capsys):
    for argv in (
        ["report", str(SITE)],
        ["field", str(SITE)],
        ["verify", str(SITE), str(SITE)],
        ["network", str(SITE), str(SITE)],
        ["chain", str(SITE), str(SITE)],
        ["report", str(INSTANCES / "polygon_b.csv")],
    ):
        line = _refused(capsys, argv)
        assert f"{argv[1]} is a site file; planner {argv[0]} {PLAN_WORDS}" in line, line
    # the message the report gave before named the site's "source" text as if it were a path
    assert "plan it first: planner plan" in _refused(capsys, ["report", str(SITE)])


def test_other_outputs_and_inputs_in_the_wrong_place(capsys, files):
    plan = str(files["plan.json"])
    cases = [
        (["plan", str(files["network.json"])], "is a network report", SITE_WORDS),
        (["report", str(files["field.json"])], "is a field sheet", PLAN_WORDS),
        (["validate", str(files["control.json"])], "is a list of control points", SITE_WORDS),
        (["network", str(SITE), plan, "--control", str(SITE)], "is a site file", "planner network --control expects"),
        (["plan", str(SITE), "--control", plan], "is a plan", "planner plan --control expects control points"),
        (["network", str(SITE), plan, "--observations", plan], "is a plan", "--observations expects field obs"),
        (["network", str(SITE), plan, "--traverse", str(files["control.json"])], "control points", "expects a trav"),
        (["field", str(files["traverse.json"])], "is a traverse", PLAN_WORDS),
        (["plan", str(files["observations.json"])], "is a file of field observations", SITE_WORDS),
    ]
    for argv, given, expected in cases:
        line = _refused(capsys, argv)
        assert given in line and expected in line, line


def test_empty_folder_and_missing_paths(capsys, tmp_path):
    line = _refused(capsys, ["plan", ""])
    assert "the site path is empty" in line and SITE_WORDS in line
    line = _refused(capsys, ["report", str(tmp_path)])
    assert f"{tmp_path} is a folder; planner report {PLAN_WORDS}" in line
    missing = tmp_path / "missing.json"
    line = _refused(capsys, ["validate", str(missing)], ExitCode.INVALID_INPUT)
    assert str(missing) in line and "cannot read file" in line
    line = _refused(capsys, ["field", str(missing)], ExitCode.INVALID_INPUT)
    assert str(missing) in line


def test_an_invalid_small_json_is_refused_by_the_check(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"zones": [')
    with pytest.raises(InputError, match=r"bad.json: line 1 column 12: invalid JSON"):
        file_kind(bad)


def test_file_kind_by_suffix_and_content(tmp_path, files):
    assert file_kind(SITE) == "site" and file_kind(INSTANCES / "polygon_b.csv") == "site"
    assert file_kind(INSTANCES / "house2.ifc") == "site"
    for name, kind in (
        ("plan.json", "plan"),
        ("network.json", "network report"),
        ("field.json", "field sheet"),
        ("control.json", "control"),
        ("observations.json", "observations"),
        ("traverse.json", "traverse"),
    ):
        assert file_kind(files[name]) == kind, name
    (tmp_path / "stations.csv").write_text("# tls-planner station list: x (greedy, 1 stations)\nID,X,Y,Z\nS1,0,0,0\n")
    (tmp_path / "field.csv").write_text("no.,station,x m,y m\n1,S1,0,0\n")
    (tmp_path / "field.geojson").write_text(json.dumps({"type": "FeatureCollection", "frame": "site", "features": []}))
    (tmp_path / "plan.geojson").write_text(json.dumps({"type": "FeatureCollection", "planner": {}, "features": []}))
    (tmp_path / "odd.txt").write_text("x")
    (tmp_path / "list.json").write_text("[1, 2]")
    assert [
        file_kind(tmp_path / n)
        for n in ("stations.csv", "field.csv", "field.geojson", "plan.geojson", "odd.txt", "list.json")
    ] == ["station list", "field sheet", "field sheet", "site", "unknown", "unknown"]
    assert file_kind(tmp_path) == "folder"
    assert set(EXPECTED) <= set(KINDS)


def test_a_large_json_is_judged_from_its_head(tmp_path, monkeypatch):
    """Past HEAD_BYTES only the head is scanned: nested keys and keys in strings do not count."""
    monkeypatch.setattr(fk, "HEAD_BYTES", 256)
    big, tail = tmp_path / "big.json", {"log": "x" * 1000}
    big.write_text(
        json.dumps({"instance": "x", "note": 'a "zones": b', "parameters": {"zones": 1}, "method": "g"} | tail)
    )
    assert file_kind(big) == "plan"
    big.write_text(json.dumps({"parameters": {"stations": 1, "method": 2}, "format": "tls-planner/1"} | tail))
    assert file_kind(big) == "site"
    big.write_text(json.dumps([{"name": "P1", "x": 0, "y": 0}] * 100))
    assert file_kind(big) == "control"
    big.write_text("{" * 300)  # invalid, and too big to be parsed here: left to the reader
    assert file_kind(big) == "unknown"


def test_the_site_suffixes_are_the_readers():
    from planner.io.load import READERS

    assert fk.SITE_SUFFIXES == READERS
