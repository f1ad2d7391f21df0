"""Field time of an ordered plan: per setup (walk to it, set up and level, scan, scan its targets), in
total, and split into sessions of a given length.

A setup's time is ``walk_m / walking_speed + setup_time + scan_time(setting) + targets x target_scan_time``
(:class:`~planner.instrument.field_table.FieldProperties`). Sessions are filled in visiting order: a setup that
would make the session longer than ``--session`` opens the next one (the walk to it included).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

from planner.core.errors import UsageError
from planner.instrument.field_table import FieldProperties

_UNITS = {"h": 3600.0, "min": 60.0, "s": 1.0}


def parse_duration(text: str) -> float:
    """Seconds of ``4h``, ``90min``, ``1h30min``, ``45s`` (a bare number is hours), e.g. ``--session 4h``."""
    raw = str(text).strip().lower().replace(" ", "")
    try:
        hours = float(raw)
    except ValueError:
        parts = re.fullmatch(r"((\d+(\.\d+)?)(h|min|s))+", raw)
        if not parts:
            raise UsageError(
                "expected a duration such as 4h, 90min, 1h30min or 45s", field="--session", value=text
            ) from None
        seconds = sum(float(v) * _UNITS[u] for v, _, u in re.findall(r"(\d+(\.\d+)?)(h|min|s)", raw))
    else:
        seconds = hours * 3600.0
    if not (math.isfinite(seconds) and seconds > 0):
        raise UsageError("must be a duration > 0", field="--session", value=text)
    return seconds


@dataclass(frozen=True)
class Setup:
    """One row of the sheet's timing: station ``id`` as setup ``number`` (from 1)."""

    number: int
    id: str
    walk_m: float
    walk_s: float
    setup_s: float
    scan_s: float
    targets_s: float
    session: int
    setting: str = ""  # the scan setting of this setup

    @property
    def station_s(self) -> float:
        """Time spent at the station (setup, scan, targets)."""
        return self.setup_s + self.scan_s + self.targets_s

    @property
    def total_s(self) -> float:
        return self.walk_s + self.station_s


@dataclass(frozen=True)
class Session:
    number: int
    setups: tuple[int, ...]  # setup numbers
    duration_s: float

    @property
    def label(self) -> str:
        return f"session {self.number}: setups {self.setups[0]}-{self.setups[-1]}, {self.duration_s / 60:.0f} min"


@dataclass(frozen=True)
class FieldTime:
    """Times of every setup, the total and the sessions; ``setting`` is the scan setting timed."""

    setups: tuple[Setup, ...]
    sessions: tuple[Session, ...]
    setting: str
    session_s: float | None

    @property
    def total_s(self) -> float:
        return sum(s.total_s for s in self.setups)

    @property
    def walking_s(self) -> float:
        return sum(s.walk_s for s in self.setups)

    @property
    def station_s(self) -> float:
        return sum(s.station_s for s in self.setups)

    def to_dict(self) -> dict[str, object]:
        sessions = [{"number": s.number, "setups": list(s.setups), "duration_s": s.duration_s} for s in self.sessions]
        times = {k: getattr(self, k) for k in ("setting", "total_s", "walking_s", "station_s")}
        return times | {"session_limit_s": self.session_s, "sessions": sessions}


def field_time(
    ids: Sequence[str],
    walks_m: Sequence[float],
    targets: Sequence[int],
    props: FieldProperties,
    setting: str | None = None,
    session_s: float | None = None,
    settings: Mapping[str, str] | None = None,
) -> FieldTime:
    """The field time of stations ``ids`` in visiting order; ``walks_m[k]``: the walk to station k (from the
    start for k = 0), ``targets[k]``: targets it scans. ``settings``: a scan setting per station id (a plan that
    chose them), in place of the one ``setting``."""
    named = [settings[i] if settings else (setting or props.default_setting) for i in ids]
    scans = [props.scan_time_s(n) for n in named]
    name = setting or props.default_setting
    if settings:
        names = sorted({settings[i] for i in ids})
        name = names[0] if len(names) == 1 else "per station: " + ", ".join(names)
    setups: list[Setup] = []
    sessions: list[Session] = []
    current: list[int] = []
    used = 0.0
    for k, (sid, walk, n_targets, scan, set_name) in enumerate(zip(ids, walks_m, targets, scans, named), 1):
        targets_s = n_targets * props.target_scan_time_s
        row = Setup(k, sid, walk, walk / props.walking_speed_m_s, props.setup_time_s, scan, targets_s, 0, set_name)
        if session_s is not None:
            if row.total_s > session_s:
                raise UsageError(
                    f"is shorter than setup {k} (station {sid}: {row.total_s / 60:.1f} min with the walk to it)",
                    field="--session",
                    value=f"{session_s / 60:g}min",
                )
            if current and used + row.total_s > session_s:
                sessions.append(Session(len(sessions) + 1, tuple(current), used))
                current, used = [], 0.0
        setups.append(replace(row, session=len(sessions) + 1))
        current.append(k)
        used += row.total_s
    if current:
        sessions.append(Session(len(sessions) + 1, tuple(current), used))
    return FieldTime(tuple(setups), tuple(sessions), name, session_s)
