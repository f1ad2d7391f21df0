"""Registration and network figure: overlap (registration) links, ties to control, control-traverse legs (or, with a
total station on every station, its sight lines and the Delaunay triangulation), control points and exaggerated error
ellipses (scale stated)."""

from __future__ import annotations

import math

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Ellipse, Polygon

from planner.core.checks import argument
from planner.figures.base import PLAN_MARGIN, PNG_DPI, frame_axes, legend_once
from planner.figures.labels import PointLabel, finish_plans
from planner.network.adjustment import ELLIPSE_95
from planner.plan.outcome import Outcome
from planner.plan.plan_dict import StationNumbering

STYLES = {
    "registration": ("tab:blue", "-", 1.6, "registration (overlap) link"),
    "traverse": ("tab:red", "-", 1.0, "control traverse leg (total station)"),
    "tie": ("tab:purple", ":", 0.8, "tie (station scans targets on a control point)"),
    "sight": ("0.55", ":", 0.8, "total-station sight line"),
    "delaunay": ("tab:green", "--", 0.8, "triangulation (Delaunay, intervisible)"),
}


def _exaggeration(extent_m: float, largest_m: float) -> float:
    """A round factor that draws the largest 95 % ellipse about 4 % of the extent."""
    if largest_m <= 0 or not math.isfinite(largest_m):
        return 1.0
    raw = 0.04 * extent_m / largest_m
    k = math.floor(math.log10(raw))
    return float(max(m * 10**k for m in (1, 2, 5) if m * 10**k <= raw) if raw >= 1 else 1.0)


def network_figure(o: Outcome, frame: str | None = None, numbering: StationNumbering | None = None) -> Figure:
    """The network of one frame (default: the frame with most stations); stations labelled with their numbers in
    ``numbering`` (None: those the plan records), said in the legend, control points with their names."""
    argument(o, Outcome, "outcome")
    numbering = numbering or StationNumbering.recorded(o.meta, o.stations)
    if o.network is None:
        raise ValueError("the outcome has no network report")
    g = o.network.graph
    frames = [d["frame"] for _, d in g.nodes(data=True) if d["kind"] == "station"]
    frame = frame or max(sorted(set(frames)), key=frames.count)
    nodes = [n for n, d in g.nodes(data=True) if d["frame"] == frame]
    fig = Figure(figsize=(9, 8), layout="constrained", dpi=PNG_DPI)
    ax = fig.subplots()
    for z in o.site.zones:
        if z.frame == frame:
            for ring in z.rings:
                ax.add_patch(Polygon(ring, closed=True, fill=False, ec="0.2", lw=1.0))
    once = legend_once()
    # the links of each kind as one collection (a line each was hundreds of artists to draw and lay out), the kinds
    # in the order they first come, at the lines' zorder
    segments: dict[str, list[list[tuple[float, float]]]] = {}
    for u, v, d in g.subgraph(nodes).edges(data=True):
        kind = next(k for k in STYLES if k in d["kinds"])
        segments.setdefault(kind, []).append([(g.nodes[u]["x"], g.nodes[u]["y"]), (g.nodes[v]["x"], g.nodes[v]["y"])])
    for kind, segs in segments.items():
        colour, ls, lw, label = STYLES[kind]
        ax.add_collection(
            LineCollection(segs, colors=colour, linestyles=ls, linewidths=lw, zorder=2, label=once(kind, label))
        )
    points = {p.name: p for a in o.network.adjustments for p in a.points if p.name in nodes}
    xy = np.array([(g.nodes[n]["x"], g.nodes[n]["y"]) for n in nodes])
    extent = float(np.ptp(xy, axis=0).max()) if len(xy) > 1 else 1.0
    factor = _exaggeration(extent, max((p.ellipse_a * ELLIPSE_95 for p in points.values()), default=0.0))
    labels: list[PointLabel] = []
    for n in nodes:
        d = g.nodes[n]
        if d["kind"] == "control":
            face = "white" if d.get("proposed") else "tab:red"
            shown = once("control", "control point (proposed: open)")
            ax.plot(d["x"], d["y"], marker="^", ms=9, color="tab:red", ls="none", label=shown, mfc=face)
            labels.append(PointLabel(d["x"], d["y"], n, f"control:{n}", 9.0))
        else:
            ax.plot(d["x"], d["y"], "o", ms=5, color="black", label=once("st", f"station (number: {numbering.basis})"))
            labels.append(PointLabel(d["x"], d["y"], str(numbering.number(n) or n), f"station:{n}", 5.0))
        p = points.get(n)
        if p is not None and p.ellipse_a > 0:
            a, b = 2 * ELLIPSE_95 * p.ellipse_a * factor, 2 * ELLIPSE_95 * p.ellipse_b * factor
            shown = once("ell", f"95 % error ellipse x {factor:g}")
            ax.add_patch(
                Ellipse((p.x, p.y), a, b, angle=p.ellipse_azimuth_deg, fill=False, ec="tab:orange", lw=1.2, label=shown)
            )
    frame_axes(ax, PLAN_MARGIN)
    ax.legend(loc="upper left", fontsize=7, framealpha=0.85)
    worst = max((o.network.station_sigma_m.get(n, 0.0) for n in nodes), default=0.0)
    ax.set_title(
        f"{o.site.name}: station network, frame {frame} - ellipses exaggerated x {factor:g} "
        f"(worst station {worst * 1000:.2f} mm)",
        fontsize=10,
    )
    finish_plans(fig, [(ax, frame, labels)], fontsize=6)  # last: scale bar and labels in the final layout
    return fig
