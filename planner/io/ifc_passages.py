"""Passages of a building model that no door fills: bare wall openings and rooms open to each other.

Both are read as openings of kind ``passage`` (walked and seen through as a door,
:data:`planner.coverage.openings.PASSABLE`; docs/ifc.md gives the rules):

- **an unfilled wall opening** (:func:`unfilled_openings`): an ``IfcOpeningElement`` that voids a wall, is filled by
  nothing and is no recess, low and high enough to walk through; its footprint clipped to its wall's and placed on the
  zone walls it stands in like a door's;
- **an open boundary** (:func:`open_boundaries`): two spaces of one storey that touch with no wall between them
  (exporters write a *virtual* space boundary there, which is not read: the geometry says the same).

Stretches narrower than :data:`MIN_WIDTH_M` stay wall either way (no one carries a scanner through them).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import shapely

from planner.io.ifc_geom import Solid, solid_of
from planner.site.model import Opening, Zone

#: an unfilled opening's bottom may lie this far (m) above its storey's floor: a threshold or a step one walks over;
#: a window's sill (0.6 m and up) is higher
MAX_SILL_M = 0.3
#: an unfilled opening this high (m) or higher is walked through with a scanner on its tripod (1.8 m: a low door,
#: head bowed); lower ones are hatches or service openings
MIN_HEIGHT_M = 1.8
#: a passage at least this wide (m) along its wall: a person with a tripod; narrower stretches stay wall
MIN_WIDTH_M = 0.5
#: two spaces whose outlines lie this close (m) touch: no wall (the thinnest partition is thicker) stands between
ABUT_M = 0.05
#: a wall's footprint shrunk by this much (m) before it cuts an open boundary (walls that end on the boundary
#: cut nothing)
WALL_SHRINK_M = 0.01


def unfilled_openings(model: Any, storey: Any, floor_z_m: float, settings: Any) -> list[tuple[str, Solid]]:
    """The name (else GlobalId) and solid, footprint clipped to its wall's, of every unfilled wall opening of ``storey``
    that one can walk through; ``floor_z_m``: the world z of the storey's floor."""
    import ifcopenshell.util.element as ue

    out = []
    for op in model.by_type("IfcOpeningElement"):
        if op.HasFillings or str(getattr(op, "PredefinedType", None) or "") == "RECESS":
            continue
        hosts = [r.RelatingBuildingElement for r in op.VoidsElements or ()]
        if not hosts or not hosts[0].is_a("IfcWall") or ue.get_container(hosts[0]) != storey:
            continue
        solid = solid_of(op, settings)
        if solid is None or solid.z_min_m - floor_z_m > MAX_SILL_M or solid.height_m < MIN_HEIGHT_M:
            continue
        wall = solid_of(hosts[0], settings)
        foot = solid.footprint if wall is None else solid.footprint.intersection(wall.footprint)
        if foot.is_empty or foot.area <= 0:
            foot = solid.footprint
        out.append((str(op.Name or op.GlobalId), Solid(foot, solid.z_min_m, solid.z_max_m)))
    return out


def wide_enough(op: Opening) -> bool:
    """True when the opening is at least :data:`MIN_WIDTH_M` wide along its wall."""
    return op.s1_m - op.s0_m >= MIN_WIDTH_M


def open_boundaries(zones: Sequence[Zone], walls: Sequence[shapely.Geometry]) -> dict[str, list[Opening]]:
    """Zone id to the passages of that zone (only zones that have some) to the zones of ``zones`` (the inside zones of
    one storey) it touches where no footprint of ``walls`` stands between, named ``open to <room>``. Each stretch of a
    zone's wall within :data:`ABUT_M` of another zone is one."""
    cut = shapely.union_all([w.buffer(-WALL_SHRINK_M, join_style="mitre") for w in walls]) if walls else None
    polys = {z.id: z.polygon for z in zones}
    near = {z.id: p.buffer(ABUT_M, join_style="mitre") for z, p in zip(zones, polys.values(), strict=True)}
    out: dict[str, list[Opening]] = {}
    for z in zones:
        for w in z.walls:
            a, b = np.asarray(w.start, float), np.asarray(w.end, float)
            u = (b - a) / w.length_m
            line = shapely.LineString([a, b])
            for other in zones:
                if other.id == z.id or not near[other.id].intersects(line):
                    continue
                shared = line.intersection(near[other.id])
                if cut is not None:
                    shared = shared.difference(cut)
                for part in getattr(shared, "geoms", [shared]):
                    if not isinstance(part, shapely.LineString) or part.is_empty:
                        continue
                    s = (shapely.get_coordinates(part) - a) @ u
                    s0, s1 = max(0.0, float(s.min())), min(w.length_m, float(s.max()))
                    # the widened outline runs ABUT_M past the other zone's corners: not into the wall's middle
                    s0, s1 = (s0 + ABUT_M if s0 > 1e-6 else s0), (s1 - ABUT_M if s1 < w.length_m - 1e-6 else s1)
                    if s1 - s0 < MIN_WIDTH_M:
                        continue
                    name = f"open to {other.id.rsplit('/', 1)[-1]}"
                    op = Opening(wall=w.index, s0_m=round(s0, 4), s1_m=round(s1, 4), kind="passage", name=name)
                    out.setdefault(z.id, []).append(op)
    return out
