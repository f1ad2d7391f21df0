"""The scanner's vertical field of view and its default instrument height for 3-D work (issue 46)."""

from __future__ import annotations

import math

import pytest

from planner.core.errors import InputError
from planner.instrument.models import Scanner, list_instruments, load_instrument

BASE = 'kind = "scanner"\nrange_sigma_const_mm = 1.2\nrange_sigma_ppm = 10\nangle_sigma_arcsec = 8\n'


def test_p30_blind_cone_from_its_290_deg_vertical_field():
    p30 = load_instrument("leica-p30")
    assert isinstance(p30, Scanner)
    # 360 x 290 deg: a 360 - 290 = 70 deg gap centred on the nadir, 35 deg either side of the plumb line
    assert p30.nadir_blind_half_angle_deg == 35.0 == (360 - 290) / 2
    assert p30.zenith_blind_half_angle_deg is None  # it sees through the zenith
    assert p30.instrument_height_3d_m == 1.5
    # the blind disc round the tripod at 1.5 m: 1.5 x tan 35 deg = 1.0503 m (the "about 1.05 m")
    assert 1.5 * math.tan(math.radians(p30.nadir_blind_half_angle_deg)) == pytest.approx(1.0503, abs=1e-4)


def test_other_models_have_no_vertical_field_and_nothing_changes_for_walls():
    for name in list_instruments():
        model = load_instrument(name)
        if isinstance(model, Scanner) and name != "leica-p30":
            assert (model.nadir_blind_half_angle_deg, model.zenith_blind_half_angle_deg) == (None, None), name
            assert model.instrument_height_3d_m is None, name


def test_fields_read_from_toml_with_units(tmp_path):
    f = tmp_path / "vf.toml"
    f.write_text(
        BASE + "nadir_blind_half_angle_deg = 30\nzenith_blind_half_angle_deg = 10\ninstrument_height_3d_mm = 1600\n"
    )
    model = load_instrument(str(f))
    assert isinstance(model, Scanner)
    assert (model.nadir_blind_half_angle_deg, model.zenith_blind_half_angle_deg) == (30.0, 10.0)
    assert model.instrument_height_3d_m == pytest.approx(1.6)


@pytest.mark.parametrize(
    "line, shown",
    [
        ("nadir_blind_half_angle_deg = 90", "nadir_blind_half_angle_deg = 90"),
        ("nadir_blind_half_angle_deg = -5", "nadir_blind_half_angle_deg = -5"),
        ("zenith_blind_half_angle_deg = true", "zenith_blind_half_angle_deg = True"),
        ("instrument_height_3d_m = 0", "instrument_height_3d_m = 0"),
        ("instrument_height_3d_m = -1.5", "instrument_height_3d_m = -1.5"),
    ],
)
def test_bad_values_are_refused_naming_field_and_value(tmp_path, line, shown):
    f = tmp_path / "bad.toml"
    f.write_text(BASE + line + "\n")
    with pytest.raises(InputError, match=rf"bad.toml: {shown}: must be"):
        load_instrument(str(f))


def test_a_misspelt_field_is_refused(tmp_path):
    f = tmp_path / "typo.toml"
    f.write_text(BASE + "blind_cone_deg = 35\n")
    with pytest.raises(InputError, match=r"blind_cone_deg.*unknown key"):
        load_instrument(str(f))
