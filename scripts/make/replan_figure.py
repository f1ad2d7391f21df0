"""The figure of a re-plan (docs/figures/replan_baalbek_site_doors.png, docs/field.md "Re-planning on site").

Re-plans PLAN.json after EDITS.json with :func:`planner.replan` and draws the site's walls, the closed zones and
areas (hatched), the blocked discs, the stations done (black squares), the stations of the previous plan dropped
(grey crosses), the new plan's stations to go (blue dots, numbered in the new walking order), the walk from where
the crew stands, and the walls lost (red). Usage::

    planner plan instances/baalbek_site_doors.json --out out/bd --field out/bd
    python scripts/make/replan_figure.py out/bd/plan.json instances/baalbek_site_doors.edits.json \
        docs/figures/replan_baalbek_site_doors.png
"""

from __future__ import annotations

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.patches import Circle, Polygon

import planner


def main(plan: str, edits: str, out: str) -> None:
    r = planner.replan(plan, edits)
    site = r.source.site
    fig, ax = plt.subplots(figsize=(10, 8), dpi=110)
    closed = set(r.edits.closed_zones)
    for z in site.zones:
        xy = z.polygon.exterior.coords
        ax.add_patch(
            Polygon(
                list(xy),
                closed=True,
                fill=z.id in closed,
                facecolor="#f3c6c6",
                hatch="//" if z.id in closed else None,
                edgecolor="#555",
                lw=0.8,
            )
        )
        c = z.polygon.representative_point()
        ax.annotate(z.id + (" (closed)" if z.id in closed else ""), (c.x, c.y), fontsize=7, color="#777", ha="center")
    for a in r.edits.areas:
        ax.add_patch(
            Polygon(list(a.polygon), closed=True, facecolor="#999" if a.kind == "obstacle" else "#f3c6c6", alpha=0.6)
        )
    for e in r.edits.blocked:
        ax.add_patch(Circle(e.station.xy, max(e.radius_m, 0.8), facecolor="none", edgecolor="#d62728", lw=1.2))
        ax.plot(*e.station.xy, marker="x", color="#d62728", ms=7)
    t = r.rest.coverage.targets
    for k in r.rest.lost.pieces:  # the walls lost, in red
        ax.plot([t.a[k][0], t.b[k][0]], [t.a[k][1], t.b[k][1]], color="#d62728", lw=3, solid_capstyle="butt")
    dropped = set(r.changes.dropped) - set(r.changes.blocked)
    for s in r.source.planned:
        if s.id in dropped:
            ax.plot(s.x, s.y, marker="x", color="#aaa", ms=6)
    if r.sheet is not None:
        for leg in r.sheet.legs:
            xs, ys = zip(*leg)
            ax.plot(xs, ys, color="#1f77b4", lw=0.8, alpha=0.7)
        for n, k in enumerate(r.sheet.order, 1):
            s = r.sheet.stations[k]
            ax.plot(s.x, s.y, "o", color="#1f77b4", ms=6)
            ax.annotate(str(n), s.xy, textcoords="offset points", xytext=(4, 4), fontsize=7, color="#1f77b4")
        ax.plot(*r.sheet.start_xy, marker="*", color="#2ca02c", ms=14, zorder=5)
    for s in r.done:
        ax.plot(s.x, s.y, "s", color="black", ms=6, zorder=4)
    s = r.solution
    ax.set_title(
        f"{site.name}: re-plan after {len(r.done)} done, {len(r.edits.blocked)} blocked, zone(s) "
        f"{', '.join(r.edits.closed_zones) or 'none'} closed\n{s.rest_count} stations to go (bound {s.rest_bound}, "
        f"scope pool); walls lost {r.rest.lost.length_m:.1f} m (red); walk from the crew (green star)",
        fontsize=9,
    )
    handles = [
        plt.Line2D([], [], ls="", marker="s", color="black", label="done"),
        plt.Line2D([], [], ls="", marker="o", color="#1f77b4", label="to go (walking order)"),
        plt.Line2D([], [], ls="", marker="x", color="#d62728", label="blocked (disc)"),
        plt.Line2D([], [], ls="", marker="x", color="#aaa", label="dropped from the plan"),
        plt.Line2D([], [], ls="", marker="*", color="#2ca02c", ms=10, label="crew"),
    ]
    ax.legend(handles=handles, loc="lower left", fontsize=7)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    fig.tight_layout()
    fig.savefig(out)
    print(f"wrote {out}")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
