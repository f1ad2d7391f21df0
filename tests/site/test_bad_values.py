"""Bad values in otherwise well-formed inputs (docs/hard-inputs.md): JSON the parser chokes on, keys given
twice, absurd parameters and coordinates, numbers that were silently rounded. Each is a one-line error,
exit 3, naming the file and where the value is; none is an internal error (exit 1) or a silent fix."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from planner.cli import main
from tests.cli.test_cli import assert_one_line_error
from tests.conftest import HEADER

SQUARE = {"id": "court", "scan_side": "inside", "coordinates": [[0, 0], [20, 0], [20, 10], [0, 10]], "height_m": 5}
ZONE_TEXT = json.dumps(SQUARE)
#: a 5000-digit height, a 400-digit coordinate: the error names the line and column where the number starts
DIGITS = '{"zones": [' + ZONE_TEXT.replace('"height_m": 5', '"height_m": ' + "9" * 5000) + "]}"
FAR = '{"zones": [' + ZONE_TEXT.replace("[20, 0]", "[" + "9" * 400 + ", 0]") + "]}"


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def site(tmp_path: Path, name: str = "site.json", zone: dict | None = None, **extra) -> Path:
    return write(tmp_path, name, json.dumps({"zones": [zone or SQUARE], **extra}))


def cli(capsys, *argv: str) -> tuple[int, str]:
    code = main(list(argv))
    return code, capsys.readouterr().err


def refused(capsys, fragments: tuple[str, ...], *argv: str, exit_code: int = 3) -> None:
    """``planner *argv`` fails with ``exit_code`` (3: invalid input) and one line holding every fragment."""
    code, err = cli(capsys, *argv)
    assert code == exit_code, err
    assert_one_line_error(err, *fragments)


@pytest.mark.parametrize(
    "name, text, fragments",
    [
        # nesting past Python's recursion limit: a RecursionError (exit 1) before; now located
        ("deep.json", "[" * 100000 + "]" * 100000, ("line 1 column 101", "invalid JSON: nested too deeply")),
        # a 5000-digit height: json's int() stopped at 4300 digits with a ValueError (exit 1)
        (
            "digits.json",
            DIGITS,
            (f"line 1 column {DIGITS.index('9') + 1}:", "(5000 digits)", "invalid JSON: number out of range"),
        ),
        # a 400-digit coordinate: an int no float holds, an OverflowError (exit 1) when converted
        (
            "far.json",
            FAR,
            (f"line 1 column {FAR.index('9') + 1}:", "(400 digits)", "invalid JSON: number out of range"),
        ),
        # a lone surrogate: read, then a UnicodeEncodeError (exit 1) when the summary was printed
        (
            "surrogate.json",
            '{"name": "\\ud800", "zones": [' + ZONE_TEXT + "]}",
            ("name = '\\ud800'", "not valid Unicode"),
        ),
        (
            "surrogate_id.json",
            '{"zones": [' + ZONE_TEXT.replace('"court"', '"c\\udc00"') + "]}",
            ("zones[1].id", "not valid Unicode"),
        ),
    ],
)
def test_json_the_parser_chokes_on_is_a_one_line_error(tmp_path, capsys, name, text, fragments):
    path = write(tmp_path, name, text)
    refused(capsys, (name, *fragments), "validate", str(path))


def test_a_lone_surrogate_is_refused_by_plan_too_and_a_pair_is_read(tmp_path, capsys):
    # plan printed its summary with the surrogate: UnicodeEncodeError, exit 1; a pair (one emoji) is text
    bad = write(tmp_path, "s.json", '{"name": "\\ud800", "zones": [' + ZONE_TEXT + "]}")
    refused(capsys, ("s.json", "not valid Unicode"), "plan", str(bad), "--method", "greedy", "--out", str(tmp_path))
    good = write(tmp_path, "ok.json", '{"name": "\\ud83d\\ude00 \\\\ud800", "zones": [' + ZONE_TEXT + "]}")
    assert cli(capsys, "validate", str(good))[0] == 0


def test_a_csv_cell_over_the_field_limit_is_a_one_line_error(tmp_path, capsys):
    # the csv module's "field larger than field limit (131072)" was an internal error (exit 1)
    path = write(tmp_path, "big.csv", HEADER + "A,inside,1," + "1" * 140000 + ",5,90,5\n")
    refused(capsys, ("big.csv", "line 2", "field larger than field limit (131072)"), "validate", str(path))


def test_a_key_given_twice_is_refused_with_both_values(tmp_path, capsys):
    # json keeps the last of two equal keys: theta_max 60 was dropped silently for 68
    path = write(
        tmp_path, "dup.json", '{"parameters": {"theta_max_deg": 60, "theta_max_deg": 68}, "zones": [' + ZONE_TEXT + "]}"
    )
    refused(capsys, ("dup.json", "theta_max_deg", "key given twice in one object (60 and 68)"), "validate", str(path))


@pytest.mark.parametrize(
    "parameters, fragment",
    [
        # each was accepted by validate, and overflowed (OverflowError, exit 1) or ran with no range limit in plan
        ({"max_slant_range_m": 1e300}, "max_slant_range_m = 1e+300: must be > 0 and <= 10000 m"),
        ({"sigma_req_m": 1e300}, "sigma_req_m = 1e+300: must be > 0 and <= 1 m"),
        ({"sigma_0_m": 1e300}, "sigma_0_m = 1e+300: must be a finite number >= 0 and <= 1 m"),
        ({"instrument_height_span_m": 1e300}, "instrument_height_span_m = 1e+300: must be >= 0 and <= 10000 m"),
    ],
)
def test_huge_parameters_are_refused_naming_the_field(tmp_path, capsys, parameters, fragment):
    path = site(tmp_path, parameters=parameters)
    refused(capsys, ("site.json", fragment), "validate", str(path))


def test_huge_command_line_parameters_go_through_the_same_check(tmp_path, capsys):
    # --max-range 1e300 overflowed in planning (exit 1); the bound itself (10 km) is accepted; the value came
    # from the command line, so the usage error (exit 2) names the flag, not the site parameter it sets
    path = site(tmp_path)
    refused(
        capsys,
        ("--max-range: 1e+300 is not a slant range S_max in metres (expected > 0 and <= 10000 m)",),
        "plan",
        str(path),
        "--method",
        "greedy",
        "--max-range",
        "1e300",
        "--out",
        str(tmp_path),
        exit_code=2,
    )
    fragment = ("--sigma-req: 1e+300 is not a required accuracy",)
    refused(capsys, fragment, "validate", str(path), "--sigma-req", "1e300", exit_code=2)
    assert cli(capsys, "validate", str(path), "--max-range", "10000")[0] == 0


@pytest.mark.parametrize("index", [1.9, "2"])
def test_a_table_index_that_is_no_whole_number_is_refused(tmp_path, capsys, index):
    # "index": 1.9 was read as 1 (and this table then ran 1..4); the CSV reader refuses 1.9 already
    rows = [
        {"index": k, "side_length_m": 10, "wall_height_m": 5, "interior_angle_deg": 90, "vertex_height_m": 5}
        for k in (index, 2, 3, 4)
    ]
    path = site(tmp_path, zone={"id": "T", "scan_side": "inside", "table": rows})
    refused(capsys, ("site.json", "zone T row 1", f"index = {index!r}: must be a whole number"), "validate", str(path))


def test_a_correction_of_vertex_1_point_7_is_refused(tmp_path, capsys):
    # the correction applied to vertex 1 before (printed 91 -> 90 there); "vertex": 1.0 still names vertex 1
    rows = [
        {
            "index": k,
            "side_length_m": 10,
            "wall_height_m": 5,
            "interior_angle_deg": 91 if k == 1 else 90,
            "vertex_height_m": 5,
        }
        for k in range(1, 5)
    ]
    correction = {"zone": "T", "field": "interior_angle_deg", "printed": 91, "corrected": 90, "reason": "misprint"}
    zone = {"id": "T", "scan_side": "inside", "table": rows}
    path = site(tmp_path, zone=zone, corrections=[{**correction, "vertex": 1.7}])
    refused(capsys, ("site.json", "corrections[1]", "vertex = 1.7: must be a whole number"), "validate", str(path))
    path = site(tmp_path, "whole.json", zone=zone, corrections=[{**correction, "vertex": 1.0}])
    assert cli(capsys, "validate", str(path))[0] == 0


@pytest.mark.parametrize("scale", ["1:2_0", "1:5 0", "1:5e1", "1:٥٠"])
def test_a_drawing_scale_takes_plain_digits_only(tmp_path, capsys, scale):
    # these were read as 1:20, 1:50, 1:50 and 1:50 (spaces dropped, then float()); CSV and JSON refuse 3_0
    path = site(tmp_path, parameters={"drawing_scale": scale})
    refused(capsys, ("site.json", f"drawing_scale = {scale!r}: not a drawing scale like 1:50"), "validate", str(path))
    # given by --scale it is a usage error naming the flag
    code, err = cli(capsys, "validate", str(site(tmp_path, "plain.json")), "--scale", scale)
    assert code == 2
    assert_one_line_error(err, f"--scale: {scale} is not a drawing scale like 1:50")


@pytest.mark.parametrize("scale", ["1:50", " 1 : 50 ", "50", "1:50.0"])
def test_a_drawing_scale_written_plainly_is_read(tmp_path, capsys, scale):
    code = main(["validate", str(site(tmp_path)), "--scale", scale])
    assert code == 0 and "(drawing scale 1:50)" in capsys.readouterr().out


@pytest.mark.parametrize("heights, wall, value", [([-3, 5, 5, 5], 1, "-3"), ([5, 5, 5, 0], 4, "0")])
def test_a_wall_height_of_a_coordinate_zone_must_be_a_height(tmp_path, capsys, heights, wall, value):
    # -3 and 0 were accepted with a note ("printed -3") while a table row's wall_height_m 0 is refused
    path = site(tmp_path, zone={**SQUARE, "wall_heights_m": heights})
    refused(
        capsys,
        ("site.json", f"zone court wall {wall}", f"wall_heights_m = {value}: must be a height > 0"),
        "validate",
        str(path),
    )


def test_control_points_beyond_the_coordinate_limit_are_refused(tmp_path, capsys):
    # x = 1e12 was accepted (zones are limited to +-1e8 m), in the instance and in a --control file
    path = site(tmp_path, control_points=[{"name": "F", "x": 1e12, "y": 0}])
    refused(
        capsys,
        ("site.json", "control point F", "x = 1e+12: must be a finite number within +-1e+08 m"),
        "validate",
        str(path),
    )
    control = write(tmp_path, "control.json", json.dumps([{"name": "F", "x": 5, "y": -1e12}]))
    plan = write(
        tmp_path,
        "plan.json",
        json.dumps({"stations": [{"id": "S", "zone": "court", "side": "inside", "x": 5, "y": 5}]}),
    )
    refused(
        capsys,
        ("control.json", "control point F", "y = -1e+12: must be a finite number within +-1e+08 m"),
        "network",
        str(site(tmp_path, "plain.json")),
        str(plan),
        "--control",
        str(control),
    )
