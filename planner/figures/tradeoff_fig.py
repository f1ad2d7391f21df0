"""The trade-off figure of a field-time plan: stations against hours on site, one bar per plan of the trade-off table,
stacked set-up, scan, walking and targets, with its station count above it."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from matplotlib.figure import Figure

#: the parts of a plan's time, in stacking order, with their colours
PARTS = (
    ("setup_s", "set-up", "#7f7f7f"),
    ("scan_s", "scan", "#1f77b4"),
    ("walking_s", "walking", "#2ca02c"),
    ("targets_s", "targets", "#ff7f0e"),
)


def tradeoff_figure(rows: Sequence[Mapping[str, Any]], kept: str, title: str = "") -> Figure:
    """Hours per plan (``rows``: plan.json's ``hours.tradeoff.rows``), stacked by part, the kept plan marked; plans
    without one (a setting that does not meet the spacing) are listed at zero, marked so."""
    fig = Figure(figsize=(8.0, 4.2))
    ax = fig.add_subplot(1, 1, 1)
    labels = [str(r["label"]).replace("one setting: ", "") for r in rows]
    x = list(range(len(rows)))
    bottom = [0.0] * len(rows)
    for key, name, colour in PARTS:
        h = [float(r.get(key) or 0.0) / 3600.0 for r in rows]
        ax.bar(x, h, bottom=bottom, color=colour, label=name, width=0.6)
        bottom = [b + v for b, v in zip(bottom, h)]
    for k, r in enumerate(rows):
        n = r.get("stations")
        text = "no plan" if n is None else f"{n} st." + (" (kept)" if r["label"] == kept else "")
        ax.annotate(text, (k, bottom[k]), textcoords="offset points", xytext=(0, 3), ha="center", fontsize=8)
    ax.set_xticks(x, labels, rotation=20, ha="right", fontsize=8)
    ax.set_ylabel("hours on site (one crew)")
    ax.set_title(title or "stations and hours: plans at one setting, fewest stations, field time", fontsize=9)
    ax.legend(fontsize=8, loc="upper left")
    ax.margins(y=0.15)
    fig.tight_layout()
    return fig
