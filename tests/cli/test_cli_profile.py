"""Tuning profiles: ``plan --help`` on one screen, ``--help-all`` and ``--config FILE`` for the rest."""

from __future__ import annotations

import argparse
import json
import re
import tomllib

import pytest

from planner.cli import build_parser, main
from planner.cli.profile import DEFAULT_PROFILE, TUNING, apply_config
from tests.conftest import INSTANCES


def _plan_parser(parser: argparse.ArgumentParser | None = None) -> argparse.ArgumentParser:
    parser = parser or build_parser()
    subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return subs.choices["plan"]


def _options(text: str) -> list[str]:
    """The option lines of a help text: '  -h, --help ...', '  --method {...}' (continuation lines start deeper)."""
    return re.findall(r"^  (-[-\w]+)", text, flags=re.MULTILINE)


def test_plan_help_fits_one_screen_and_help_all_lists_every_option(capsys):
    assert main(["plan", "--help"]) == 0
    short = _options(capsys.readouterr().out)
    assert len(short) <= 35, short  # issue 33: about 30 options, at most 35
    assert main(["plan", "--help-all"]) == 0
    full = capsys.readouterr().out
    everything = _options(full)
    for flag in TUNING["plan"]:
        assert flag not in short and flag in everything, flag
    assert set(short) <= set(everything)
    # every option of the parser is listed by one of the two (nothing unreachable)
    flags = {s for a in _plan_parser()._actions for s in a.option_strings if s.startswith("--")}
    assert flags <= set(everything) | {"--help"}
    assert full.count("[tuning]") == len(TUNING["plan"])


def test_shipped_profile_holds_every_tuning_default_as_the_parser_has_it():
    profile = tomllib.loads(DEFAULT_PROFILE.read_text())["plan"]
    actions = {s: a for a in _plan_parser()._actions for s in a.option_strings}
    with_default = {f[2:]: actions[f].default for f in TUNING["plan"] if actions[f].default not in (None, [])}
    assert profile == with_default  # the file documents exactly the defaults the command uses
    # keys without a default are named in the file as comments, so the file lists every knob
    text = DEFAULT_PROFILE.read_text()
    for flag in TUNING["plan"]:
        assert re.search(rf"^#? ?{flag[2:]} = ", text, flags=re.MULTILINE), flag


def test_config_sets_defaults_and_the_command_line_wins(tmp_path):
    cfg = tmp_path / "my.toml"
    cfg.write_text('[plan]\ntile-window-radius = 80\nbackend = "scip"\nno_ring_bound = true\n')
    parser = build_parser()
    argv = ["plan", "site.json", "--config", str(cfg), "--backend", "highs"]
    apply_config(parser, argv)
    args = parser.parse_args(argv)
    assert args.tile_window_radius == 80.0 and args.no_ring_bound is True  # from the file
    assert args.backend == "highs"  # the command line wins over the file
    fresh = build_parser().parse_args(["plan", "site.json"])
    assert fresh.tile_window_radius == 60.0 and fresh.backend == "cpsat"  # a new parser: the defaults again


@pytest.mark.parametrize(
    "body, fragment",
    [
        ("[plan]\nno-such-knob = 1\n", "[plan] no-such-knob: no such option"),
        ("[plan]\ntile-window-radius = -3\n", "[plan] tile-window-radius: must be > 0"),
        ('[plan]\nbackend = "gurobi"\n', "[plan] backend: must be one of"),
        ("[plan]\nlayer-cuts = 1\n", "[plan] layer-cuts: expected true or false"),
        ("[plant]\nbackend = 'scip'\n", "[plant] is no command"),
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


def test_profile_value_reaches_the_plan(tmp_path, capsys):
    # an 8 x 4 m room seen from inside (2 stations): the profile's verify spacing is the one the plan records
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
    cfg.write_text("[plan]\nverify-spacing = 0.25\nno-precision = true\n")
    out = tmp_path / "out"
    code = main(["plan", str(site), "--method", "greedy", "--config", str(cfg), "--out", str(out), "--quiet"])
    assert code == 0, capsys.readouterr().err
    plan = json.loads((out / "plan.json").read_text())
    text = json.dumps(plan)
    assert '"verify_spacing_m": 0.25' in text, sorted(plan)


@pytest.mark.parametrize("extra", [[], ["--tiles", "off"], ["--method", "greedy"]])
def test_plan_validates_the_site_once(monkeypatch, capsys, tmp_path, extra):
    # issue 33: one validation per `planner plan` run, handed to the memory guard, the strategy and the plan
    # (validate_site is the one caller of site_scanner: counting it counts the validations)
    import planner.site.validate as validate

    calls = []
    real = validate.site_scanner
    monkeypatch.setattr(validate, "site_scanner", lambda site: calls.append(site.name) or real(site))
    assert main(["plan", str(INSTANCES / "polygon_b.json"), "--quiet", "--no-pricing", *extra]) == 0, (
        capsys.readouterr().err
    )
    assert calls == ["polygon_b"]
