"""Plan figure of one zone-side: walls coloured by coverage (count | best incidence), uncovered in red, line width by
wall height, obstacles and no-go areas, numbered stations by kind, movement fields and tripod discs."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.colors import BoundaryNorm, ListedColormap, Normalize
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon

from planner.core.checks import argument
from planner.coverage.targets import SIDE_CODE
from planner.figures.base import PLAN_MARGIN, PNG_DPI, frame_axes, legend_once, png_bytes
from planner.figures.forked import drawn
from planner.figures.labels import PointLabel, finish_plans
from planner.figures.layout import Layouts
from planner.figures.storey_fig import draw_obstacles
from planner.plan.outcome import Outcome
from planner.plan.plan_dict import StationNumbering
from planner.site.candidate import CandidateKind
from planner.site.model import SITE_FRAME, ScanSide

MARKERS = {
    CandidateKind.VERTEX: ("^", "vertex K^B"),
    CandidateKind.WALL: ("s", "wall K^C"),
    CandidateKind.CIRCLE: ("o", "circle"),
    CandidateKind.FIELD: ("D", "field sample"),
    CandidateKind.GRID: ("P", "grid"),
    CandidateKind.REGION: ("*", "from regions (whole zone-side, unseen piece)"),
    CandidateKind.AXIS: ("v", "axis cell (regions)"),
    CandidateKind.PRICED: ("X", "priced (regions)"),
}
UNCOVERED = "red"
FIELD_STYLE: dict[str, Any] = dict(closed=True, fc="gold", ec="darkgoldenrod", alpha=0.25, lw=0.5)
DISC_STYLE: dict[str, Any] = dict(fill=False, ls="--", ec="tab:purple", lw=0.8)
STATION_STYLE: dict[str, Any] = dict(ms=7, mfc="white", mec="black", ls="none")


def _background(ax, o: Outcome, frame: str, zone_id: str) -> None:
    """The other zones of the frame in light grey (one collection: a patch each was hundreds of artists to draw)."""
    rings = [ring for z in o.site.zones if z.frame == frame and z.id != zone_id for ring in z.rings]
    if rings:
        ax.add_collection(PolyCollection(rings, closed=True, facecolors="none", edgecolors="0.75", linewidths=0.6))
    if frame == SITE_FRAME:
        draw_obstacles(ax, o.site)


def _pieces(o: Outcome, zi: int, side: ScanSide):
    t = o.coverage.targets
    m = (t.zone == zi) & (t.side == SIDE_CODE[side])
    segs = np.stack([t.a[m], t.b[m]], axis=1)
    h = np.maximum(t.ha_m[m], t.hb_m[m])
    width = 1.0 + 3.0 * h / max(float(h.max()), 1e-9)
    return segs, o.coverage.count[m], o.coverage.best_incidence_deg[m], width


def _stations(ax, o: Outcome, zone_id: str, side: ScanSide, numbering: StationNumbering) -> list[PointLabel]:
    """Draw the zone-side's stations; their number labels, to be placed once the panel is complete."""
    labels: list[PointLabel] = []
    numbers = numbering.numbers
    once = legend_once()
    for s in o.stations:
        if s.zone != zone_id or s.side is not side:
            continue
        if s.field:
            ax.add_patch(Polygon(s.field, **FIELD_STYLE, label=once("field", "movement field")))
        r = o.tripod_radius_m.get(s.id)
        if r:
            ax.add_patch(Circle((s.x, s.y), r, **DISC_STYLE, label=once("disc", "tripod disc")))
        marker, name = MARKERS[s.kind]
        ax.plot(s.x, s.y, marker=marker, **STATION_STYLE, label=once(s.kind, f"station: {name}"))
        labels.append(PointLabel(s.x, s.y, str(numbers[s.id]), f"station:{s.id}", 7.0))
    return labels


def plan_figure(
    o: Outcome,
    zone_id: str,
    side: ScanSide | str,
    numbering: StationNumbering | None = None,
    layouts: Layouts | None = None,
) -> Figure:
    """Two panels of one zone-side: coverage count and best incidence angle of every wall piece; stations labelled
    with their numbers in ``numbering`` (None: those the plan records), said in the title. ``layouts``: the layouts
    of the plan figures drawn before, whose layout this one takes where it fits (:mod:`planner.figures.layout`)."""
    argument(o, Outcome, "outcome")
    numbering = numbering or StationNumbering.recorded(o.meta, o.stations)
    side = ScanSide(side)
    zi = next(i for i, z in enumerate(o.site.zones) if z.id == zone_id)
    zone = o.site.zones[zi]
    segs, count, inc, width = _pieces(o, zi, side)
    theta = o.site.parameters.theta_max_deg
    fig = Figure(figsize=(13, 6.2), layout="constrained", dpi=PNG_DPI)
    axes = fig.subplots(1, 2)
    top = max(int(count.max()) if count.size else 1, 1)
    cmap_n = ListedColormap(["#74c476", "#31a354", "#238b45", "#006d2c", "#00441b"][: max(1, min(top, 5))])
    norm_n = BoundaryNorm(np.arange(0.5, min(top, 5) + 1.5), cmap_n.N)
    panels = (
        (axes[0], np.minimum(count, 5).astype(float), cmap_n, norm_n, "stations seeing the piece"),
        (axes[1], inc, "viridis_r", Normalize(0.0, theta), "best incidence angle (deg)"),
    )
    panel_labels: list[tuple[Axes, str, list[PointLabel]]] = []
    for ax, values, cmap, norm, label in panels:
        _background(ax, o, zone.frame, zone.id)
        for k, ring in enumerate(zone.rings[1:]):
            ax.add_patch(Polygon(ring, closed=True, fc="0.88", ec="none", label=None if k else "free-standing block"))
        seen = count > 0
        lc = LineCollection(segs[seen], array=values[seen], cmap=cmap, norm=norm, linewidths=width[seen])
        ax.add_collection(lc)
        if (~seen).any():
            ax.add_collection(
                LineCollection(
                    segs[~seen],
                    colors=UNCOVERED,
                    linewidths=width[~seen] + 1.5,
                    label=f"uncovered ({int((~seen).sum())} pieces)",
                )
            )
        cb = fig.colorbar(lc, ax=ax, shrink=0.8)
        if cmap is cmap_n:
            cb.set_ticks(range(1, min(top, 5) + 1))
        cb.set_label(label + (" (5 = 5 or more)" if cmap is cmap_n and top > 5 else ""))
        labels = _stations(ax, o, zone.id, side, numbering)
        frame_axes(ax, PLAN_MARGIN)
        ax.legend(loc="upper left", fontsize=7, framealpha=0.8)
        panel_labels.append((ax, zone.frame, labels))
    hmax = max((*zone.vertex_heights_m, *(h for hs in zone.hole_heights_m for h in hs)))
    axes[0].set_title(f"coverage count (line width ~ wall height, max {hmax:g} m)")
    axes[1].set_title(f"best incidence (limit {theta:g} deg)")
    n = sum(1 for s in o.stations if s.zone == zone.id and s.side is side)
    fig.suptitle(
        f"{o.site.name}: zone {zone.id}, {side.value} - {n} stations, "
        f"{100 * float((count > 0).mean()) if count.size else 100:.1f} % of pieces covered; {numbering.legend}"
    )
    finish_plans(
        fig, panel_labels, fontsize=7, layouts=layouts
    )  # last: scale bars and labels in the final, frozen layout
    return fig


def plan_figures(o: Outcome, numbering: StationNumbering | None = None) -> list[tuple[str, Figure]]:
    """One plan figure per zone-side, titled ``zone/side``, stations numbered by ``numbering`` (:func:`plan_figure`);
    the first lays out the figures after it (:mod:`planner.figures.layout`)."""
    argument(o, Outcome, "outcome")
    layouts = Layouts()
    return [
        (f"{z.id}/{side.value}", plan_figure(o, z.id, side, numbering, layouts))
        for z in o.site.zones
        for side in z.scan_side.sides
    ]


def plan_pngs(o: Outcome, numbering: StationNumbering | None = None) -> list[tuple[str, bytes]]:
    """:func:`plan_figures` as PNG bytes (:func:`planner.figures.base.png_bytes`), drawn on two cores where one is free
    (:func:`planner.figures.forked.drawn`): the first figure sets the layout, the others take it where they share its
    make-up and are laid out afresh where not, so each image is the same however they are shared out."""
    argument(o, Outcome, "outcome")
    sides = [(z.id, side) for z in o.site.zones for side in z.scan_side.sides]
    if not sides:
        return []
    layouts = Layouts()
    first = png_bytes(plan_figure(o, sides[0][0], sides[0][1], numbering, layouts))
    closed = replace(layouts, closed=True)
    rest = drawn(lambda zs: png_bytes(plan_figure(o, zs[0], zs[1], numbering, closed)), sides[1:])
    return [(f"{z}/{side.value}", png) for (z, side), png in zip(sides, [first, *rest])]
