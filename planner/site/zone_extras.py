"""The JSON keys that act on zones already read: ``placements`` (table zones into the site frame)
and ``openings`` (doors, gates, windows on zone walls). See docs/instance-format.md."""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Protocol

from planner.core.errors import InputError
from planner.site.features import OPENING_KINDS, SITE_FRAME, Opening
from planner.site.model import Zone
from planner.site.placement import Placement, place_zone
from planner.site.snap import snap_zones


class _Reads(Protocol):
    file: str

    def fail(self, message: str, **where: Any) -> InputError: ...

    def obj(self, value: Any, what: str, allowed: set[str], **where: Any) -> dict[str, Any]: ...

    def num(self, data: dict[str, Any], key: str, **where: Any) -> float: ...


def place_and_open(r: _Reads, zones: tuple[Zone, ...], placements: Any, openings: list[Any]) -> tuple[Zone, ...]:
    """Zones with their placements applied and snapped together (:mod:`planner.site.snap`), then their
    openings attached (openings are in wall terms, so they do not move with a placement)."""
    by_id = {z.id: z for z in zones}
    table = r.obj(placements, "placements", set(by_id))
    out = dict(by_id)
    for zid, raw in table.items():
        if by_id[zid].frame == SITE_FRAME:
            raise r.fail("only a table zone (own frame) takes a placement", zone=zid, field="placements")
        d = r.obj(raw, "placement", {"origin", "rotation_deg", "source"}, zone=zid)  # source: for the reader
        origin = d.get("origin")
        if not isinstance(origin, list) or len(origin) != 2:
            raise r.fail("origin must be [x, y] in metres", zone=zid, field="placements.origin", value=origin)
        xy = tuple(r.num({"origin": v}, "origin", zone=zid) for v in origin)
        out[zid] = place_zone(by_id[zid], Placement((xy[0], xy[1]), r.num(d, "rotation_deg", zone=zid)))
    if table:
        out = {z.id: z for z in snap_zones(tuple(out[z.id] for z in zones), set(table))}
    grouped: dict[str, list[Opening]] = {}
    for k, raw in enumerate(openings, 1):
        zid, op = _opening(r, raw, k)
        if zid not in by_id:
            raise r.fail("opening names no zone of this instance", zone=zid, row=f"openings[{k}]", field="zone")
        grouped.setdefault(zid, []).append(op)
    for zid, ops in grouped.items():
        out[zid] = replace(out[zid], openings=out[zid].openings + tuple(ops))
    return tuple(out[z.id] for z in zones)


def _opening(r: _Reads, raw: Any, k: int) -> tuple[str, Opening]:
    where = {"row": f"openings[{k}]"}
    d = r.obj(raw, "opening", {"zone", "wall", "s0_m", "s1_m", "kind", "name"}, **where)
    zid = d.get("zone")
    if not isinstance(zid, str) or not zid:
        raise r.fail("must name a zone", field="zone", value=zid, **where)
    kind = d.get("kind", "door")
    if kind not in OPENING_KINDS:
        raise r.fail(f"must be one of {', '.join(OPENING_KINDS)}", zone=zid, field="kind", value=kind, **where)
    wall = r.num(d, "wall", zone=zid, **where)
    if wall != int(wall):
        raise r.fail("must be a whole wall number", zone=zid, field="wall", value=wall, **where)
    s0, s1 = r.num(d, "s0_m", zone=zid, **where), r.num(d, "s1_m", zone=zid, **where)
    if not 0.0 <= s0 < s1:  # checked here, where the zone is known (the Opening itself knows only its name)
        raise r.fail("needs 0 <= s0_m < s1_m", zone=zid, field="s0_m..s1_m", value=f"{s0:g}..{s1:g}", **where)
    return zid, Opening(int(wall), s0, s1, kind, str(d.get("name", f"{kind} {k}")))
