"""Comparison figure: station counts per instance and method, and solve time per backend."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure


def comparison_figure(rows: Sequence[Mapping[str, Any]], title: str = "closed form vs greedy vs optimal") -> Figure:
    """Rows as written by ``scripts/bench/benchmark.py`` (instance, method, backend, overlap, stations, time_s, status).

    Left: stations per instance for closed form, greedy, and the best MILP plan without and with overlap. Right: MILP
    solve time per backend and instance (log scale; hatched = not proven optimal).
    """
    instances = list(dict.fromkeys(r["instance"] for r in rows))
    series: dict[str, list[float]] = {}
    for label, pick in (
        ("closed form", lambda r: r["method"] == "closed-form"),
        ("greedy", lambda r: r["method"] == "greedy"),
        ("MILP", lambda r: r["method"] == "milp" and r.get("overlap", "no") == "no"),
        ("MILP + overlap", lambda r: r["method"] == "milp" and r.get("overlap") == "yes"),
    ):
        vals = [
            min((float(r["stations"]) for r in rows if r["instance"] == i and pick(r)), default=np.nan)
            for i in instances
        ]
        if not all(np.isnan(vals)):
            series[label] = vals
    fig = Figure(figsize=(13, 5), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    x = np.arange(len(instances))
    w = 0.8 / max(len(series), 1)
    for k, (label, vals) in enumerate(series.items()):
        bars = ax1.bar(x + (k - (len(series) - 1) / 2) * w, vals, w, label=label)
        ax1.bar_label(bars, fmt="%g", fontsize=7)
    ax1.set_xticks(x, instances)
    ax1.set_ylabel("stations")
    ax1.set_title("stations per method")
    ax1.legend(fontsize=8)
    milp = [r for r in rows if r["method"] == "milp"]
    backends = list(dict.fromkeys(r["backend"] for r in milp))
    groups = list(dict.fromkeys((r["instance"], r.get("overlap", "no")) for r in milp))
    wb = 0.8 / max(len(backends), 1)
    for k, b in enumerate(backends):
        t, hatch = [], []
        for inst, ov in groups:
            r = next(
                (r for r in milp if r["backend"] == b and r["instance"] == inst and r.get("overlap", "no") == ov), None
            )
            t.append(float(r["time_s"]) if r else np.nan)
            hatch.append(r is not None and r.get("status") != "optimal")
        bars = ax2.bar(np.arange(len(groups)) + (k - (len(backends) - 1) / 2) * wb, t, wb, label=b)
        for bar, h in zip(bars, hatch):
            if h:
                bar.set_hatch("//")
    ax2.set_xticks(
        np.arange(len(groups)), [f"{i}\n{'overlap' if ov == 'yes' else 'plain'}" for i, ov in groups], fontsize=8
    )
    ax2.set_yscale("log")
    ax2.set_ylabel("solve time (s, log scale)")
    ax2.set_title("MILP solve time per backend (hatched: not proven optimal)")
    if backends:
        ax2.legend(fontsize=8)
    fig.suptitle(title)
    return fig
