"""The command line: exit codes and one-line errors naming file, zone/row and value."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from planner.cli import main
from tests.conftest import INSTANCES, ROOT, square_rows


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def assert_one_line_error(err: str, *fragments: str) -> None:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for f in fragments:
        assert f in lines[0], (f, lines[0])


def test_validate_baalbek_lists_corrections_and_closures(capsys):
    code, out, _ = run(capsys, "validate", str(INSTANCES / "baalbek.json"))
    assert code == 0
    for zone in ["Z1", "Z6", "Z11", "outline"]:
        assert f"\n{zone} " in out
    assert "corrections applied: 3" in out and "misclosures accepted: 1" in out
    assert "outline vertex 18 interior_angle_deg: printed 0 -> 90.676" in out
    assert "Z3 vertex 6 interior_angle_deg: printed 128.929 -> 252.366" in out
    assert "S_max 95.913 m" in out and "1:50,247" in out  # outline closes to 16 mm


def test_validate_json_output(capsys):
    code, out, _ = run(capsys, "validate", str(INSTANCES / "polygon_b.json"), "--json")
    data = json.loads(out)
    assert code == 0 and data["zones"][0]["id"] == "B" and len(data["zones"][0]["polygon"]) == 5
    assert data["parameters"]["max_slant_range_m"] == 95.913


def test_non_closing_csv_exits_3_naming_zone_and_misclosure(capsys, write_csv):
    rows = square_rows("R")
    rows[2] = ("R", "inside", 3, 10.0, 5.0, 95.0, 5.0)  # angles sum to 365
    code, _, err = run(capsys, "validate", str(write_csv(rows)))
    assert code == 3
    assert_one_line_error(err, "site.csv", "zone R", "angular misclosure +5.000 deg")


def test_linear_misclosure_exits_3(capsys, write_csv):
    rows = square_rows("R")
    rows[0] = ("R", "inside", 1, 10.5, 5.0, 90, 5.0)
    code, _, err = run(capsys, "validate", str(write_csv(rows)))
    assert code == 3
    assert_one_line_error(err, "zone R", "linear misclosure 0.500 m", "1:81")


@pytest.mark.parametrize(
    "row, fragment",
    [
        (("R", "inside", 2, 0, 5, 90, 5), "zone R row 2: side_length_m = 0"),
        (("R", "inside", 2, -10, 5, 90, 5), "side_length_m = -10"),
        (("R", "inside", 2, 10, -5, 90, 5), "wall_height_m = -5"),
        (("R", "inside", 2, 10, 5, 90, 0), "vertex_height_m = 0"),
        (("R", "inside", 2, 10, 5, 360, 5), "interior_angle_deg = 360: outside (0, 360)"),
        (("R", "inside", 2, 10, 5, 0, 5), "interior_angle_deg = 0"),
        (("R", "inside", 2, "nan", 5, 90, 5), "line 3: side_length_m = 'nan': must be finite"),
        (("R", "inside", 2, 10, "inf", 90, 5), "wall_height_m = 'inf': must be finite"),
        (("R", "inside", 2, 10, 5, "ninety", 5), "interior_angle_deg = 'ninety': not a number"),
        (("R", "sideways", 2, 10, 5, 90, 5), "scan_side = 'sideways'"),
    ],
)
def test_bad_values_exit_3(capsys, write_csv, row, fragment):
    rows = square_rows("R")
    rows[1] = row
    code, _, err = run(capsys, "validate", str(write_csv(rows)))
    assert code == 3
    assert_one_line_error(err, "site.csv", fragment)


def test_missing_and_unknown_columns(capsys, write_csv):
    header = "zone,scan_side,index,side_length_m,wall_height_m,interior_angle_deg\n"
    code, _, err = run(capsys, "validate", str(write_csv([r[:6] for r in square_rows()], header=header)))
    assert code == 3
    assert_one_line_error(err, "line 1: vertex_height_m: missing column")
    header = "zone,scan_side,index,side_length_m,wall_height_m,interior_angle_deg,vertex_height_m,colour\n"
    code, _, err = run(capsys, "validate", str(write_csv([r + ("red",) for r in square_rows()], header=header)))
    assert code == 3
    assert_one_line_error(err, "colour: unknown column")


def test_empty_file(capsys, tmp_path):
    for name in ("empty.csv", "empty.json"):
        (tmp_path / name).write_text("  \n")
        code, _, err = run(capsys, "validate", str(tmp_path / name))
        assert code == 3
        assert_one_line_error(err, name, "empty file")


def test_self_intersecting_zone_says_where(capsys, tmp_path):
    inst = {
        "zones": [
            {"id": "bow", "scan_side": "inside", "coordinates": [[0, 0], [10, 10], [10, 0], [0, 10]], "height_m": 5}
        ]
    }
    (tmp_path / "bow.json").write_text(json.dumps(inst))
    code, _, err = run(capsys, "validate", str(tmp_path / "bow.json"))
    assert code == 3
    assert_one_line_error(err, "bow.json", "zone bow", "sides 1 and 3 meet at (5.000, 5.000)")


def test_accuracy_below_non_instrument_errors_exits_4(capsys):
    # sqrt(3 * 0.5^2) = 0.866 mm > 0.8 mm
    code, _, err = run(capsys, "validate", str(INSTANCES / "polygon_a.json"), "--sigma-req", "0.0008")
    assert code == 4
    assert_one_line_error(err, "polygon_a.json", "sigma_req_mm = 0.8", "no instrument error budget left")


def test_unknown_instrument_is_a_usage_error_naming_the_flag(capsys):
    # the name came from the command line, not from the site file: --instrument is named, not the file
    code, _, err = run(capsys, "validate", str(INSTANCES / "polygon_a.json"), "--instrument", "riegl-x")
    assert code == 2
    assert_one_line_error(
        err, "usage error: --instrument: riegl-x is no instrument model", "known: dissertation-tables"
    )
    assert "polygon_a.json" not in err


@pytest.mark.parametrize("value", ["90", "0", "-5", "120"])
def test_theta_max_outside_0_90_is_a_usage_error_naming_the_flag(capsys, value):
    code, _, err = run(capsys, "validate", str(INSTANCES / "polygon_a.json"), "--theta-max", value)
    assert code == 2
    assert_one_line_error(err, f"--theta-max: {float(value):g} is not an incidence angle limit", "(0, 90)")
    assert "theta_max_deg" not in err


def test_theta_max_in_instance_file_names_the_file(capsys, tmp_path):
    inst = json.loads((INSTANCES / "polygon_a.json").read_text())
    inst["parameters"]["theta_max_deg"] = 95
    (tmp_path / "polygon_a.csv").write_text((INSTANCES / "polygon_a.csv").read_text())
    (tmp_path / "a.json").write_text(json.dumps(inst))
    code, _, err = run(capsys, "validate", str(tmp_path / "a.json"))
    assert code == 3
    assert_one_line_error(err, "a.json", "theta_max_deg = 95")


def test_usage_errors_exit_2_in_one_line(capsys):
    # argparse's errors too: no usage block before the message, the option and the value named
    for argv, words in (
        (["validate"], "the following arguments are required: site"),
        (["frobnicate"], "invalid choice: 'frobnicate'"),
        (["verify", "x.json", "p.json", "--incidence", "4d"], "argument --incidence: invalid choice: '4d'"),
        (["plan", "x.json", "--set", "incidence=4d"], "--set incidence: must be one of horizontal, 3d, got '4d'"),
        (["plan", "x.json", "--target-spacing", "0"], "argument --target-spacing: must be > 0, got '0'"),
        (["plan", "x.json", "--grid-spacing", "nan"], "argument --grid-spacing: must be > 0, got 'nan'"),
        (["plan", "x.json", "--set", "plane-refine-steps=-1"], "--set plane-refine-steps: must be >= 0, got '-1'"),
        (["plan", "x.json", "--set", "seed=-1"], "--set seed: must be >= 0, got '-1'"),
        (["export", "x.json", "--seed", "-1"], "argument --seed: must be >= 0, got '-1'"),
        (["plan", "x.json", "--time-limit", "-5"], "argument --time-limit: must be > 0, got '-5'"),
        (["plan", "x.json", "--set", "max-link=0"], "--set max-link: must be > 0, got '0'"),
        (["verify", "x.json", "p.json", "--spacing", "1e-9"], "argument --spacing: must be >= 0.001 and <= 10"),
        (["assemble", "x.json", "--wall-thickness", "-1"], "argument --wall-thickness: must be >= 0"),
    ):
        assert main(argv) == 2, argv
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and words in err and "usage:" not in err, (argv, err)
    assert main(["--version"]) == 0


def test_missing_file_and_unknown_format(capsys, tmp_path):
    code, _, err = run(capsys, "validate", str(tmp_path / "nope.json"))
    assert code == 3 and "nope.json" in err
    (tmp_path / "site.dwg").write_text("0\nEOF\n")
    code, _, err = run(capsys, "validate", str(tmp_path / "site.dwg"))
    assert code == 3
    assert_one_line_error(err, "site.dwg", "unknown input format")
    (tmp_path / "site.dxf").write_text("0\nEOF\n")  # a DXF with no sections at all
    code, _, err = run(capsys, "validate", str(tmp_path / "site.dxf"))
    assert code == 3
    assert_one_line_error(err, "site.dxf", "not a readable DXF file")


def test_scale_option_sets_accuracy(capsys):
    code, out, _ = run(capsys, "validate", str(INSTANCES / "polygon_a.csv"), "--scale", "1:100")
    # 1:100 -> 20 mm (table 1.1); the CSV's default leica-p30 then reaches 490.5 m by (3.1)
    # (sigma_instr = sqrt(400 - 0.75) = 19.98 mm), more than its 270 m datasheet range, which caps it
    assert code == 0 and "sigma_req 20 mm (drawing scale 1:100)" in out
    assert "S_max 270.000 m [datasheet range of leica-p30 ((3.1) gives 490.5" in out


@pytest.mark.slow
def test_console_script_and_module_agree():
    args = ["validate", str(INSTANCES / "polygon_c.json")]
    exe = Path(sys.executable).parent / "planner"
    as_module = subprocess.run([sys.executable, "-m", "planner", *args], capture_output=True, text=True, cwd=ROOT)
    assert as_module.returncode == 0, as_module.stderr
    assert "C        both" in as_module.stdout
    if exe.exists():
        as_script = subprocess.run([str(exe), *args], capture_output=True, text=True, cwd=ROOT)
        assert (as_script.returncode, as_script.stdout) == (as_module.returncode, as_module.stdout)
    bad = subprocess.run([sys.executable, "-m", "planner", "validate", "missing.csv"], capture_output=True, text=True)
    assert bad.returncode == 3 and len(bad.stderr.strip().splitlines()) == 1


def test_a_closed_output_pipe_stops_quietly_with_141():
    # `planner validate SITE --json | head -c 0`: the reader has closed the pipe (here before the interpreter
    # has even started, so the first write fails); the command must not report an internal error (exit 1)
    # but stop quietly, as a shell reports SIGPIPE (128 + 13)
    proc = subprocess.Popen(
        [sys.executable, "-m", "planner", "validate", str(INSTANCES / "baalbek.json"), "--json"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        cwd=ROOT,
    )
    assert proc.stdout is not None and proc.stderr is not None
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 141 and "internal error" not in err


def test_unusable_output_paths_are_one_line_usage_errors(capsys, tmp_path):
    afile = tmp_path / "afile"
    afile.write_text("x")
    # a plan's --out or --report that is a file is refused before the planning starts
    for flag in ("--out", "--report"):
        code, out, err = run(capsys, "plan", str(INSTANCES / "polygon_b.json"), "--method", "greedy", flag, str(afile))
        assert code == 2 and out == "" and err.count("\n") == 1 and f"{flag} = " in err
    # an export into a folder, or into a folder that does not exist, names the path
    for target in (tmp_path, tmp_path / "no" / "such" / "x.mps"):
        code, _, err = run(
            capsys, "export", str(INSTANCES / "polygon_b.json"), "--format", "orlib", "--out", str(target)
        )
        assert code == 2 and err.count("\n") == 1 and str(target) in err


def test_a_hand_edited_plan_json_is_refused_in_one_line(capsys, tmp_path, write_csv):
    # a 10 x 10 m block scanned from outside (3 stations, a connected network): a small plan to edit
    site = write_csv(square_rows(side="outside"))
    assert main(["plan", str(site), "--method", "greedy", "--out", str(tmp_path), "--quiet"]) == 0
    capsys.readouterr()
    good = json.loads((tmp_path / "plan.json").read_text())
    cases = [
        (lambda d: d.update(parameters="x"), "parameters = 'x': must be an object"),
        (lambda d: d["parameters"].update(seed="abc"), "parameters.seed = 'abc': must be an integer >= 0"),
        (lambda d: d["parameters"].update(target_spacing_m=0), "parameters.target_spacing_m = 0: must be a number > 0"),
        (lambda d: d.update(counts="x"), "counts = 'x': must be an object"),
        (lambda d: d["stations"][1].update(id=d["stations"][0]["id"]), "station id used twice (also stations[1])"),
    ]
    for edit, words in cases:
        data = json.loads(json.dumps(good))
        edit(data)
        (tmp_path / "bad.json").write_text(json.dumps(data))
        code, _, err = run(capsys, "report", str(tmp_path / "bad.json"), "--no-network", "--out", str(tmp_path / "r"))
        assert code == 3 and err.count("\n") == 1 and "bad.json" in err and words in err, err
    # the network keys stations by id too: the duplicate is refused there as well, not merged
    code, _, err = run(capsys, "network", str(site), str(tmp_path / "bad.json"))
    assert code == 3 and "station id used twice" in err
    # values found wrong after reading name the file they came from
    data = json.loads(json.dumps(good))
    data["parameters"]["theta_max_deg"] = 95
    (tmp_path / "theta.json").write_text(json.dumps(data))
    code, _, err = run(capsys, "report", str(tmp_path / "theta.json"), "--no-network", "--out", str(tmp_path / "r"))
    assert code == 3 and "theta.json: theta_max_deg = 95" in err
    first = good["stations"][0]["id"]
    for obs, words in (
        (
            {"kind": "distance", "at": first, "to": "NOPE", "value": 5, "sigma": 0.002},
            "observations[1]: distance = '" + first + "->NOPE': names no point of the network: NOPE",
        ),
        (
            {"kind": "distance", "at": first, "to": good["stations"][1]["id"], "value": 5, "sigma": 0},
            "sigma must be > 0, got 0",
        ),
    ):
        (tmp_path / "obs.json").write_text(json.dumps({"observations": [obs]}))
        code, _, err = run(
            capsys,
            "network",
            str(site),
            str(tmp_path / "plan.json"),
            "--observations",
            str(tmp_path / "obs.json"),
        )
        assert code == 3 and "obs.json: " in err and words in err, err
    # a plan without stations has no network (verify reports it as 0 % covered instead)
    (tmp_path / "empty.json").write_text(json.dumps({**good, "stations": []}))
    for command in ("network", "chain"):
        code, _, err = run(capsys, command, str(site), str(tmp_path / "empty.json"))
        assert code == 3 and err.count("\n") == 1 and "the plan has no stations" in err


def test_verify_says_when_the_plan_was_made_under_other_limits(tmp_path, capsys, write_csv):
    # A plan made at theta_max 78 deg is checked against the site's 68 deg (the check is of the site as
    # given, so it may fail), but the command says so and how to check it under its own limits. The site: a
    # 10 x 10 m room (its table's theta_max 68 deg, as polygon B's); any cover will do
    out = tmp_path / "p"
    site = str(write_csv(square_rows()))
    assert main(["plan", site, "--theta-max", "78", "--method", "greedy", "--out", str(out)]) == 0
    capsys.readouterr()
    main(["verify", site, str(out / "plan.json")])
    text = capsys.readouterr().out
    assert "made with theta_max_deg = 78.0 (checked here: 68.0); give --theta-max 78.0" in text
    assert main(["verify", site, str(out / "plan.json"), "--theta-max", "78"]) == 0
    assert "made with" not in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv, code, words",
    [
        # each refused before any planning (the plan of Baalbek takes ~9 s; these take none of it)
        (
            ["--set", "worker-memory=2GiB"],
            2,
            "--set worker-memory = 2147483648: ",
        ),
        (["--network", "--control", "no-such-control.json"], 3, "no-such-control.json: cannot read file"),
        (["--out", ""], 2, "--out = '': is empty"),
    ],
)
def test_plan_option_values_are_checked_before_the_planning(capsys, argv, code, words):
    assert main(["plan", str(INSTANCES / "baalbek.json"), *argv]) == code
    out, err = capsys.readouterr()
    assert words in err and err.count("\n") == 1 and out == ""  # no plan summary: nothing was planned
