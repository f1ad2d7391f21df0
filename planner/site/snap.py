"""Zones placed together are snapped onto each other, so that a shared wall is ONE line.

Placements from printed tables leave the two faces of a wall a few mm to a few cm apart, so one face lies a
hair in front of the other and hides it from its own room. Zones are taken largest first; each vertex of a
placed zone within ``SNAP_M`` of a vertex of a zone already taken moves onto it, else within ``SNAP_M`` of
a wall of one onto that wall. Every move is noted in the zone's notes; vertex count and numbering stay.
A zone accepted with a misclosure has vertices known only to within what the compass rule moved them
(``max_vertex_shift_m``): they snap within ``SNAP_M`` plus that shift.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import shapely
from shapely.ops import nearest_points

from planner.site.model import SITE_FRAME, Zone

#: the largest misfit between two faces of one wall that snapping closes
SNAP_M = 0.20


def snap_zones(zones: tuple[Zone, ...], movable: set[str], snap_m: float = SNAP_M) -> tuple[Zone, ...]:
    """The zones with each movable (placed) zone's vertices snapped onto zones taken before it."""
    order = sorted((z for z in zones if z.frame == SITE_FRAME), key=lambda z: (z.id in movable, -z.area_m2))
    taken: list[Zone] = []
    out = {z.id: z for z in zones}
    for z in order:
        if z.id in movable and taken:
            shift = z.closure.max_vertex_shift_m if z.closure is not None and z.misclosed else 0.0
            out[z.id] = _snap(z, taken, snap_m + shift)
        taken.append(out[z.id])
    return tuple(out[z.id] for z in zones)


def _snap(zone: Zone, taken: list[Zone], snap_m: float) -> Zone:
    verts = np.concatenate([t.xy for t in taken])
    edges = shapely.union_all([shapely.LinearRing(t.xy) for t in taken])
    xy = zone.xy.copy()
    for k, p in enumerate(zone.xy):
        d = np.hypot(*(verts - p).T)
        if d.min() <= snap_m:
            xy[k] = verts[int(d.argmin())]
            continue
        pt = shapely.Point(*p)
        if edges.distance(pt) <= snap_m:
            q = nearest_points(edges, pt)[0]
            xy[k] = (q.x, q.y)
    moved = float(np.max(np.hypot(*(xy - zone.xy).T)))
    if moved == 0.0:
        return zone
    note = f"snapped onto neighbouring zones: largest vertex move {moved:.3f} m"
    return replace(zone, vertices=tuple(map(tuple, xy.tolist())), notes=zone.notes + (note,))
