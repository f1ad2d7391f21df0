"""An instrument's field properties: setup time, scan time per setting, walking speed, target limits.

They are read from the ``[field]`` table of a model file in ``models/`` (:mod:`planner.instrument.models`);
each model file names the source of every default in a comment. A model without the table gets
:data:`DEFAULT_FIELD`, whose values are stated assumptions, not measurements (docs/field.md).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace
from typing import Any

from planner.core.checks import finite_number
from planner.core.errors import InputError

#: a setting's name as the datasheets print it: the point spacing at a range, "6.3 mm @ 10 m"
_SETTING = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*mm\s*@\s*(\d+(?:\.\d+)?)\s*m\s*$")
#: keys of a ``[field]`` table besides ``scan_time_s``
_NUMBERS = ("setup_time_s", "walking_speed_m_s", "target_scan_time_s", "target_range_m", "target_incidence_deg")


@dataclass(frozen=True)
class FieldProperties:
    """What a crew needs to time a plan with one instrument."""

    setup_time_s: float = 180.0  # setting up, levelling and taking down the scanner at one station
    walking_speed_m_s: float = 0.8  # carrying the scanner on its tripod
    scan_times_s: tuple[tuple[str, float], ...] = (("default", 300.0),)  # one full scan at each setting
    default_setting: str = "default"  # used when none is asked for; one of ``scan_times_s``
    target_scan_time_s: float = 30.0  # the fine scan of one registration target a station scans
    target_range_m: float = 25.0  # farthest a target (sphere or checkerboard) is measured reliably from
    target_incidence_deg: float = 45.0  # largest incidence at which a flat (checkerboard) target is measured
    source: str = field(default="planner assumptions (docs/field.md)", compare=False)

    def __post_init__(self) -> None:
        for name in _NUMBERS:
            value = getattr(self, name)
            zero_ok = name in ("setup_time_s", "target_scan_time_s")
            if not finite_number(value) or value < 0 or (value == 0 and not zero_ok):
                need = ">= 0" if zero_ok else "> 0"
                raise InputError(f"must be a finite number {need}", field=f"field.{name}", value=value)
        if not (incidence := self.target_incidence_deg) < 90:
            raise InputError("must be below 90 deg", field="field.target_incidence_deg", value=incidence)
        if not self.scan_times_s:
            raise InputError("needs at least one setting", field="field.scan_time_s")
        for name, secs in self.scan_times_s:
            if not finite_number(secs) or secs <= 0:
                raise InputError(
                    "must be a finite number of seconds > 0", field=f"field.scan_time_s.{name}", value=secs
                )
        if self.default_setting not in self.settings:
            raise self._unknown(self.default_setting, "field.default_setting", "is not a setting of scan_time_s")

    @property
    def settings(self) -> tuple[str, ...]:
        """The names of the scan settings, in file order."""
        return tuple(name for name, _ in self.scan_times_s)

    def step_rad(self, setting: str) -> float:
        """The angular step of ``setting`` (rad), read from its name, the point spacing at a range as the
        datasheets print it: "6.3 mm @ 10 m" steps 6.3e-3 / 10 = 6.3e-4 rad."""
        if setting not in self.settings:
            raise self._unknown(setting, "setting")
        found = _SETTING.match(setting)
        if found is None or float(found.group(2)) <= 0 or float(found.group(1)) <= 0:
            raise InputError(
                "names no point spacing: a setting for --max-point-spacing is named as 'SPACING mm @ RANGE m'",
                field=f"field.scan_time_s.{setting}",
                value=setting,
            )
        return float(found.group(1)) * 1e-3 / float(found.group(2))

    def by_step(self) -> tuple[tuple[str, float, float], ...]:
        """``(setting, step_rad, scan_time_s)`` of every setting, coarsest step first."""
        rows = [(name, self.step_rad(name), float(secs)) for name, secs in self.scan_times_s]
        return tuple(sorted(rows, key=lambda r: -r[1]))

    def only(self, setting: str) -> FieldProperties:
        """These properties with ``setting`` as the only scan setting (a plan at one setting)."""
        return replace(self, scan_times_s=((setting, self.scan_time_s(setting)),), default_setting=setting)

    def settings_by_step(self) -> tuple[str, ...]:
        """The names of the settings, coarsest step first (as :meth:`by_step` orders them)."""
        return tuple(name for name, _, _ in self.by_step())

    def scan_time_s(self, setting: str | None = None) -> float:
        """Seconds of one scan at ``setting`` (None: the default setting)."""
        name = self.default_setting if setting is None else setting
        for key, secs in self.scan_times_s:
            if key == name:
                return float(secs)
        raise self._unknown(name, "--setting")

    def _unknown(self, setting: str, field: str, why: str = "unknown scan setting") -> InputError:
        return InputError(f"{why} (known: {', '.join(self.settings)})", field=field, value=setting)


DEFAULT_FIELD = FieldProperties()


def field_from_mapping(data: Any) -> FieldProperties:
    """A :class:`FieldProperties` from the ``[field]`` table of a model file (unknown keys refused)."""
    if not isinstance(data, dict):
        raise InputError("must be a table", field="field", value=data)
    values: dict[str, Any] = {}
    for key, raw in data.items():
        if key == "scan_time_s":
            if not isinstance(raw, dict):
                raise InputError("must be a table of setting = seconds", field="field.scan_time_s", value=raw)
            values["scan_times_s"] = tuple(
                (str(k), float(v) if isinstance(v, int) and not isinstance(v, bool) else v) for k, v in raw.items()
            )
        elif key in _NUMBERS:
            values[key] = float(raw) if isinstance(raw, int) and not isinstance(raw, bool) else raw
        elif key in ("default_setting", "source"):
            values[key] = str(raw)
        else:
            raise InputError("unknown key of a [field] table", field=f"field.{key}", value=raw)
    if "scan_times_s" in values and "default_setting" not in values:
        values["default_setting"] = values["scan_times_s"][0][0] if values["scan_times_s"] else ""
    return FieldProperties(**values)
