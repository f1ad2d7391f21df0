"""Registration groups by where a station stands: the accessible area it serves from.

A candidate used to take the registration group of the zone-side whose geometry proposed it, and
duplicates were dropped in pool order; on a plant of many outside-scanned objects most candidates
then fell to the first zone (the grid of its reach covers the whole site), and connectivity was
enforced for that zone only. Here the group is decided by the station's position:

- inside an inside-scanned zone (the smallest one that holds it): that zone's interior,
  ``"<zone>/inside"`` (a room is scanned from within; its walls cut it off from the rest);
- otherwise the connected part of its frame's open ground it stands in: the frame's extent (the
  site boundary, or the zones' bounding box grown by 1 km) less every zone polygon, obstacle and
  no-go area. A frame whose open ground is one piece and holds one outside zone keeps the old label
  ``"<zone>/outside"``; otherwise the label is ``"<frame>/area <k>"`` (k from 1, pieces ordered by
  their lowest-left point, so the labels do not depend on zone order).

Each group is one accessible area: the stations standing in it must form one registration bundle.
A station serves from there every zone face its coverage row holds.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import shapely

from planner.candidates.model import Candidate
from planner.site.model import SITE_FRAME, ScanSide, Site

#: open ground of a frame without a boundary reaches this far beyond its zones
FAR_M = 1000.0


def open_ground(site: Site, frame: str) -> list[shapely.Polygon]:
    """The connected pieces of ``frame``'s open ground (outside every zone, obstacle and no-go area)."""
    polys = [z.polygon for z in site.zones if z.frame == frame]
    if frame == SITE_FRAME:
        polys += [shapely.Polygon(o.vertices) for o in site.obstacles]
        polys += [shapely.Polygon(n.vertices) for n in site.no_go_areas]
    taken = shapely.union_all([shapely.Polygon(p.exterior) for p in polys])
    if frame == SITE_FRAME and site.boundary is not None:
        extent = shapely.Polygon(site.boundary)
    else:
        x0, y0, x1, y1 = shapely.bounds(taken)
        extent = shapely.box(x0 - FAR_M, y0 - FAR_M, x1 + FAR_M, y1 + FAR_M)
    free = shapely.difference(extent, taken)
    pieces = [g for g in getattr(free, "geoms", [free]) if not g.is_empty and g.area > 0]
    return sorted(pieces, key=lambda g: (round(g.bounds[1], 6), round(g.bounds[0], 6)))


def registration_groups(site: Site, candidates: Sequence[Candidate]) -> tuple[str, ...]:
    """The registration group (accessible area) of every candidate, as a label."""
    out = [""] * len(candidates)
    by_frame: dict[str, list[int]] = {}
    for k, c in enumerate(candidates):
        by_frame.setdefault(c.frame, []).append(k)
    for frame, idx in by_frame.items():
        xy = np.array([candidates[k].xy for k in idx], dtype=float).reshape(-1, 2)
        best_area = np.full(len(idx), np.inf)
        rooms = [z for z in site.zones if z.frame == frame and ScanSide.INSIDE in z.scan_side.sides]
        for z in rooms:
            hit = shapely.contains_xy(shapely.Polygon(z.polygon.exterior), xy[:, 0], xy[:, 1]) & (z.area_m2 < best_area)
            for j in np.flatnonzero(hit):
                out[idx[j]] = f"{z.id}/inside"
            best_area[hit] = z.area_m2
        rest = np.flatnonzero(~np.isfinite(best_area))
        if rest.size == 0:
            continue
        pieces = open_ground(site, frame)
        outside = [z for z in site.zones if z.frame == frame and ScanSide.OUTSIDE in z.scan_side.sides]
        if len(pieces) <= 1:
            label = f"{outside[0].id}/outside" if len(outside) == 1 else f"{frame}/area 1"
            for j in rest:
                out[idx[j]] = label
            continue
        pts = shapely.points(xy[rest])
        dist = np.stack([shapely.distance(p, pts) for p in pieces])  # 0 inside a piece; else the nearest
        for j, k in zip(rest, np.argmin(dist, axis=0)):
            out[idx[j]] = f"{frame}/area {k + 1}"
    return tuple(out)
