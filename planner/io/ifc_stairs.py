"""Stairs of a building model: which zone of one storey a stair leads up to which zone of the next.

Every ``IfcStair`` of a read storey (and every ``IfcStairFlight`` that is not part of one) becomes a
:class:`planner.site.stairs.Stair` when the storey above is read too (docs/ifc.md): its footprint and z extent from its
body (else its parts'), in world coordinates; its lower and upper zones the inside zones of its storey and of the next
one up that meet most of its footprint widened by ``NEAR_M``. A stair whose top stays more than ``REACH_TOL_M`` below
the next storey's elevation, or with no zone below or above, is left out.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import shapely

from planner.io.ifc_geom import Solid, largest_polygon, solid_of
from planner.site.model import ScanSide, Zone
from planner.site.stairs import Stair

#: a zone within this distance (m) of the stair's footprint may be its lower or upper zone
NEAR_M = 0.5
#: a stair's top may stay this far (m) below the next storey's elevation and still reach it
REACH_TOL_M = 0.5


@dataclass(frozen=True, kw_only=True)
class StoreyZones:
    """One read storey: its entity, elevation (m) and the zones read from it."""

    entity: Any
    elevation_m: float
    zones: tuple[Zone, ...]


def _stair_solid(stair: Any, settings: Any) -> Solid | None:
    """The stair's own solid, else the union of its parts' (flights, landings)."""
    import ifcopenshell.util.element as ue

    own = solid_of(stair, settings)
    if own is not None:
        return own
    parts = [s for e in ue.get_decomposition(stair) if (s := solid_of(e, settings)) is not None]
    if not parts:
        return None
    foot = shapely.union_all([s.footprint for s in parts])
    return Solid(foot, min(s.z_min_m for s in parts), max(s.z_max_m for s in parts))


def _stairs_of(storey: Any) -> list[Any]:
    import ifcopenshell.util.element as ue

    out = []
    for e in ue.get_decomposition(storey):
        if e.is_a("IfcStair"):
            out.append(e)
        elif e.is_a("IfcStairFlight"):
            agg = ue.get_aggregate(e)
            if agg is None or not agg.is_a("IfcStair"):
                out.append(e)
    return out


def _best_zone(zones: Sequence[Zone], near: shapely.Geometry) -> Zone | None:
    """The inside zone that meets most of ``near`` (None: none meets it)."""
    scored = [
        (z.polygon.intersection(near).area, k, z)
        for k, z in enumerate(zones)
        if ScanSide.INSIDE in z.scan_side.sides and z.polygon.intersects(near)
    ]
    scored = [s for s in scored if s[0] > 0]
    return max(scored, key=lambda s: (s[0], -s[1]))[2] if scored else None


def read_stairs(storeys: Sequence[StoreyZones], settings: Any) -> tuple[Stair, ...]:
    """The stairs between consecutive read storeys (``storeys`` sorted by elevation; see the module docstring)."""
    out: list[Stair] = []
    for lower, upper in zip(storeys, storeys[1:]):
        for element in _stairs_of(lower.entity):
            solid = _stair_solid(element, settings)
            if solid is None or solid.z_max_m < upper.elevation_m - REACH_TOL_M:
                continue
            foot = largest_polygon(shapely.simplify(solid.footprint, 0.01))
            if foot.is_empty or foot.area <= 0:
                continue
            near = foot.buffer(NEAR_M)
            below, above = _best_zone(lower.zones, near), _best_zone(upper.zones, near)
            if below is None or above is None:
                continue
            ring = tuple((round(float(x), 4), round(float(y), 4)) for x, y in foot.exterior.coords[:-1])
            name = str(element.Name or element.GlobalId)
            z = dict(z_min_m=round(solid.z_min_m, 4), z_max_m=round(solid.z_max_m, 4))
            out.append(Stair(name=name, lower_zone=below.id, upper_zone=above.id, footprint=ring, **z))
    return tuple(out)
