"""What ``planner plan`` and ``planner network`` print is read by a person (issue 45, step 7): no Python reprs,
zones in the order of the site file, alike notes folded into one line with a count, and errors of a flag's
value that name the flag the user typed (not the field it sets) with the usage-error exit code."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from planner.cli import main
from planner.core.errors import ExitCode
from tests.cli.test_cli import assert_one_line_error
from tests.conftest import INSTANCES, ROOT

#: what a Python repr leaves in text: a dict or list literal, a quoted item in brackets, None/True/False as words
REPR = re.compile(r"\{'|\{\"|\[\s*['\"(\d{]|\b(None|True|False)\b")


def _zones_of_table(text: str, head: str) -> list[str]:
    """The zone column of the table whose header line starts with ``head`` (after its indent)."""
    lines = text.splitlines()
    start = next(k for k, line in enumerate(lines) if line.strip().startswith(head))
    rows = []
    for line in lines[start + 1 :]:
        if not line.startswith("  ") or line.startswith("   "):
            break
        rows.append(line.split()[0])
    return rows


@pytest.mark.slow
def test_polygon_b_summary_has_no_python_reprs(capsys: pytest.CaptureFixture[str]) -> None:
    # the Done-when line: no `{'` in the output of `planner plan instances/polygon_b.json`; the presolve's dict
    # was printed as it was ({'candidates_in': 1058, ...}); nor None/True/False or bracketed reprs anywhere
    assert main(["plan", str(INSTANCES / "polygon_b.json"), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "{'" not in out
    assert REPR.search(out) is None, REPR.search(out)
    # the presolve in words, and the labels that say what the numbers mean
    assert "presolve: candidates 1,058 -> " in out and "overlap links" in out
    assert "over the candidate pool (MILP)" in out and "over every position in the plane" in out
    assert "(solver alone, 1 thread)" in out and "registration: every registration group connected" in out
    # the verification is an aligned table: every row as long as the widest, numbers ending in one column
    table = out[out.index("verification at") :].splitlines()[1:3]
    assert table[0].split() == ["zone", "side", "points", "covered", "covered", "%"]
    assert len({len(line) for line in table}) == 1


def test_zones_print_in_the_order_of_the_site_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # house_doors.json lists house, R1, R2, R3; the greedy picks its stations in R1, R3, house, R2 order, which
    # the zone table followed before
    site = json.loads((INSTANCES / "house_doors.json").read_text())
    order = [z["id"] for z in site["zones"]]
    assert (
        main(["plan", str(INSTANCES / "house_doors.json"), "--method", "greedy", "--quiet", "--out", str(tmp_path)])
        == 0
    )
    out = capsys.readouterr().out
    picked = list(dict.fromkeys(s["zone"] for s in json.loads((tmp_path / "plan.json").read_text())["stations"]))
    assert picked != order  # else this test would check nothing
    assert _zones_of_table(out, "zone   side     stations") == order
    assert _zones_of_table(out, "zone   side     points") == order
    assert REPR.search(out) is None


def test_baalbek_datum_notes_fold_into_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # baalbek's 12 zones are 12 network parts, each with a datum note that differs only in its control points'
    # names: one line with the count instead of 12 (the stations: the recorded plan of tests/network/expected)
    recorded = json.loads((ROOT / "tests" / "network" / "expected" / "baalbek.json").read_text())
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"source": str(INSTANCES / "baalbek.json"), "stations": recorded["stations"]}))
    assert main(["network", str(INSTANCES / "baalbek.json"), str(plan), "--quiet"]) == 0
    out = capsys.readouterr().out
    datum = [line for line in out.splitlines() if line.startswith("  note: datum")]
    assert len(datum) == 1, datum
    assert datum[0].startswith("  note: datum of the network part holding CP1: CP1.1, CP1.2, CP1.3 held fixed")
    assert datum[0].endswith("(same for 12: CP1, CP2, CP3, CP4, CP5, ..., CP12)")
    assert REPR.search(out) is None


def test_a_negative_max_range_names_the_flag_and_the_value(capsys: pytest.CaptureFixture[str]) -> None:
    # it named the site parameter it sets (max_slant_range_m = -5, exit 3 as if the file were wrong)
    code = main(["plan", str(INSTANCES / "polygon_b.json"), "--max-range", "-5"])
    err = capsys.readouterr().err
    assert code == ExitCode.USAGE
    assert_one_line_error(err, "usage error: --max-range: -5 is not a slant range S_max in metres", "> 0")
    assert "max_slant_range_m" not in err and "polygon_b.json" not in err


@pytest.mark.parametrize(
    "argv, words",
    [
        # PlanOptions' own words were "k = 2: k > 1 needs method='milp' (method 'greedy' ...)"
        (["--method", "greedy", "--k", "2"], "--k: 2 needs --method milp (the greedy method covers each piece once)"),
        (["--overlap", "1.5"], "--overlap: 1.5 is not a registration overlap (expected a fraction in [0, 1)"),
        (["--set", "angular-tolerance=-1"], "--set angular-tolerance: -1 is not a closure tolerance"),
    ],
)
def test_other_bad_flags_are_named_as_typed(capsys: pytest.CaptureFixture[str], argv: list[str], words: str) -> None:
    code = main(["plan", str(INSTANCES / "polygon_b.json"), *argv])
    err = capsys.readouterr().err
    assert code == ExitCode.USAGE
    assert_one_line_error(err, words)
    assert "method='milp'" not in err and "angular_tolerance_deg" not in err
