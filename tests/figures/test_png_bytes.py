"""A frozen figure is saved whole in one draw (:func:`planner.figures.base.png_bytes`): the bytes ``savefig`` of the
whole figure gives (its pixels; opaque, in RGB), nothing drawn past its edge (what ``bbox_inches="tight"`` would cut to lies inside it), widened
where a title runs past the edge; a live layout is laid out and kept."""

from __future__ import annotations

import io

import numpy as np
import PIL.Image
import pytest
from matplotlib.figure import Figure

from planner.figures.base import PLAN_MARGIN, PNG_DPI, drop_frozen_layout, frame_axes, png_bytes
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


def _pixels(png: bytes) -> np.ndarray:
    """The RGB pixels of a PNG."""
    return np.asarray(PIL.Image.open(io.BytesIO(png)).convert("RGB"))


@pytest.mark.slow  # two figures drawn: seconds on a busy machine
def test_a_frozen_figure_gives_the_pixels_of_savefig_of_the_whole_figure():
    buf = io.BytesIO()
    fig = _panels()
    drop_frozen_layout(fig)
    fig.savefig(buf, format="png", dpi=110)
    assert np.array_equal(_pixels(png_bytes(_panels())), _pixels(buf.getvalue()))


def test_an_opaque_figure_is_saved_as_rgb_at_the_set_level():
    png = png_bytes(_panels())
    image = PIL.Image.open(io.BytesIO(png))
    assert image.mode == "RGB" and image.info.get("dpi") == pytest.approx((PNG_DPI, PNG_DPI), abs=0.01)
    transparent = Figure(figsize=(2, 1))
    transparent.patch.set_alpha(0.0)
    transparent.subplots().patch.set_alpha(0.0)
    assert PIL.Image.open(io.BytesIO(png_bytes(transparent))).mode == "RGBA"  # transparency kept


def _size(png: bytes) -> tuple[int, int]:
    """(width, height) in pixels of a PNG."""
    return int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")


def test_a_title_wider_than_the_figure_widens_the_image():
    fig = _panels()
    fig.suptitle("a site name long enough to run past both edges of a six-inch figure " * 2)
    width, height = _size(png_bytes(fig))
    title = fig.texts[-1].get_window_extent(fig.canvas.get_renderer())
    assert width >= title.width * 110 / fig.dpi and width > 6 * 110 and height >= 3 * 110


def test_a_live_layout_is_still_laid_out_and_kept():
    fig = Figure(figsize=(4, 3), layout="constrained")
    fig.subplots().plot([0, 1], [0, 1])
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, bbox_inches="tight")
    again = Figure(figsize=(4, 3), layout="constrained")
    again.subplots().plot([0, 1], [0, 1])
    assert np.array_equal(_pixels(png_bytes(again)), _pixels(buf.getvalue()))
    drop_frozen_layout(again)  # a live engine is no placeholder: it stays
    assert again.get_layout_engine() is not None


def test_a_frozen_figure_is_drawn_once_whole_nothing_past_its_edge_and_keeps_its_placeholder(monkeypatch):
    fig = _panels()
    engine = fig.get_layout_engine()
    draws = []
    real = Figure.draw
    monkeypatch.setattr(Figure, "draw", lambda self, renderer: draws.append(1) or real(self, renderer))
    png = png_bytes(fig)
    assert len(draws) == 1 and _size(png) == (6 * 110, 3 * 110)  # one draw, the whole figure
    monkeypatch.undo()
    assert fig.get_layout_engine() is engine
    # what "tight" would cut to lies inside the figure: the whole figure loses nothing
    tight = fig.get_tightbbox(fig.canvas.get_renderer())
    assert 0 <= tight.x0 and 0 <= tight.y0 and tight.x1 <= 6 and tight.y1 <= 3
