"""Draw an assembled site (zones placed by `planner assemble`): docs/baalbek_assembled.png.

Usage: python scripts/studies/figure_assembled.py [INSTANCE.json] [OUT.png]
Zones left in their own frames are named in the title, not drawn; matched walls are drawn thick (red),
collinear contacts (a side along part of a placed wall) thick in blue.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

from planner.io.load import load_site
from planner.site.assemble import assemble
from planner.site.model import SITE_FRAME, ScanSide


def main(src: str = "instances/baalbek.json", out: str = "docs/baalbek_assembled.png") -> None:
    raw = load_site(src)
    report = assemble(raw)
    site = load_site(src.replace(".json", "_site.json")) if src.endswith("baalbek.json") else raw
    fig = Figure(figsize=(10, 5.5), dpi=110)
    ax = fig.add_subplot()
    for z in site.zones:
        if z.frame != SITE_FRAME:
            continue
        outside = z.scan_side is ScanSide.OUTSIDE
        ax.add_patch(
            Polygon(
                z.xy,
                closed=True,
                fc="none" if outside else "lightsteelblue",
                ec="k",
                lw=1.2 if outside else 0.8,
                alpha=1.0 if outside else 0.7,
            )
        )
        if not outside:
            c = z.polygon.representative_point()
            ax.annotate(z.id, (c.x, c.y), ha="center", va="center", fontsize=8)
    zones = {z.id: z for z in site.zones}
    for m in report.used:
        w = zones[m.zone_a].outer_walls[m.wall_a - 1]
        ax.plot([w.start[0], w.end[0]], [w.start[1], w.end[1]], color="crimson", lw=3, solid_capstyle="butt")
    ax.plot(
        [],
        [],
        color="crimson",
        lw=3,
        label=f"matched walls ({len(report.used)}), residual <= {max(m.residual_m for m in report.used) * 1000:.1f} mm",
    )
    for c in report.contacts:
        w = zones[c.zone].outer_walls[c.wall - 1]
        ax.plot([w.start[0], w.end[0]], [w.start[1], w.end[1]], color="royalblue", lw=2.5, solid_capstyle="butt")
    if report.contacts:
        ax.plot(
            [],
            [],
            color="royalblue",
            lw=2.5,
            label=f"collinear contacts ({len(report.contacts)}), residual <= "
            f"{max(c.residual_m for c in report.contacts) * 1000:.1f} mm",
        )
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.legend(loc="lower left", fontsize=8)
    ax.set_xlabel("x, m (outline frame)")
    ax.set_ylabel("y, m")
    left = ", ".join(z for z, _ in report.unplaced) or "none"
    ax.set_title(
        f"{site.name}: zones placed from shared walls and collinear contacts (table 4.3); not placed: {left}",
        fontsize=9,
    )
    fig.tight_layout()
    fig.savefig(out)
    print(f"wrote {out}")


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("instance", nargs="?", default="instances/baalbek.json", help="the site (default: Baalbek)")
    ap.add_argument("out", nargs="?", default="docs/baalbek_assembled.png", help="the PNG to write")
    args = ap.parse_args()
    main(args.instance, args.out)
