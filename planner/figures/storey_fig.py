"""A floor plan of one frame (a building storey): every room with its openings, and the stations.

Rooms are drawn filled and named, blocks (columns, stairs) hatched, openings (doors, windows) as coloured gaps on their
walls, each station as a triangle with its id and its zone's colour.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Polygon as PolygonPatch

from planner.figures.base import PLAN_MARGIN, frame_axes
from planner.figures.labels import PointLabel, finish_plans
from planner.site.model import Site, Wall, Zone

OPENING_COLOUR = {"door": "tab:orange", "gate": "tab:brown", "window": "tab:cyan", "passage": "tab:olive"}


def storey_figure(site: Site, stations: Sequence[Any], frame: str, title: str = "") -> Figure:
    """Rooms of ``frame`` with their openings and the ``stations`` (objects with ``id``, ``zone``, ``frame``, ``x``,
    ``y``) that stand in that frame."""
    fig = Figure(figsize=(8, 6))
    ax = fig.add_subplot()
    zones = [z for z in site.zones if z.frame == frame]
    colours = {z.id: f"C{k % 10}" for k, z in enumerate(zones)}
    for z in zones:
        _room(ax, z, colours[z.id])
    mine = [s for s in stations if s.frame == frame]
    for s in mine:
        ax.plot([s.x], [s.y], marker="^", ms=9, color=colours.get(s.zone, "red"), mec="black", zorder=5)
    ax.set_title(title or f"{frame}: {len(zones)} rooms, {len(mine)} stations")
    frame_axes(ax, PLAN_MARGIN)
    labels = [PointLabel(s.x, s.y, str(s.id), f"station:{s.id}", 9.0) for s in mine] + [_name(z) for z in zones]
    finish_plans(fig, [(ax, frame, labels)], fontsize=6)  # last: scale bar and labels in the final layout
    return fig


def _room(ax: Any, zone: Zone, colour: str) -> None:
    inside = zone.scan_side.value == "inside"
    ax.add_patch(
        PolygonPatch(zone.xy, closed=True, fc=colour if inside else "none", alpha=0.15 if inside else 1, ec="none")
    )
    for ring in zone.rings:
        closed = np.vstack([ring, ring[:1]])
        ax.plot(closed[:, 0], closed[:, 1], color="black", lw=1.2)
    for hole in zone.holes:
        ax.add_patch(PolygonPatch(np.asarray(hole), closed=True, fc="0.6", ec="black", hatch="//", lw=0.8))
    for op in zone.openings:
        draw_gap(ax, zone.walls[op.wall - 1], op.s0_m, op.s1_m, OPENING_COLOUR.get(op.kind, "tab:orange"))


def _name(zone: Zone) -> PointLabel:
    """The room's name, placed next to a point inside it (with the other labels, so that it meets none)."""
    cx, cy = zone.polygon.representative_point().coords[0]
    return PointLabel(cx, cy, zone.id.rsplit("/", 1)[-1], f"room:{zone.id}", 0.0, 8.0)


def draw_obstacles(ax: Any, site: Site, zorder: float | None = None) -> None:
    """The site's obstacles (grey, hatched, labelled with their height) and no-go areas (red, hatched)."""
    for ob in site.obstacles:
        label = f"obstacle ({ob.height_m:g} m)"
        ax.add_patch(PolygonPatch(ob.vertices, fc="0.6", ec="0.3", hatch="xx", alpha=0.6, label=label, zorder=zorder))
    for a in site.no_go_areas:
        ax.add_patch(
            PolygonPatch(a.vertices, fc="mistyrose", ec="red", hatch="//", alpha=0.5, label="no-go area", zorder=zorder)
        )


def draw_gap(ax: Any, wall: Wall, s0_m: float, s1_m: float, colour: str) -> None:
    """Draw the opening from ``s0_m`` to ``s1_m`` along ``wall`` as a coloured gap."""
    a, b = np.asarray(wall.start, dtype=float), np.asarray(wall.end, dtype=float)
    u = (b - a) / wall.length_m
    p, q = a + s0_m * u, a + s1_m * u
    ax.plot([p[0], q[0]], [p[1], q[1]], color=colour, lw=4, solid_capstyle="butt", zorder=4)
