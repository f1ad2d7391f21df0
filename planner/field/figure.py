"""The field sheet's plan figure: walls (solid parts), obstacles, no-go areas, the route (legs through walls
dashed: no opening in the model), the stations numbered in visiting order and the targets. field.html embeds
it as a PNG, field.pdf draws it on its first page."""

from __future__ import annotations

from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

from planner.field.run import FieldPlan
from planner.figures.base import decorate_plan

#: the legend's entry for a leg through walls
THROUGH_LABEL = "leg through a wall (no opening in the model)"


def figure(fp: FieldPlan) -> Figure:
    """The plan: walls (solid parts), obstacles, no-go areas, the route, numbered stations and the targets."""
    fig = Figure(figsize=(11, 8), layout="constrained")
    ax = fig.subplots()
    walls = [list(w) for w in fp.space.solid_walls]
    ax.add_collection(LineCollection(walls, colors="black", linewidths=1.2, label="wall"))
    site = fp.site
    if fp.space.frame == "site":
        for ob in site.obstacles:
            ax.add_patch(Polygon(ob.vertices, closed=True, fc="0.6", ec="0.3", alpha=0.6))
        for a in site.no_go_areas:
            ax.add_patch(Polygon(a.vertices, closed=True, fc="mistyrose", ec="red", hatch="//", alpha=0.5))
    through = {c.leg for c in fp.crossings}
    labelled: set[bool] = set()
    for k, leg in enumerate(fp.legs):
        if len(leg) > 1:
            xs, ys = zip(*leg)
            wall = k in through
            label = None if wall in labelled else THROUGH_LABEL if wall else "route"
            labelled.add(wall)
            ax.plot(
                xs,
                ys,
                color="tab:orange" if wall else "tab:blue",
                ls="--" if wall else "-",
                lw=1.4,
                alpha=0.9 if wall else 0.8,
                label=label,
            )
    ax.plot(*fp.start_xy, marker="*", ms=14, color="tab:green", ls="none", label=f"start: {fp.start_label}")
    for n, k in enumerate(fp.order, 1):
        s = fp.stations[k]
        ax.plot(s.x, s.y, "o", ms=13, mfc="white", mec="black", ls="none")
        ax.annotate(str(n), (s.x, s.y), ha="center", va="center", fontsize=7, fontweight="bold")
    for t in fp.targets:
        ax.plot(t.x, t.y, marker="x" if t.kind != "control" else "^", color="tab:red", ms=6, ls="none")
        ax.annotate(t.id, (t.x, t.y), xytext=(3, -8), textcoords="offset points", fontsize=6, color="tab:red")
    decorate_plan(ax, fp.space.frame)
    ax.legend(loc="lower right", fontsize=7, framealpha=0.8)
    ax.set_title(
        f"{site.name}: {len(fp.order)} setups, {fp.options.mode} order, route {fp.route_length_m:.0f} m "
        f"(bound {fp.lower_bound_m:.0f} m, gap {100 * fp.gap:.1f} %)"
    )
    return fig
