"""What every plan figure carries: equal axes in metres, a scale bar and a north (frame +y) arrow."""

from __future__ import annotations

import io
import math
from collections.abc import Callable

import matplotlib as mpl
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.layout_engine import PlaceHolderLayoutEngine

#: room around the data of a plan panel (a share of its span, as ``Axes.margins``): the scale bar and the
#: north arrow stand in it, clear of walls and stations
PLAN_MARGIN = 0.12


def legend_once() -> Callable[[object, str], str | None]:
    """``once(key, text)``: ``text`` for the first artist of its kind, ``None`` (no legend entry) for the rest."""
    shown: set[object] = set()

    def once(key: object, text: str) -> str | None:
        first = key not in shown
        shown.add(key)
        return text if first else None

    return once


def nice_length(span_m: float) -> float:
    """A round scale-bar length (1, 2 or 5 x 10^k m) close to a fifth of ``span_m``."""
    target = max(span_m / 5.0, 1e-6)
    k = math.floor(math.log10(target))
    return min((m * 10**k for m in (1, 2, 5, 10)), key=lambda v: abs(v - target))


def decorate_plan(ax: Axes, frame: str) -> None:
    """Equal aspect, metre labels, a scale bar (lower left) and a north arrow (upper right).

    In a zone's own frame "north" is the frame's +y axis; the arrow says so.
    """
    frame_axes(ax)
    scale_and_north(ax, frame)


def frame_axes(ax: Axes, margin: float | None = None) -> None:
    """Equal aspect (limits adjusted), metre labels, a light grid; ``margin``: room around the data (a share of its
    span, as ``Axes.margins``) for the scale bar and north arrow; ``None``: matplotlib's default."""
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    if margin is not None:
        ax.margins(margin)
    ax.autoscale_view()
    ax.grid(True, lw=0.3, alpha=0.5)


def scale_and_north(ax: Axes, frame: str) -> None:
    """A scale bar in the lower left and a north arrow in the upper right of the axes' present limits (after
    :func:`planner.figures.labels.freeze_layout` they are the final ones)."""
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    w, h = x1 - x0, y1 - y0
    bar = nice_length(w)
    bx, by = x0 + 0.05 * w, y0 + 0.05 * h
    ax.plot([bx, bx + bar], [by, by], color="black", lw=3, solid_capstyle="butt", scalex=False, scaley=False)
    ax.text(bx + bar / 2, by + 0.015 * h, f"{bar:g} m", ha="center", va="bottom", fontsize=8)
    label = "N" if frame == "site" else "N\n(frame +y)"
    ax.annotate(
        label,
        xy=(0.95, 0.95),
        xytext=(0.95, 0.83),
        xycoords="axes fraction",
        ha="center",
        va="top",
        fontsize=8,
        arrowprops={"arrowstyle": "-|>", "color": "black"},
    )


def png_bytes(fig: Figure, dpi: int = 110) -> bytes:
    """The figure as PNG bytes, cut to what is drawn (``bbox_inches="tight"``).

    A figure whose layout is frozen (:func:`planner.figures.labels.freeze_layout`) is measured at ``dpi`` and drawn
    once: ``savefig`` with ``"tight"`` draws it twice, once to measure, once to render, and the plan figures spend
    most of the report's time drawing. The box is the one ``"tight"`` measures, so the image is the same."""
    buf = io.BytesIO()
    engine = fig.get_layout_engine()
    if engine is not None and not isinstance(engine, PlaceHolderLayoutEngine):  # a live layout: it needs the draw
        fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight")
        return buf.getvalue()
    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    saved_dpi = fig.dpi
    fig.dpi = dpi
    try:
        box = fig.get_tightbbox(fig.canvas.get_renderer())  # type: ignore[attr-defined]
    finally:
        fig.dpi = saved_dpi
    pad = float(mpl.rcParams["savefig.pad_inches"])
    drop_frozen_layout(fig)
    try:
        fig.savefig(buf, format="png", dpi=dpi, bbox_inches=box.padded(pad, pad))
    finally:
        fig.set_layout_engine(engine)
    return buf.getvalue()


def drop_frozen_layout(fig: Figure) -> None:
    """Take away the placeholder engine a frozen layout leaves (:func:`planner.figures.labels.freeze_layout`): with
    any layout engine set, ``savefig`` draws the figure once more before it draws it into the file; nothing is left to
    lay out. A live engine is kept."""
    if isinstance(fig.get_layout_engine(), PlaceHolderLayoutEngine):
        fig.set_layout_engine(None)
