"""A layout laid once is reused for figures of the same make-up where it fits, and the engine lays out those where it
does not (:mod:`planner.figures.layout`)."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.figure import Figure
from matplotlib.layout_engine import ConstrainedLayoutEngine

from planner.figures.base import PLAN_MARGIN, frame_axes
from planner.figures.labels import PointLabel, finish_plans
from planner.figures.layout import Layouts, fits, laid_out_boxes, make_up


def _panels(span: float = 40.0, seed: int = 3, layouts: Layouts | None = None) -> Figure:
    """Two plan panels with a colour bar each, a legend, a figure title and numbered points: a plan figure's make-up;
    ``span``: the data's extent (its tick labels' width)."""
    rng = np.random.default_rng(seed)
    fig = Figure(figsize=(6, 3), layout="constrained")
    panels = []
    for ax in fig.subplots(1, 2):
        xy = rng.uniform(0.0, span, (5, 2))
        ax.plot(xy[:, 0], xy[:, 1], "o", ms=6, ls="none", label="station")
        art = ax.scatter(xy[:, 0], xy[:, 1], c=xy[:, 0], s=4)
        fig.colorbar(art, ax=ax, shrink=0.8).set_label("x (m)")
        frame_axes(ax, PLAN_MARGIN)
        ax.legend(loc="upper left", fontsize=7)
        ax.set_title("a panel")
        panels.append((ax, "site", [PointLabel(x, y, str(k), f"station:{k}", 6.0) for k, (x, y) in enumerate(xy, 1)]))
    fig.suptitle("a figure")
    finish_plans(fig, panels, fontsize=7, layouts=layouts)
    return fig


def _positions(fig: Figure) -> list[tuple[float, ...]]:
    return [tuple(np.round(ax.get_position(original=True).bounds, 9)) for ax in fig.axes]


def _count_engine_runs(monkeypatch) -> list[int]:
    runs: list[int] = []
    real = ConstrainedLayoutEngine.execute
    monkeypatch.setattr(ConstrainedLayoutEngine, "execute", lambda self, fig: runs.append(1) or real(self, fig))
    return runs


def test_a_figure_of_the_same_make_up_takes_the_first_ones_layout_without_the_engine(monkeypatch):
    runs = _count_engine_runs(monkeypatch)
    layouts = Layouts()
    first = _panels(seed=3, layouts=layouts)
    second = _panels(seed=4, layouts=layouts)
    assert len(runs) == 1  # the first only
    assert _positions(second) == _positions(first)
    assert fits(second, second.canvas.get_renderer())
    assert len(layouts.by_make_up) == 1 and make_up(first) == make_up(second)


@pytest.mark.slow  # three figures laid out and labelled: seconds on a busy machine
def test_a_figure_the_layout_does_not_fit_is_laid_out_afresh_as_without_one(monkeypatch):
    layouts = Layouts()
    _panels(span=40.0, layouts=layouts)
    runs = _count_engine_runs(monkeypatch)
    wide = _panels(span=4.0e7, seed=5, layouts=layouts)  # long tick labels: the narrow margins would not hold them
    assert len(runs) == 1
    alone = _panels(span=4.0e7, seed=5)
    assert _positions(wide) == _positions(alone)
    assert [ax.get_xlim() for ax in wide.axes] == [ax.get_xlim() for ax in alone.axes]
    assert fits(wide, wide.canvas.get_renderer())


def test_the_engines_layout_fits_by_the_check():
    fig = _panels()
    renderer = fig.canvas.get_renderer()
    assert fits(fig, renderer)
    boxes = laid_out_boxes(fig, renderer)
    assert len(boxes) == 4 + 1  # two panels, two colour bars, the figure title


def test_another_make_up_is_laid_out_by_the_engine(monkeypatch):
    layouts = Layouts()
    _panels(layouts=layouts)
    runs = _count_engine_runs(monkeypatch)
    other = Figure(figsize=(5, 3), layout="constrained")  # another size
    ax = other.subplots()
    ax.plot([0, 1], [0, 1])
    finish_plans(other, [(ax, "site", [])], layouts=layouts)
    assert len(runs) == 1 and len(layouts.by_make_up) == 2
