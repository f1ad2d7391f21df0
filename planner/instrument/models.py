"""Instrument models (scanners, total stations) read from the TOML files in ``models/``.

A model file names its ``kind`` (``scanner`` or ``total_station``) and gives lengths with their unit in the key:
``range_sigma_const_mm = 1.2`` and ``range_sigma_const_m = 0.0012`` are the same model. Unknown keys are refused, so a
typo never silently drops a value.
"""

from __future__ import annotations

import os
import tomllib
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

from planner.core.checks import finite_number
from planner.core.errors import InputError
from planner.core.resources import data_path
from planner.instrument.accuracy import RangeAngleSigma
from planner.instrument.field_table import FieldProperties, field_from_mapping


@dataclass(frozen=True)
class Scanner(RangeAngleSigma):
    """A terrestrial laser scanner: sigma_S = X + Y ppm and angle sigma_beta. ``max_slant_range_m`` fixes S_max
    outright; otherwise S_max follows from (3.1) for the required accuracy, capped by the datasheet ``max_range_m``. For
    floors and ceilings (:mod:`planner.coverage.surface_sight`): ``nadir_blind_half_angle_deg``, the half angle of the
    cone under the instrument that it cannot see ((360 - V) / 2 for a vertical field of V deg with the gap below),
    ``zenith_blind_half_angle_deg`` the same above it, ``instrument_height_3d_m`` the default instrument height above
    the floor; None: no cone, no default height."""

    name: str = ""
    description: str = ""
    source: str = ""
    max_range_m: float | None = None
    max_slant_range_m: float | None = None
    modelling_sigma_m: float = 0.0
    #: setup and scan times, walking speed, target limits (the model's ``[field]`` table; None: the defaults)
    field_properties: FieldProperties | None = None
    nadir_blind_half_angle_deg: float | None = None
    zenith_blind_half_angle_deg: float | None = None
    instrument_height_3d_m: float | None = None

    def __post_init__(self) -> None:
        _check_positive(
            self, ("range_sigma_const_m", "range_sigma_ppm", "angle_sigma_arcsec", "modelling_sigma_m"), True
        )
        _check_positive(self, ("max_range_m", "max_slant_range_m", "instrument_height_3d_m"), False)
        for name in ("nadir_blind_half_angle_deg", "zenith_blind_half_angle_deg"):
            _check_half_angle(name, getattr(self, name))
        unlimited = self.max_range_m is None and self.max_slant_range_m is None
        if unlimited and not (self.range_sigma_ppm or self.angle_sigma_arcsec):
            # sigma_meas would not grow with range: (3.1) gives S_max = inf ("S_max inf m"), which no plan can use
            raise InputError("no range limit: give max_range_m, or a non-zero ppm or angle error", field="max_range_m")


@dataclass(frozen=True)
class TotalStation:
    """A total station: directions sigma_beta, distances a + b ppm to prisms and reflectorless."""

    name: str
    angle_sigma_arcsec: float
    prism_sigma_const_m: float
    prism_sigma_ppm: float
    reflectorless_sigma_const_m: float
    reflectorless_sigma_ppm: float
    max_range_prism_m: float | None = None
    max_range_reflectorless_m: float | None = None
    description: str = ""
    source: str = ""

    def __post_init__(self) -> None:
        _check_positive(self, ("angle_sigma_arcsec", "prism_sigma_const_m", "prism_sigma_ppm"), True)
        _check_positive(self, ("reflectorless_sigma_const_m", "reflectorless_sigma_ppm"), True)
        _check_positive(self, ("max_range_prism_m", "max_range_reflectorless_m"), False)

    def distance_model(self, reflectorless: bool = False) -> RangeAngleSigma:
        """The distance/angle error model for prism or reflectorless measurement."""
        if reflectorless:
            return RangeAngleSigma(
                self.reflectorless_sigma_const_m, self.reflectorless_sigma_ppm, self.angle_sigma_arcsec
            )
        return RangeAngleSigma(self.prism_sigma_const_m, self.prism_sigma_ppm, self.angle_sigma_arcsec)


Instrument = Scanner | TotalStation
_KINDS: dict[str, type[Scanner] | type[TotalStation]] = {"scanner": Scanner, "total_station": TotalStation}


#: no instrument constant is anywhere near this; a larger one is a typo that would overflow the accuracy model
MAX_MODEL_VALUE = 1e9


def _check_positive(obj: object, names: tuple[str, ...], zero_ok: bool) -> None:
    for name in names:
        v = getattr(obj, name)
        if v is None:
            continue
        if not finite_number(v) or v < 0 or (v == 0 and not zero_ok) or v > MAX_MODEL_VALUE:
            need = ">= 0" if zero_ok else "> 0"
            raise InputError(
                f"must be a finite number {need} and <= {MAX_MODEL_VALUE:g}", zone=None, field=name, value=v
            )


def _check_half_angle(name: str, v: Any) -> None:
    """A blind cone's half angle: None (no cone) or a number of degrees in [0, 90)."""
    if v is None:
        return
    if not finite_number(v) or not 0 <= v < 90:
        raise InputError("must be a half angle in degrees, >= 0 and < 90", zone=None, field=name, value=v)


def default_models_dir() -> Path:
    """Where instrument files are looked up: $PLANNER_MODELS_DIR, else the repository's ``models/`` (the copy an
    installed wheel ships, outside a checkout)."""
    env = os.environ.get("PLANNER_MODELS_DIR")
    if env:
        return Path(env)
    return data_path("models")


def list_instruments(models_dir: Path | None = None) -> list[str]:
    """Names of the instrument files available (file stem = instrument name)."""
    folder = models_dir or default_models_dir()
    if not folder.is_dir():  # e.g. a mistyped $PLANNER_MODELS_DIR: say so instead of listing nothing
        env = os.environ.get("PLANNER_MODELS_DIR")
        source = " ($PLANNER_MODELS_DIR)" if env and Path(env) == folder else ""
        raise InputError(f"the instrument models folder{source} is not a folder", field="models", value=str(folder))
    return sorted(p.stem for p in folder.glob("*.toml"))


def load_instrument(name_or_path: str, models_dir: Path | None = None) -> Instrument:
    """Load an instrument by name (``leica-p30``) or by the path of a TOML file; an InputError for an
    unknown name (listing the known ones), an unreadable file, an unknown key or a value out of range."""
    path = Path(name_or_path)
    if path.suffix != ".toml":
        folder = models_dir or default_models_dir()
        path = folder / f"{name_or_path}.toml"
        if not path.is_file():
            known = ", ".join(list_instruments(folder)) or "none"
            raise InputError(f"unknown instrument (known: {known})", field="instrument", value=name_or_path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise InputError(f"cannot read instrument file: {exc}", file=str(path)) from None
    try:
        return instrument_from_mapping(data, default_name=path.stem)
    except InputError as exc:
        raise exc.located(str(path)) from None


def instrument_from_mapping(data: dict[str, Any], default_name: str = "") -> Instrument:
    """Build a Scanner or TotalStation from a mapping with unit-suffixed keys."""
    kind = data.get("kind")
    cls = _KINDS.get(kind) if isinstance(kind, str) else None
    if cls is None:
        raise InputError("must be 'scanner' or 'total_station'", field="kind", value=kind)
    wanted = {f.name for f in fields(cls)}
    values: dict[str, Any] = {"name": data.get("name", default_name)}
    for key, raw in data.items():
        if key in ("kind", "name"):
            continue
        if key == "field" and kind == "scanner":
            values["field_properties"] = field_from_mapping(raw)
            continue
        target, scale = (key[:-3] + "_m", 1e-3) if key.endswith("_mm") else (key, 1.0)
        if target not in wanted or target == "field_properties":
            raise InputError(f"unknown key for a {kind}", field=key, value=raw)
        if target in values:
            raise InputError("given twice (in two units)", field=key, value=raw)
        if scale != 1.0:
            if not isinstance(raw, (int, float)) or isinstance(raw, bool):
                raise InputError("must be a number", field=key, value=raw)
            raw = float(raw) * scale
        elif isinstance(raw, int) and not isinstance(raw, bool):
            raw = float(raw)
        values[target] = raw
    try:
        return cls(**values)
    except TypeError as exc:
        raise InputError(f"incomplete instrument model: {exc}", field="kind", value=kind) from None
