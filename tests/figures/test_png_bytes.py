"""A frozen figure saved in one draw (:func:`planner.figures.base.png_bytes`) gives the bytes ``savefig`` with
``bbox_inches="tight"`` gives (two draws), and the layout frozen without a draw places labels where a draw would."""

from __future__ import annotations

import io

import numpy as np
import pytest
from matplotlib.figure import Figure

from planner.figures.base import PLAN_MARGIN, drop_frozen_layout, frame_axes, png_bytes
from planner.figures.labels import PointLabel, finish_plans


def _panels(seed: int = 3) -> Figure:
    """Two plan panels with a colour bar each, a legend and numbered points: the make-up of a plan figure."""
    rng = np.random.default_rng(seed)
    fig = Figure(figsize=(6, 3), layout="constrained")
    panels = []
    for ax in fig.subplots(1, 2):
        xy = rng.uniform(0.0, 40.0, (5, 2))
        ax.plot(xy[:, 0], xy[:, 1], "o", ms=6, ls="none", label="station")
        art = ax.scatter(xy[:, 0], xy[:, 1], c=xy[:, 0], s=4)
        fig.colorbar(art, ax=ax, shrink=0.8).set_label("x (m)")
        frame_axes(ax, PLAN_MARGIN)
        ax.legend(loc="upper left", fontsize=7)
        panels.append((ax, "site", [PointLabel(x, y, str(k), f"station:{k}", 6.0) for k, (x, y) in enumerate(xy, 1)]))
    finish_plans(fig, panels, fontsize=7)
    return fig


@pytest.mark.slow  # two figures drawn: seconds on a busy machine
def test_one_draw_gives_the_bytes_of_savefig_tight():
    buf = io.BytesIO()
    _panels().savefig(buf, format="png", dpi=110, bbox_inches="tight")
    assert png_bytes(_panels()) == buf.getvalue()


def test_a_live_layout_is_still_laid_out_and_kept():
    fig = Figure(figsize=(4, 3), layout="constrained")
    fig.subplots().plot([0, 1], [0, 1])
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, bbox_inches="tight")
    again = Figure(figsize=(4, 3), layout="constrained")
    again.subplots().plot([0, 1], [0, 1])
    assert png_bytes(again) == buf.getvalue()
    drop_frozen_layout(again)  # a live engine is no placeholder: it stays
    assert again.get_layout_engine() is not None


def test_the_frozen_layout_keeps_its_placeholder_after_saving():
    fig = _panels()
    engine = fig.get_layout_engine()
    png_bytes(fig)
    assert fig.get_layout_engine() is engine
