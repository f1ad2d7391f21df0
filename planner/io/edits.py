"""The edits of a re-plan (``edits.json``, format ``planner-edits/1``): what changed on site since a plan was made,
read and checked against that plan and its site (:func:`read_edits`, :func:`edits_from_dict`).

Stations are named by the number the field sheet and plan.json print (``number``, the walking order) or by their
label (``label``, else ``id``). Every refusal is one line naming the file, the entry (``stations[3]``,
``areas[1]``) and the bad value (docs/field.md, "Re-planning on site", describes every key)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from planner.core.errors import InputError
from planner.core.fileio import read_json
from planner.site.geometry import as_vertices, check_simple_polygon

#: the format tag every edits file starts with
EDITS_FORMAT = "planner-edits/1"
#: the keys of an edits file, of a station entry, of an area, of the plan reference and of the crew
TOP_KEYS = frozenset({"format", "plan", "stations", "areas", "closed_zones", "crew", "time_left_h"})
STATION_KEYS = frozenset({"station", "status", "x", "y", "radius_m", "note"})
AREA_KEYS = frozenset({"kind", "polygon", "note"})
PLAN_KEYS = frozenset({"instance", "fingerprint"})
CREW_KEYS = frozenset({"station", "x", "y"})
STATUSES = ("done", "blocked")
AREA_KINDS = ("obstacle", "closed")
#: the least radius a blocked station keeps clear where neither the entry nor the plan gives a larger one (a
#: tripod's own footprint: a plan's disc of 0 m means the position is exact, not that a van leaves room beside it)
MIN_BLOCKED_RADIUS_M = 0.5
#: where a station done in an earlier re-plan comes from (plan.json's station entry, ``"status": "done"``)
CARRIED_ROW = "plan.json stations"


@dataclass(frozen=True, kw_only=True)
class PlannedStation:
    """A station of the edited plan as plan.json records it: its walking-order ``number``, ``label``, ``id``,
    position and tripod disc."""

    number: int
    label: str
    id: str
    xy: tuple[float, float]
    tripod_radius_m: float


@dataclass(frozen=True, kw_only=True)
class StationEdit:
    """One station marked ``done`` (at ``xy``: as planned, or where it really stood) or ``blocked`` (nothing may
    stand within ``radius_m`` of its planned position); ``entry``: where the file gives it (``stations[2]``)."""

    station: PlannedStation
    status: str
    xy: tuple[float, float]
    moved: bool
    radius_m: float
    entry: str


@dataclass(frozen=True, kw_only=True)
class AreaEdit:
    """A polygon drawn on site (site frame, metres): an ``obstacle`` (no station inside, sight blocked) or a
    ``closed`` area (no station inside; sight passes)."""

    kind: str
    polygon: tuple[tuple[float, float], ...]
    note: str
    entry: str


@dataclass(frozen=True, kw_only=True)
class Edits:
    """The edits of one re-plan, checked against its plan: ``file`` names them in messages."""

    file: str
    stations: tuple[StationEdit, ...] = ()
    areas: tuple[AreaEdit, ...] = ()
    closed_zones: tuple[str, ...] = ()
    crew_station: PlannedStation | None = None
    crew_xy: tuple[float, float] | None = None
    time_left_h: float | None = None
    raw: dict[str, Any] | None = None

    @property
    def done(self) -> tuple[StationEdit, ...]:
        return tuple(e for e in self.stations if e.status == "done")

    @property
    def blocked(self) -> tuple[StationEdit, ...]:
        return tuple(e for e in self.stations if e.status == "blocked")

    def lines(self) -> list[str]:
        """The edits in words, a line each kind."""
        moved = sum(e.moved for e in self.done)
        carried = sum(e.entry.startswith(CARRIED_ROW) for e in self.done)
        before = f", {carried} of them done before (plan.json)" if carried else ""
        out = [f"edits {self.file}: {len(self.done)} done ({moved} moved{before}), {len(self.blocked)} blocked"]
        if self.areas:
            kinds = [sum(a.kind == k for a in self.areas) for k in AREA_KINDS]
            out.append(f"areas: {kinds[0]} obstacle(s), {kinds[1]} closed")
        if self.closed_zones:
            out.append(f"closed zones: {', '.join(self.closed_zones)}")
        if self.crew_xy is not None:
            at = f"station {self.crew_station.number}" if self.crew_station else "a point"
            out.append(f"crew at {at} ({self.crew_xy[0]:.2f}, {self.crew_xy[1]:.2f})")
        if self.time_left_h is not None:
            out.append(f"time left today: {self.time_left_h:g} h")
        return out


def planned_stations(meta: dict[str, Any]) -> tuple[PlannedStation, ...]:
    """The stations of a plan.json (its ``stations`` list), numbered as the file numbers them (plan order where
    it records no numbers)."""
    out = []
    for k, s in enumerate(meta.get("stations") or [], 1):
        if not isinstance(s, dict):
            continue
        number = s.get("number")
        radius = s.get("tripod_radius_m")
        out.append(
            PlannedStation(
                number=int(number) if isinstance(number, int) and not isinstance(number, bool) else k,
                label=str(s.get("label") or s.get("id")),
                id=str(s.get("id")),
                xy=(float(s["x"]), float(s["y"])),
                tripod_radius_m=float(radius) if isinstance(radius, (int, float)) else 0.0,
            )
        )
    return tuple(out)


def read_edits(path: str | Path, meta: dict[str, Any], zone_ids: tuple[str, ...]) -> Edits:
    """The edits file ``path`` read and checked against the plan (``meta``: its plan.json) and the site's zones."""
    return edits_from_dict(read_json(path), str(path), meta, zone_ids)


def edits_from_dict(data: Any, file: str, meta: dict[str, Any], zone_ids: tuple[str, ...]) -> Edits:
    """Edits given as data (the parsed JSON of an edits file; ``file`` names it in messages), checked against the
    plan ``meta`` and the site's ``zone_ids``. Raises InputError (exit 3), one line: unknown keys, a station not in
    the plan or marked twice, a zone not in the site, a polygon of fewer than 3 vertices or of non-numbers, a
    negative radius, a plan reference that names another plan."""
    r = _Reader(file)
    top = r.obj(data, "edits", TOP_KEYS)
    if top.get("format") != EDITS_FORMAT:
        raise r.fail(f"must be {EDITS_FORMAT!r}", field="format", value=top.get("format"))
    _check_plan(r, top.get("plan"), meta)
    stations = planned_stations(meta)
    edits = tuple(_station(r, e, f"stations[{k}]", stations) for k, e in enumerate(r.items(top, "stations"), 1))
    seen: dict[int, str] = {}
    for e in edits:
        if e.station.number in seen:
            raise r.fail(
                f"station marked twice (first in {seen[e.station.number]})",
                row=e.entry,
                field="station",
                value=e.station.number,
            )
        seen[e.station.number] = e.entry
    areas = tuple(_area(r, a, f"areas[{k}]") for k, a in enumerate(r.items(top, "areas"), 1))
    zones = []
    for k, z in enumerate(r.items(top, "closed_zones"), 1):
        if not isinstance(z, str) or z not in zone_ids:
            raise r.fail(
                f"not a zone of the site (zones: {', '.join(zone_ids)})",
                row=f"closed_zones[{k}]",
                field="zone",
                value=z,
            )
        if z in zones:
            raise r.fail("zone closed twice", row=f"closed_zones[{k}]", field="zone", value=z)
        zones.append(z)
    crew_station, crew_xy = _crew(r, top.get("crew"), stations)
    hours = None
    if top.get("time_left_h") is not None:
        hours = r.number(top["time_left_h"], "time_left_h", None)
        if hours <= 0:
            raise r.fail("must be a number of hours > 0", field="time_left_h", value=top["time_left_h"])
    return Edits(
        file=file,
        stations=edits,
        areas=areas,
        closed_zones=tuple(zones),
        crew_station=crew_station,
        crew_xy=crew_xy,
        time_left_h=hours,
        raw=top,
    )


def with_plan_done(edits: Edits, meta: dict[str, Any], plan_file: str) -> Edits:
    """``edits`` with the stations the plan records as done (``"status": "done"`` in plan.json: done in an earlier
    re-plan, at the position written there) added as done, so that a re-plan of a re-plan keeps them without being
    told again. An edits entry marking one done again is kept (its position wins); one blocking it is refused
    (InputError: the scan exists), as is a station status in plan.json other than done."""
    marked = {e.station.id: e for e in edits.stations}
    by_id = {s.id: s for s in planned_stations(meta)}
    carried = []
    for k, row in enumerate(meta.get("stations") or [], 1):
        if not isinstance(row, dict) or "status" not in row:
            continue
        if row["status"] != "done":
            raise InputError(
                "must be 'done' (a station done in an earlier re-plan)",
                file=plan_file,
                row=f"stations[{k}]",
                field="status",
                value=row["status"],
            )
        s = by_id[str(row.get("id"))]
        again = marked.get(s.id)
        if again is not None and again.status != "done":
            raise InputError(
                f"station {s.number} ({s.label}) was done in an earlier re-plan ({plan_file}); it cannot be "
                f"{again.status}",
                file=edits.file,
                row=again.entry,
                field="status",
                value=again.status,
            )
        if again is None:
            carried.append(
                StationEdit(station=s, status="done", xy=s.xy, moved=False, radius_m=0.0, entry=f"{CARRIED_ROW}[{k}]")
            )
    if not carried:
        return edits
    return replace(edits, stations=(*carried, *edits.stations))


class _Reader:
    """Holds the file name, so that every refusal names it."""

    def __init__(self, file: str) -> None:
        self.file = file

    def fail(self, message: str, **where: Any) -> InputError:
        return InputError(message, file=self.file, **where)

    def obj(self, value: Any, what: str, allowed: frozenset[str], row: str | None = None) -> dict[str, Any]:
        if not isinstance(value, dict):
            raise self.fail("must be an object", row=row, field=what, value=type(value).__name__)
        unknown = sorted(set(value) - allowed)
        if unknown:
            raise self.fail(f"unknown key (allowed: {', '.join(sorted(allowed))})", row=row, field=unknown[0])
        return value

    def items(self, data: dict[str, Any], key: str) -> list[Any]:
        value = data.get(key, [])
        if not isinstance(value, list):
            raise self.fail("must be a list", field=key, value=type(value).__name__)
        return value

    def number(self, value: Any, field: str, row: str | None) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.fail("must be a finite number", row=row, field=field, value=value)
        return float(value)


def _check_plan(r: _Reader, ref: Any, meta: dict[str, Any]) -> None:
    """The optional reference to the plan the edits were made on, checked against plan.json."""
    if ref is None:
        return
    ref = r.obj(ref, "plan", PLAN_KEYS)
    recorded = {"instance": meta.get("instance"), "fingerprint": (meta.get("pool") or {}).get("fingerprint")}
    for key in ("instance", "fingerprint"):
        if key in ref and ref[key] != recorded[key]:
            raise r.fail(f"names another plan (this plan's: {recorded[key]!r})", field=f"plan.{key}", value=ref[key])


def _find(r: _Reader, ref: Any, stations: tuple[PlannedStation, ...], row: str, field: str) -> PlannedStation:
    """The planned station named by its number or its label (or id)."""
    if isinstance(ref, int) and not isinstance(ref, bool):
        hit = [s for s in stations if s.number == ref]
        what = f"numbers 1-{len(stations)}" if stations else "no stations"
    elif isinstance(ref, str):
        hit = [s for s in stations if ref in (s.label, s.id)]
        what = "labels as on the field sheet"
    else:
        raise r.fail("must be a station number or label", row=row, field=field, value=ref)
    if not hit:
        raise r.fail(f"not a station of the plan ({what})", row=row, field=field, value=ref)
    return hit[0]


def _station(r: _Reader, value: Any, row: str, stations: tuple[PlannedStation, ...]) -> StationEdit:
    e = r.obj(value, "station entry", STATION_KEYS, row)
    if "station" not in e:
        raise r.fail("missing", row=row, field="station")
    s = _find(r, e["station"], stations, row, "station")
    status = e.get("status")
    if status not in STATUSES:
        raise r.fail(f"must be one of {', '.join(STATUSES)}", row=row, field="status", value=status)
    has_xy = [k for k in ("x", "y") if k in e]
    if has_xy and status != "done":
        raise r.fail("only a done station has a measured position", row=row, field=has_xy[0], value=e[has_xy[0]])
    if len(has_xy) == 1:
        raise r.fail("a measured position needs both x and y", row=row, field=has_xy[0], value=e[has_xy[0]])
    if "radius_m" in e and status != "blocked":
        raise r.fail("only a blocked station has a radius", row=row, field="radius_m", value=e["radius_m"])
    xy = s.xy
    if has_xy:
        xy = (r.number(e["x"], "x", row), r.number(e["y"], "y", row))
    radius = max(s.tripod_radius_m, MIN_BLOCKED_RADIUS_M)
    if e.get("radius_m") is not None:
        radius = r.number(e["radius_m"], "radius_m", row)
        if radius < 0:
            raise r.fail("must be a radius >= 0 m", row=row, field="radius_m", value=e["radius_m"])
    return StationEdit(station=s, status=status, xy=xy, moved=xy != s.xy, radius_m=radius, entry=row)


def _area(r: _Reader, value: Any, row: str) -> AreaEdit:
    a = r.obj(value, "area", AREA_KEYS, row)
    kind = a.get("kind")
    if kind not in AREA_KINDS:
        raise r.fail(f"must be one of {', '.join(AREA_KINDS)}", row=row, field="kind", value=kind)
    if "polygon" not in a:
        raise r.fail("missing", row=row, field="polygon")
    try:
        xy = as_vertices(a["polygon"], what="polygon", zone=None)
        check_simple_polygon(xy, what="polygon")
    except InputError as err:
        at = f"{err.row}: " if err.row else ""
        raise r.fail(f"{at}{err.message}", row=row, field="polygon", value=_short(a["polygon"])) from None
    note = a.get("note", "")
    if not isinstance(note, str):
        raise r.fail("must be a text", row=row, field="note", value=note)
    return AreaEdit(kind=kind, polygon=tuple((float(x), float(y)) for x, y in xy), note=note, entry=row)


def _crew(
    r: _Reader, value: Any, stations: tuple[PlannedStation, ...]
) -> tuple[PlannedStation | None, tuple[float, float] | None]:
    """Where the crew stands: at a planned station, or at a point."""
    if value is None:
        return None, None
    c = r.obj(value, "crew", CREW_KEYS)
    if "station" in c:
        if "x" in c or "y" in c:
            raise r.fail("give a station or a point, not both", field="crew.x" if "x" in c else "crew.y")
        s = _find(r, c["station"], stations, "crew", "station")
        return s, s.xy
    if "x" not in c or "y" not in c:
        raise r.fail("needs a station, or both x and y", field="crew")
    return None, (r.number(c["x"], "crew.x", None), r.number(c["y"], "crew.y", None))


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
