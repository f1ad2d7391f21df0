"""What every plan figure carries: equal axes in metres, a scale bar and a north (frame +y) arrow."""

from __future__ import annotations

import io
import math
from collections.abc import Callable

import matplotlib as mpl
import PIL.Image
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.layout_engine import PlaceHolderLayoutEngine
from matplotlib.text import Text
from matplotlib.transforms import Bbox

#: the resolution of the report's images (:func:`png_bytes`); a figure made at it is laid out, labelled and drawn with
#: one renderer, which measures each text once
PNG_DPI = 110
#: zlib level of those images: on plan figures 3 encodes a quarter faster than the default 6, a few per cent larger
PNG_LEVEL = 3

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


def png_bytes(fig: Figure, dpi: int = PNG_DPI) -> bytes:
    """The figure as PNG bytes, drawn once where its layout is known.

    A figure laid out by its engine and frozen (:func:`planner.figures.labels.freeze_layout`) is saved whole: the
    constrained layout has put every axes, tick label, colour bar and legend inside the figure, 3 points from its edge,
    so the box ``bbox_inches="tight"`` would measure is the figure less that padding; measuring it walks every axes'
    ticks and texts once more, about a fifth of a plan figure's time. Only a title or figure text can pass the edge
    (the layout makes room for a title's height, not its width): the image is then widened to hold it. A figure with no
    layout engine is cut to what is drawn, measured without a draw; a live layout is saved with ``"tight"``."""
    engine = fig.get_layout_engine()
    if engine is not None and not isinstance(engine, PlaceHolderLayoutEngine):  # a live layout: it needs the draw
        return _encoded(fig, dpi, "tight")
    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    pad = float(mpl.rcParams["savefig.pad_inches"])
    if engine is None:  # nothing laid out: cut to the tight box, measured at ``dpi``
        saved_dpi = fig.dpi
        fig.dpi = dpi
        try:
            box = fig.get_tightbbox(fig.canvas.get_renderer()).padded(pad, pad)  # type: ignore[attr-defined]
        finally:
            fig.dpi = saved_dpi
    else:
        box = _past_the_edge(fig, pad)
    drop_frozen_layout(fig)
    try:
        return _encoded(fig, dpi, box)
    finally:
        fig.set_layout_engine(engine)


def _encoded(fig: Figure, dpi: int, box: Bbox | str) -> bytes:
    """``fig`` drawn at ``dpi`` into ``box`` (inches, or ``"tight"``) as PNG: RGB where every pixel is opaque (a
    plan's image a tenth smaller than RGBA), at zlib level :data:`PNG_LEVEL`."""
    if not isinstance(fig.canvas, FigureCanvasAgg):  # its own canvas (not a passing one): its renderer stays
        FigureCanvasAgg(fig)
    raw = io.BytesIO()
    fig.savefig(raw, format="rgba", dpi=dpi, bbox_inches=box)
    drawn = fig.canvas.renderer  # type: ignore[attr-defined]  # the one the image was drawn with: its size
    size = (int(drawn.width), int(drawn.height))
    image = PIL.Image.frombuffer("RGBA", size, raw.getvalue(), "raw", "RGBA", 0, 1)
    alpha = image.getchannel("A").getextrema()
    if alpha == (255, 255):
        image = image.convert("RGB")
    out = io.BytesIO()
    image.save(out, format="png", compress_level=PNG_LEVEL, dpi=(dpi, dpi))
    return out.getvalue()


def _past_the_edge(fig: Figure, pad: float) -> Bbox:
    """The figure's box in inches, widened (and padded by ``pad``) to hold any figure text or axes title that runs past
    its edge."""
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    # the figure's texts and each axes' plain Text children: its titles and texts (its placed labels are annotations,
    # inside the axes by construction)
    texts = [*fig.texts, *(t for ax in fig.axes for t in ax.get_children() if type(t) is Text)]
    boxes = [t.get_window_extent(renderer) for t in texts if t.get_visible() and t.get_text()]
    whole = fig.bbox
    out = [b for b in boxes if b.x0 < whole.x0 or b.y0 < whole.y0 or b.x1 > whole.x1 or b.y1 > whole.y1]
    if not out:
        return fig.bbox_inches
    return Bbox.union([whole, *out]).transformed(fig.dpi_scale_trans.inverted()).padded(pad, pad)


def drop_frozen_layout(fig: Figure) -> None:
    """Take away the placeholder engine a frozen layout leaves (:func:`planner.figures.labels.freeze_layout`): with
    any layout engine set, ``savefig`` draws the figure once more before it draws it into the file; nothing is left to
    lay out. A live engine is kept."""
    if isinstance(fig.get_layout_engine(), PlaceHolderLayoutEngine):
        fig.set_layout_engine(None)
