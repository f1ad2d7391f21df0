"""Tuning keys: ``plan --help-all`` short, every knob still settable by ``--set KEY=VALUE`` and ``--config FILE``."""

from __future__ import annotations

import argparse
import json
import re
import tomllib

import pytest

from planner.cli import build_parser, main
from planner.cli.profile import DEFAULT_PROFILE, TUNING, apply_config
from planner.cli.tuning import profile_text
from planner.core.settings import SETTINGS
from tests.conftest import INSTANCES, square_rows


def _subparsers(parser: argparse.ArgumentParser | None = None) -> dict[str, argparse.ArgumentParser]:
    parser = parser or build_parser()
    return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices


def _plan_parser(parser: argparse.ArgumentParser | None = None) -> argparse.ArgumentParser:
    return _subparsers(parser)["plan"]


def _options(text: str) -> list[str]:
    """The option lines of a help text: '  -h, --help ...', '  --method {...}' (continuation lines start deeper)."""
    return re.findall(r"^  (-[-\w]+)", text, flags=re.MULTILINE)


def test_plan_help_all_lists_every_option_and_tuning_key(capsys):
    assert main(["plan", "--help"]) == 0
    short = capsys.readouterr().out
    assert len(_options(short)) <= 38, _options(short)
    assert "--help-all lists them" in short  # the keys are found from --help
    assert main(["plan", "--help-all"]) == 0
    full = capsys.readouterr().out
    options = _options(full)
    assert len(options) <= 45, options
    # every option of the parser is listed (nothing unreachable), and no tuning key is an option
    flags = {s for a in _plan_parser()._actions for s in a.option_strings if s.startswith("--")}
    assert flags | {"-h"} == set(options) | {"--help"}
    keys = full.split("tuning keys (")[1]
    for key in TUNING["plan"]:
        assert f"--{key}" not in flags, key
        assert re.search(rf"^  {key}[=\[]", keys, flags=re.MULTILINE), key  # listed with its values and help
        assert SETTINGS[key].help.split()[0] in keys


def test_every_subcommand_has_at_most_45_options(capsys):
    for name, sub in _subparsers().items():
        options = [a for a in sub._actions if a.option_strings]
        assert len(options) <= 45, (name, len(options))


def test_shipped_profile_is_the_table_of_keys():
    text = DEFAULT_PROFILE.read_text()
    # the file is written from the table: python -c "from planner.cli.tuning import profile_text;
    # open('planner/cli/profiles/default.toml', 'w').write(profile_text('plan'))"
    assert text == profile_text("plan")
    profile = tomllib.loads(text)["plan"]
    with_default = {k: SETTINGS[k].initial for k in TUNING["plan"] if SETTINGS[k].initial not in (None, [])}
    assert profile == with_default  # the file holds exactly the defaults the command uses
    fresh = build_parser().parse_args(["plan", "site.json"])
    for key in TUNING["plan"]:
        assert getattr(fresh, SETTINGS[key].dest) == SETTINGS[key].initial, key  # and the parser starts from them
        assert re.search(rf"^#? ?{key} = ", text, flags=re.MULTILINE), key  # keys without a default: commented


def test_set_and_config_set_the_flag_attributes_and_the_command_line_wins(tmp_path):
    cfg = tmp_path / "my.toml"
    cfg.write_text('[plan]\ntile-budget = 80\nbackend = "scip"\nexterior = true\nmethod = "greedy"\n')
    parser = build_parser()
    argv = ["plan", "site.json", "--config", str(cfg), "--set", "backend=highs", "--set", "seed=2"]
    argv += [
        "--set",
        "ifc-windows",
        "--set",
        "layer-height=WALLS=3",
        "--set",
        "layer-height=ROOF=5",
        "--method",
        "milp",
    ]
    apply_config(parser, argv)
    args = parser.parse_args(argv)
    assert args.tile_budget == 80.0 and args.exterior is True  # from the file
    assert args.backend == "highs" and args.method == "milp"  # the command line wins over the file
    assert args.seed == 2 and args.ifc_windows is True and args.layer_height == ["WALLS=3", "ROOF=5"]
    fresh = build_parser().parse_args(["plan", "site.json"])
    assert fresh.tile_budget == 420.0 and fresh.backend == "cpsat"  # a new parser: the defaults again
    assert fresh.layer_height == [] and fresh.ifc_windows is False
    later = build_parser().parse_args(["plan", "s.json", "--set", "seed=3", "--set", "seed=4", "--set", "exterior=no"])
    assert later.seed == 4 and later.exterior is False  # the last --set of a key wins
    sizes = build_parser().parse_args(["plan", "s.json", "--set", "worker-memory=2G", "--memory-limit", "512M"])
    assert (sizes.worker_memory, sizes.memory_limit) == (2 * 2**30, 512 * 2**20)  # bytes inside


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["--set", "tile-budget=-3"], "--set tile-budget: must be > 0, got '-3'"),
        (["--set", "backend=gurobi"], "--set backend: must be one of cpsat"),
        (["--set", "exterior=maybe"], "--set exterior: expected true or false"),
        (["--set", "variant=no-such"], "--set variant: unknown variant 'no-such'"),
        (["--set", "plane-refine-steps=-1"], "--set plane-refine-steps: must be >= 0, got '-1'"),
        (["--set", "angular-tolerance=x"], "--set angular-tolerance: expected a number, got 'x'"),
        (["--set", "tile-budge=3"], "no tuning key 'tile-budge' of 'planner plan'"),
        (["--set", "tile-budge=3"], "did you mean tile-budget?"),
        (["--set", "method=greedy"], "--method is an option of 'planner plan', not a tuning key"),
        (["--set", "layer-height=A=1", "--set", "layer-height=a=2"], "layer 'A' given twice"),
        (["--set", "max-link"], "--set max-link: expected max-link=M"),
    ],
)
def test_bad_set_is_one_line_usage_error(capsys, argv, fragment):
    code = main(["plan", str(INSTANCES / "polygon_b.json"), *argv])
    err = capsys.readouterr().err
    assert code == 2, err
    assert len(err.strip().splitlines()) == 1 and fragment in err and "Traceback" not in err, err


@pytest.mark.parametrize(
    "body, fragment",
    [
        ("[plan]\nno-such-knob = 1\n", "bad.toml: [plan] no-such-knob: no tuning key 'no-such-knob'"),
        ("[plan]\ntile-budget = -3\n", "[plan] tile-budget: must be > 0"),
        ('[plan]\nbackend = "gurobi"\n', "[plan] backend: must be one of"),
        ("[plan]\nexterior = 1\n", "[plan] exterior: expected true or false"),
        ("[plant]\nbackend = 'scip'\n", "[plant] is no command"),
        ("[plan]\nlayer-height = ['W=1', 'w=2']\n", "[plan] layer-height: layer 'W' given twice"),
        ("[plan]\nseed = [2]\n", "[plan] seed: not a value this key takes"),
        ("[plan\n", "not a TOML file"),
    ],
)
def test_bad_profile_is_one_line_usage_error(tmp_path, capsys, body, fragment):
    cfg = tmp_path / "bad.toml"
    cfg.write_text(body)
    code = main(["plan", str(INSTANCES / "polygon_b.json"), "--config", str(cfg)])
    err = capsys.readouterr().err
    assert code == 2, err
    assert len(err.strip().splitlines()) == 1 and fragment in err and "Traceback" not in err, err


def test_missing_profile_is_usage_error(tmp_path, capsys):
    code = main(["plan", str(INSTANCES / "polygon_b.json"), "--config", str(tmp_path / "none.toml")])
    err = capsys.readouterr().err
    assert code == 2 and "cannot read the profile" in err and "none.toml" in err


@pytest.mark.parametrize("given", ["config", "set"])
def test_tuning_value_reaches_the_plan(tmp_path, capsys, given):
    # an 8 x 4 m room seen from inside (2 stations): the key's seed is the one the plan records
    site = tmp_path / "room.json"
    site.write_text(
        json.dumps(
            {
                "zones": [
                    {"id": "R", "scan_side": "inside", "height_m": 3, "coordinates": [[0, 0], [8, 0], [8, 4], [0, 4]]}
                ]
            }
        )
    )
    cfg = tmp_path / "p.toml"
    cfg.write_text("[plan]\nseed = 7\nno-precision = true\n")
    keys = ["--config", str(cfg)] if given == "config" else ["--set", "seed=7", "--set", "no-precision"]
    out = tmp_path / "out"
    code = main(["plan", str(site), "--method", "greedy", *keys, "--out", str(out), "--quiet"])
    assert code == 0, capsys.readouterr().err
    plan = json.loads((out / "plan.json").read_text())
    text = json.dumps(plan)
    assert '"seed": 7' in text and '"precision": false' in text, sorted(plan)


@pytest.mark.parametrize(
    "extra",
    [
        [],
        pytest.param(["--tiles", "off"], marks=pytest.mark.slow),
        pytest.param(["--method", "greedy"], marks=pytest.mark.slow),
    ],
)
def test_plan_validates_the_site_once(monkeypatch, capsys, tmp_path, extra, write_csv):
    # one validation per `planner plan` run, handed to the memory guard, the strategy and the plan
    # (validate_site is the one caller of site_scanner: counting it counts the validations); the site: a 10 x 10 m
    # room (a table, named "site"), every stage of polygon B's run at a tenth of its cost
    import planner.site.validate as validate

    calls = []
    real = validate.site_scanner
    monkeypatch.setattr(validate, "site_scanner", lambda site: calls.append(site.name) or real(site))
    room = str(write_csv(square_rows()))
    assert main(["plan", room, "--quiet", "--set", "variant=no-pricing", *extra]) == 0, capsys.readouterr().err
    assert calls == ["site"]
