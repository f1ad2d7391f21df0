"""The whole site in one figure (:func:`site_figure`): every zone's walls, blocks and openings, obstacles and no-go
areas, the stations numbered in walking order (or plan order), the registration links between them, the control points,
a scale bar and north arrow, and labels that never overlap (:mod:`planner.figures.labels`).

One panel per frame (a table site, one frame per zone, gets one panel per zone), numbered on across the panels. For
large sites the figure grows and the markers, lines and numbers shrink with the number of stations; a number that fits
nowhere within :data:`LEADER_MAX_PX` of its station is left out and counted under the panel (the station table still
lists it).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import networkx as nx
import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Polygon

from planner.core.checks import argument
from planner.figures.base import PLAN_MARGIN, PNG_DPI, frame_axes
from planner.figures.labels import PointLabel, finish_plans
from planner.figures.storey_fig import OPENING_COLOUR, draw_gap, draw_obstacles
from planner.network.survey import registration_links
from planner.plan.outcome import Outcome
from planner.plan.plan_dict import StationNumbering
from planner.site.model import SITE_FRAME, ControlPoint

#: the farthest a number is put from its station (pixels beyond the marker), on a leader line
LEADER_MAX_PX = 60.0
#: more links than this per station are drawn as their shortest spanning forest (:func:`shown_links`)
DENSE_LINKS = 3
_LINK = "tab:blue"
_CONTROL = "tab:red"


def _links(o: Outcome) -> list[tuple[str, str]]:
    """The registration links: the network's where it was checked, else the plan's relation afresh."""
    if o.network is not None:
        g = o.network.graph
        return [(u, v) for u, v, d in g.edges(data=True) if "registration" in d["kinds"]]
    if not o.stations:
        return []
    return registration_links(o.sight, list(o.stations), o.registration, o.coverage.problem)


def shown_links(o: Outcome, links: Sequence[tuple[str, str]]) -> list[tuple[str, str]]:
    """The links drawn: all of them, or, where they are more than :data:`DENSE_LINKS` per station (a large open area
    where every station registers to every other), the shortest spanning forest of them, which shows what is connected
    to what in one line per station."""
    if len(links) <= DENSE_LINKS * max(len(o.stations), 1):
        return list(links)
    xy = {s.id: s.xy for s in o.stations}
    g = nx.Graph()
    g.add_weighted_edges_from((u, v, math.dist(xy[u], xy[v])) for u, v in links)
    return sorted((u, v) for u, v, _ in nx.minimum_spanning_edges(g, algorithm="kruskal"))


def _control(o: Outcome, control: Sequence[ControlPoint] | None) -> list[ControlPoint]:
    if control is not None:
        return list(control)
    if o.network is not None:
        g = o.network.graph
        return [
            ControlPoint(n, d["x"], d["y"], proposed=bool(d.get("proposed")), frame=d["frame"])
            for n, d in g.nodes(data=True)
            if d["kind"] == "control"
        ]
    return list(o.site.control_points)


def _count(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def _scale(n: int) -> tuple[float, float, float]:
    """Marker size (points), font size and wall line width for ``n`` stations."""
    if n <= 30:
        return 6.0, 7.0, 1.0
    if n <= 80:
        return 4.5, 6.0, 0.8
    return 3.5, 5.0, 0.6


def _walls(ax: Axes, o: Outcome, frame: str, lw: float) -> None:
    zones = [z for z in o.site.zones if z.frame == frame]
    segs = [np.vstack([r, r[:1]]) for z in zones for r in z.rings]
    ax.add_collection(LineCollection(segs, colors="black", linewidths=lw, zorder=2))
    for z in zones:
        for hole in z.holes:
            ax.add_patch(Polygon(np.asarray(hole), closed=True, fc="0.85", ec="none", zorder=1))
        for op in z.openings:
            draw_gap(ax, z.walls[op.wall - 1], op.s0_m, op.s1_m, OPENING_COLOUR.get(op.kind, "tab:orange"))
    if frame == SITE_FRAME:
        draw_obstacles(ax, o.site, zorder=1)


def _panel(
    ax: Axes,
    o: Outcome,
    frame: str,
    numbers: dict[str, int],
    links: list[tuple[str, str]],
    control: list[ControlPoint],
) -> list[PointLabel]:
    """Draw one frame's panel; the labels of its stations and control points, to be placed last."""
    ms, _, lw = _scale(len(o.stations))
    _walls(ax, o, frame, lw)
    st = {s.id: s for s in o.stations if s.frame == frame}
    segs = [(st[u].xy, st[v].xy) for u, v in links if u in st and v in st]
    if segs:
        ax.add_collection(
            LineCollection(segs, colors=_LINK, linewidths=0.6 + 0.4 * lw, alpha=0.7, zorder=3, gid="links")
        )
    labels: list[PointLabel] = []
    mine = sorted(st.values(), key=lambda s: numbers[s.id])
    if mine:
        xy = np.array([s.xy for s in mine], dtype=float)
        ax.plot(xy[:, 0], xy[:, 1], "o", ms=ms, mfc="white", mec="black", mew=0.8, ls="none", zorder=4, gid="stations")
    labels += [PointLabel(s.x, s.y, str(numbers[s.id]), f"station:{s.id}", ms) for s in mine]
    here = [c for c in control if c.frame == frame]
    for c in here:
        face = "white" if c.proposed else _CONTROL
        ax.plot(c.x, c.y, "^", ms=ms + 2, color=_CONTROL, mfc=face, zorder=4, gid=f"control:{c.name}")
    labels += [PointLabel(c.x, c.y, c.name, f"control:{c.name}", ms + 2) for c in here]
    frame_axes(ax, PLAN_MARGIN)
    if len({z.frame for z in o.site.zones}) > 1:
        ax.set_title(f"frame {frame}: {_count(len(mine), 'station')}", fontsize=9)
    return labels


def site_figure(
    o: Outcome,
    numbering: StationNumbering | None = None,
    control: Sequence[ControlPoint] | None = None,
    *,
    order: Sequence[str] | None = None,
) -> Figure:
    """Every zone of the site with the stations, their registration links and the control points: one panel per frame,
    each with a scale bar and a north arrow, every label placed without overlap.

    The network report of ``o``, where present, gives the registration links and the control points (proposed ones drawn
    open), else the links are the plan's registration relation computed afresh. ``numbering``: the stations' numbers
    (None: those the plan records, :meth:`StationNumbering.recorded
    <planner.plan.plan_dict.StationNumbering.recorded>`), said in the title; ``order``: instead, station ids in
    walking order (:meth:`StationNumbering.walking <planner.plan.plan_dict.StationNumbering.walking>`);
    ``control``: control points to draw instead.
    """
    argument(o, Outcome, "outcome")
    if order is not None:
        numbering = StationNumbering.walking(o.stations, order)
    numbering = numbering or StationNumbering.recorded(o.meta, o.stations)
    numbers = {s.id: numbering.number(s.id) for s in o.stations}
    frames = list(dict.fromkeys(z.frame for z in o.site.zones))
    ncols = math.ceil(math.sqrt(len(frames)))
    nrows = math.ceil(len(frames) / ncols)
    fig = Figure(figsize=_size(o, frames, ncols, nrows), layout="constrained", dpi=PNG_DPI)
    axes = np.atleast_1d(fig.subplots(nrows, ncols, squeeze=False).ravel())
    every, points = _links(o), _control(o, control)
    links = shown_links(o, every)
    labels = [_panel(ax, o, frame, numbers, links, points) for ax, frame in zip(axes, frames)]
    for ax in axes[len(frames) :]:
        ax.set_visible(False)
    link = "registration link"
    if len(links) < len(every):
        link = f"registration links: shortest spanning forest ({len(links)} of {len(every)})"
    handles = [
        Line2D([], [], color="black", lw=1.0, label="wall"),
        Line2D([], [], color=_LINK, lw=1.0, label=link),
        Line2D([], [], marker="o", ls="none", mfc="white", mec="black", label=f"station (number: {numbering.basis})"),
    ]
    if points:
        handles.append(Line2D([], [], marker="^", ls="none", color=_CONTROL, label="control point (open: proposed)"))
    if any(op.kind != "passage" for z in o.site.zones for op in z.openings):
        handles.append(Line2D([], [], color="tab:orange", lw=4, label="opening"))
    if any(op.kind == "passage" for z in o.site.zones for op in z.openings):
        handles.append(Line2D([], [], color=OPENING_COLOUR["passage"], lw=4, label="passage (no door)"))
    fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), fontsize=8, frameon=False)
    fig.suptitle(f"{o.site.name}: {_count(len(o.stations), 'station')}, numbered in {numbering.basis}")
    panels = [(ax, frame, mine) for ax, frame, mine in zip(axes, frames, labels)]
    finish_plans(fig, panels, fontsize=_scale(len(o.stations))[1], max_gap_px=LEADER_MAX_PX)
    return fig


def _size(o: Outcome, frames: list[str], ncols: int, nrows: int) -> tuple[float, float]:
    """Figure size (inches): about 10 in wide for a small site, growing with the stations to 16, the height after the
    site's shape (one frame) or the panel grid."""
    width = min(16.0, 10.0 + 0.06 * max(0, len(o.stations) - 30))
    if len(frames) > 1:
        return width, min(12.0, width * nrows / ncols * 0.9 + 0.6)
    xy = np.vstack([np.asarray(r) for z in o.site.zones for r in z.rings])
    span = np.ptp(xy, axis=0)
    ratio = float(span[1] / span[0]) if span[0] > 0 else 1.0
    return width, float(np.clip(width * ratio + 1.2, 5.0, 12.0))
