"""Instrument models read from models/*.toml."""

from __future__ import annotations

import math
import re

import pytest

from planner.core.errors import InputError
from planner.instrument.accuracy import ErrorBudget, max_slant_range_m, sigma_instr_m
from planner.instrument.models import Scanner, TotalStation, list_instruments, load_instrument
from planner.site.params import Parameters, resolve_range_limit


def test_bundled_models_load():
    names = list_instruments()
    assert {"leica-p30", "leica-scanstation-2", "topcon-os-105", "dissertation-tables"} <= set(names)
    for name in names:
        assert load_instrument(name).name == name


def test_p30_values_and_units():
    p30 = load_instrument("leica-p30")
    assert isinstance(p30, Scanner)
    # 1.2 mm + 10 ppm, 8"
    assert (p30.range_sigma_const_m, p30.range_sigma_ppm, p30.angle_sigma_arcsec) == (pytest.approx(0.0012), 10.0, 8.0)


def test_topcon_distance_models():
    ts = load_instrument("topcon-os-105")
    assert isinstance(ts, TotalStation)
    assert ts.distance_model().range_sigma_const_m == pytest.approx(0.002)
    assert ts.distance_model(reflectorless=True).range_sigma_const_m == pytest.approx(0.003)
    assert ts.distance_model().range_sigma_ppm == 2.0


def test_unit_change_leaves_s_max_unchanged(tmp_path):
    # the same P30 written in metres instead of millimetres gives the same S_max
    (tmp_path / "p30m.toml").write_text(
        'kind = "scanner"\nrange_sigma_const_m = 0.0012\nrange_sigma_ppm = 10\nangle_sigma_arcsec = 8\n'
    )
    in_m = load_instrument(str(tmp_path / "p30m.toml"))
    in_mm = load_instrument("leica-p30")
    s = sigma_instr_m(0.01, ErrorBudget())
    assert max_slant_range_m(in_m, s) == pytest.approx(max_slant_range_m(in_mm, s), rel=1e-12)


def test_unknown_instrument_lists_known():
    with pytest.raises(InputError, match=r"instrument = 'leica-p99': unknown instrument \(known: .*leica-p30"):
        load_instrument("leica-p99")


def test_unknown_key_refused(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text(
        'kind = "scanner"\nrange_sigma_const_mm = 1\nrange_sigma_ppm = 1\nangle_sigma_arcsec = 1\nrange_sigma_cnst_mm = 2\n'
    )
    with pytest.raises(InputError, match=r"bad.toml: range_sigma_cnst_mm.*unknown key"):
        load_instrument(str(f))


def test_negative_sigma_refused(tmp_path):
    f = tmp_path / "neg.toml"
    f.write_text('kind = "scanner"\nrange_sigma_const_mm = -1\nrange_sigma_ppm = 1\nangle_sigma_arcsec = 1\n')
    with pytest.raises(InputError, match=r"range_sigma_const_m = -0.001"):
        load_instrument(str(f))


def test_range_limit_sources():
    params = Parameters()
    assert resolve_range_limit(params, load_instrument("dissertation-tables")).max_slant_range_m == 95.913
    derived = resolve_range_limit(params, load_instrument("leica-p30"))
    assert derived.max_slant_range_m == pytest.approx(239.55, abs=0.005) and "(3.1)" in derived.source
    override = resolve_range_limit(Parameters(max_slant_range_m=50.0), load_instrument("leica-p30"))
    assert override.max_slant_range_m == 50.0
    # ScanStation 2: X = 4 mm, no ppm, so (3.1) reduces to S = sqrt(sigma_instr^2 - X^2) / (sigma_beta / rho)
    # = sqrt(9.9624^2 - 4^2) mm / (12.4 / 206265) = 151.77 m, inside its 300 m datasheet range
    ss2 = resolve_range_limit(params, load_instrument("leica-scanstation-2"))
    assert ss2.max_slant_range_m == pytest.approx(math.sqrt(9.96243**2 - 16) / 1000 / (12.4 / 206264.806), rel=1e-5)


def test_datasheet_range_caps_the_derived_one(tmp_path):
    # a P30 model with a 100 m datasheet range: (3.1) gives 239.55 m, the cap wins
    f = tmp_path / "short.toml"
    f.write_text(
        'kind = "scanner"\nrange_sigma_const_mm = 1.2\nrange_sigma_ppm = 10\nangle_sigma_arcsec = 8\nmax_range_m = 100\n'
    )
    limit = resolve_range_limit(Parameters(), load_instrument(str(f)))
    assert limit.max_slant_range_m == 100.0 and "239.55" in limit.source


@pytest.mark.parametrize("value, shown", [("true", "True"), ("1e308", "1e+308")])
def test_a_boolean_or_absurd_constant_is_refused(tmp_path, value, shown):
    # TOML booleans are no 1" of angle; 1e308" overflowed the accuracy model instead of being refused
    f = tmp_path / "odd.toml"
    f.write_text(f'kind = "scanner"\nrange_sigma_const_mm = 1\nrange_sigma_ppm = 1\nangle_sigma_arcsec = {value}\n')
    with pytest.raises(
        InputError, match=re.escape(f"angle_sigma_arcsec = {shown}: must be a finite number >= 0 and <= 1e+09")
    ):
        load_instrument(str(f))


def test_a_models_folder_that_is_not_there_is_named(monkeypatch, tmp_path):
    # a mistyped $PLANNER_MODELS_DIR listed no instrument and then called every name unknown ("known: none")
    monkeypatch.setenv("PLANNER_MODELS_DIR", str(tmp_path / "nowhere"))
    with pytest.raises(
        InputError, match=r"models = '.*nowhere': the instrument models folder \(\$PLANNER_MODELS_DIR\)"
    ):
        load_instrument("leica-p30")


FLAT = 'kind = "scanner"\nrange_sigma_const_mm = 1.2\nrange_sigma_ppm = 0\nangle_sigma_arcsec = 0\n'


def test_a_model_whose_error_does_not_grow_with_range_needs_a_range(tmp_path, capsys):
    # a constant range error alone gave S_max = inf: validate printed "S_max inf m" (exit 0) and plan crashed
    # ("buffer distance must be finite", exit 1); now the model is refused, naming its file
    from planner.cli import main
    from tests.cli.test_cli import assert_one_line_error

    flat = tmp_path / "flat.toml"
    flat.write_text(FLAT)
    with pytest.raises(InputError, match=r"flat.toml: max_range_m: no range limit: give max_range_m, or a non-zero"):
        load_instrument(str(flat))
    site = tmp_path / "sq.json"
    site.write_text(
        '{"zones": [{"id": "court", "scan_side": "inside", "coordinates": [[0, 0], [20, 0], [20, 10], '
        '[0, 10]], "height_m": 5}]}'
    )
    for argv in (["validate"], ["plan", "--method", "greedy", "--out", str(tmp_path)]):
        assert main([argv[0], str(site), *argv[1:], "--instrument", str(flat)]) == 3
        assert_one_line_error(capsys.readouterr().err, "flat.toml", "no range limit")
    # with a datasheet range it is a model: S_max is that range
    flat.write_text(FLAT + "max_range_m = 50\n")
    assert resolve_range_limit(Parameters(), load_instrument(str(flat))).max_slant_range_m == 50.0


def test_a_range_limit_beyond_10_km_is_refused(tmp_path):
    # 1e-300 ppm leaves (3.1) a range of 4e304 m, a 1e9 m datasheet range 1e9 m: no plan can use either
    for name, extra in (
        ("tiny", "range_sigma_ppm = 1e-300\nangle_sigma_arcsec = 0\n"),
        ("far", "range_sigma_ppm = 0\nangle_sigma_arcsec = 0\nmax_range_m = 1e9\n"),
    ):
        f = tmp_path / f"{name}.toml"
        f.write_text(f'kind = "scanner"\nrange_sigma_const_mm = 1.2\n{extra}')
        with pytest.raises(InputError, match=rf"instrument = '{name}': S_max .* is beyond 10000 m"):
            resolve_range_limit(Parameters(), load_instrument(str(f)))
