"""The field sheet's plan figure (:func:`figure`): walls (solid parts), obstacles, no-go areas, the route (legs
through walls dashed: no opening in the model), the stations numbered in visiting order and the targets, with a
scale bar and a north arrow. field.html embeds it as a PNG, field.pdf draws it on its first page.

The numbers and target names are placed last, so that no two overlap, nor cover a marker, the scale bar or the
north arrow (:func:`planner.figures.labels.finish_plans`): next to their point where there is room, else on a
leader line up to :data:`LEADER_MAX_PX` away; one that fits nowhere is left out and counted under the plan
(the setup table and the target table still list it).
"""

from __future__ import annotations

import math

from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Polygon

from planner.field.run import FieldPlan
from planner.field.walking import WalkSpace
from planner.figures.base import PLAN_MARGIN, frame_axes
from planner.figures.labels import PointLabel, finish_plans

#: the legend's entries for a leg through walls and a stair leg (across storeys)
THROUGH_LABEL = "leg through a wall (no opening in the model)"
STAIR_LABEL = "stair leg (foot to head)"
#: the figure's size (inches) unless the caller gives the paper's (field.pdf)
SIZE = (11.0, 8.0)
#: marker sizes (points) of a station, a target and the start; font sizes of their labels
STATION_PT, TARGET_PT, START_PT = 8.0, 6.0, 14.0
STATION_FONT, TARGET_FONT = 8.0, 6.5
#: the farthest a label is put from its point (pixels beyond the marker), on a leader line
LEADER_MAX_PX = 80.0
_TARGET, _STAIR = "tab:red", "tab:purple"


def _walls(ax: Axes, space: WalkSpace) -> None:
    ax.add_collection(LineCollection([list(w) for w in space.solid_walls], colors="black", linewidths=1.2, zorder=2))


def _legs(ax: Axes, walks: list, walls: list, stairs: list | None = None) -> None:
    """Draw the walks, the legs through walls (orange, dashed) and the stair legs (purple)."""
    ax.add_collection(LineCollection(walks, colors="tab:blue", linewidths=1.4, alpha=0.8, zorder=3, gid="route"))
    if walls:
        ax.add_collection(
            LineCollection(walls, colors="tab:orange", linewidths=1.4, linestyles="--", zorder=3, gid="through")
        )
    if stairs:
        ax.add_collection(LineCollection(stairs, colors=_STAIR, linewidths=2.2, zorder=4, gid="stair"))


def _points(ax: Axes, fp: FieldPlan, numbered: list, targets: list, start: bool = True) -> list[PointLabel]:
    """Draw the ``numbered`` stations ((setup number, station)), the start where the panel holds it (``start``)
    and ``targets``; their labels, to be placed once the plan is complete."""
    labels: list[PointLabel] = []
    starts_at_station = False
    for n, s in numbered:
        ax.plot(s.x, s.y, "o", ms=STATION_PT, mfc="white", mec="black", mew=1.0, ls="none", zorder=5)
        at_start = start and s.xy == fp.start_xy
        starts_at_station |= at_start
        size = max(STATION_PT, START_PT) if at_start else STATION_PT  # the start's star is drawn over it
        labels.append(PointLabel(s.x, s.y, str(n), f"station:{s.id}", size, STATION_FONT))
    if start:  # over the station it may stand on: a white circle must not hide it
        ax.plot(*fp.start_xy, marker="*", ms=START_PT, color="tab:green", mec="darkgreen", mew=0.6, ls="none", zorder=6)
        if not starts_at_station:
            labels.append(PointLabel(*fp.start_xy, "start", "start", START_PT, TARGET_FONT))
    for t in targets:
        ax.plot(t.x, t.y, marker="x" if t.kind != "control" else "^", color=_TARGET, ms=TARGET_PT, ls="none", zorder=5)
        labels.append(PointLabel(t.x, t.y, t.id, f"target:{t.id}", TARGET_PT, TARGET_FONT))
    return labels


def _finish(fig: Figure, fp: FieldPlan, panels: list, through: bool, stairs: bool = False) -> None:
    """The legend under the plan, then the labels of ``panels`` placed (targets' in the targets' colour)."""
    handles = [
        Line2D([], [], color="black", lw=1.2, label="wall"),
        Line2D([], [], color="tab:blue", lw=1.4, label="route"),
    ]
    if stairs:
        handles.append(Line2D([], [], color=_STAIR, lw=2.2, label=STAIR_LABEL))
    if through:
        handles.append(Line2D([], [], color="tab:orange", lw=1.4, ls="--", label=THROUGH_LABEL))
    handles += [
        Line2D([], [], marker="*", ms=10, color="tab:green", ls="none", label=f"start: {fp.start_label}"),
        Line2D(
            [], [], marker="o", mfc="white", mec="black", ls="none", label=f"station (number: {fp.numbering.basis})"
        ),
    ]
    if fp.targets:
        handles.append(Line2D([], [], marker="x", color=_TARGET, ls="none", label="target"))
    fig.legend(handles=handles, loc="outside lower center", ncols=min(len(handles), 3), fontsize=8, frameon=False)
    for placed in finish_plans(fig, panels, max_gap_px=LEADER_MAX_PX):
        for text in placed.texts:
            if str(text.get_gid()).startswith("label:target:"):
                text.set_color(_TARGET)


def _frame_legs(fp: FieldPlan, fr: str, through: set[int]) -> tuple[list, list, list]:
    """The route's parts in frame ``fr``: walks, legs through walls, and the stair legs that end in ``fr``."""
    walks: list[list[tuple[float, float]]] = []
    walls: list[list[tuple[float, float]]] = []
    stairs: list[list[tuple[float, float]]] = []
    for k, (leg, frs) in enumerate(zip(fp.legs, fp.leg_frames)):
        run: list[tuple[float, float]] = []
        for t, (p, f) in enumerate(zip(leg, frs)):
            if t and frs[t - 1] != f and fr in (f, frs[t - 1]):
                (walls if k in through else stairs).append([leg[t - 1], p])
            if f == fr:
                run.append(p)
                continue
            if len(run) > 1:
                (walls if k in through else walks).append(run)
            run = []
        if len(run) > 1:
            (walls if k in through else walks).append(run)
    return walks, walls, stairs


def _storey_figure(fp: FieldPlan, size: tuple[float, float]) -> Figure:
    """Across storeys: one panel per frame walked through, two side by side in a row, each with its walls, the
    route's parts in that frame, its stations and the targets its stations see; a stair leg is drawn in both
    panels it joins (purple), from the foot to the head."""
    frames = [sp.frame for sp in fp.spaces]
    fig = Figure(figsize=size, layout="constrained")
    ncols = min(len(frames), 2)  # two storeys side by side; more in rows of two
    grid = fig.subplots(math.ceil(len(frames) / ncols), ncols, squeeze=False).ravel()
    for spare in grid[len(frames) :]:
        spare.set_visible(False)
    through = {c.leg for c in fp.crossings}
    number = {k: fp.numbering.number(fp.stations[k].id) for k in fp.order}
    seers = {s.id: s.frame for s in fp.stations}
    panels = []
    for ax, sp in zip(grid, fp.spaces):
        fr = sp.frame
        _walls(ax, sp)
        _legs(ax, *_frame_legs(fp, fr, through))
        numbered = [(number[k], s) for k, s in enumerate(fp.stations) if s.frame == fr and k in number]
        targets = [tg for tg in fp.targets if fr in {seers.get(i) for i in tg.seen_by}]
        labels = _points(ax, fp, numbered, targets, start=fr == fp.space.frame)
        frame_axes(ax, PLAN_MARGIN)
        ax.set_title(fr, fontsize=9)
        panels.append((ax, fr, labels))
    fig.suptitle(
        f"{fp.site.name}: {len(fp.order)} setups on {len(frames)} storeys, {fp.options.mode} order, route "
        f"{fp.route_length_m:.0f} m with {len(fp.stair_legs)} stair leg(s) (bound {fp.lower_bound_m:.0f} m, gap "
        f"{100 * fp.gap:.1f} %)"
    )
    _finish(fig, fp, panels, bool(through), stairs=True)
    return fig


def figure(fp: FieldPlan, size: tuple[float, float] = SIZE) -> Figure:
    """The plan of the field sheet (see the module text), drawn for ``size`` (inches): the labels are placed for
    it, so a caller that prints on other paper passes the paper's size rather than resizing the figure. One panel;
    labels with ``gid`` ``label:station:ID`` (text: the setup number), ``label:target:ID`` and ``label:start``
    (where the start is no station). Across storeys (``fp.spaces``): one panel per storey."""
    if fp.spaces:
        return _storey_figure(fp, size)
    fig = Figure(figsize=size, layout="constrained")
    ax = fig.subplots()
    _walls(ax, fp.space)
    site = fp.site
    if fp.space.frame == "site":
        for ob in site.obstacles:
            ax.add_patch(Polygon(ob.vertices, closed=True, fc="0.6", ec="0.3", alpha=0.6, zorder=1))
        for a in site.no_go_areas:
            ax.add_patch(Polygon(a.vertices, closed=True, fc="mistyrose", ec="red", hatch="//", alpha=0.5, zorder=1))
    through = {c.leg for c in fp.crossings}
    walks = [leg for k, leg in enumerate(fp.legs) if len(leg) > 1 and k not in through]
    walls = [leg for k, leg in enumerate(fp.legs) if len(leg) > 1 and k in through]
    _legs(ax, walks, walls)
    numbering = fp.numbering
    numbered = [(numbering.number(fp.stations[k].id), fp.stations[k]) for k in fp.order]
    labels = _points(ax, fp, numbered, list(fp.targets))
    frame_axes(ax, PLAN_MARGIN)
    ax.set_title(
        f"{site.name}: {len(fp.order)} setups, {fp.options.mode} order, route {fp.route_length_m:.0f} m "
        f"(bound {fp.lower_bound_m:.0f} m, gap {100 * fp.gap:.1f} %)"
    )
    _finish(fig, fp, [(ax, fp.space.frame, labels)], bool(walls))
    return fig
