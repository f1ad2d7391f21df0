"""A constrained layout laid once and reused for figures of the same make-up (:class:`Layouts`).

Matplotlib's constrained layout measures every axes' decorations (tick labels, axis labels, titles, colour bars) twice
over, each measure recomputing the ticks several times: most of a plan figure's cost before it is drawn. The figures
of one report that share a make-up (size, dpi, the same axes and colour bars, a figure title or not) get nearly the
same layout, so the first is laid out by its engine and its positions (:class:`Layout`) are tried on the next ones.
A reused layout is kept only where it holds what the engine guarantees (:func:`fits`): every axes' decorations (as the
engine measures them) and every figure text and legend lie inside the figure and clear of each other by
:data:`GAP_PX`; else the engine lays that figure out afresh. Same figures in the same order, same layouts.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backend_bases import RendererBase
from matplotlib.figure import Figure
from matplotlib.transforms import Bbox

#: pixels kept free between any two laid-out boxes (axes with their decorations, figure texts, legends)
GAP_PX = 2.0

Key = tuple[object, ...]


@dataclass(frozen=True, kw_only=True)
class Layout:
    """Where a layout engine put a figure's axes (in ``fig.axes`` order): each one's original position (figure
    fraction, ``x0, y0, width, height``), anchor and box aspect, and the figure title's position (None: none)."""

    positions: tuple[tuple[float, float, float, float], ...]
    anchors: tuple[str | tuple[float, float], ...]
    box_aspects: tuple[float | None, ...]
    suptitle: tuple[float, float] | None


@dataclass(frozen=True)
class Layouts:
    """The layouts laid so far for figures drawn together, by make-up (:func:`make_up`); the first figure of each
    make-up sets it. Filled as figures are laid out (the mapping, not the object, changes)."""

    by_make_up: dict[Key, Layout] = field(default_factory=dict)
    #: take no new make-up: a figure of another make-up is laid out by its engine each time, so that each figure's
    #: layout depends on the first figures' alone, not on which others were drawn before it (figures drawn apart)
    closed: bool = False


def make_up(fig: Figure) -> Key:
    """What must agree for a layout to carry over: the figure's size and dpi, each axes' place in its grid (rows,
    columns, first and last cell; None: a colour bar or an axes placed by hand), kind (colour bar or not), visibility
    and whether it takes part in the layout, the figure title and the figure legends."""
    axes = tuple((_cell(ax), hasattr(ax, "_colorbar"), ax.get_visible(), ax.get_in_layout()) for ax in fig.axes)
    suptitle = getattr(fig, "_suptitle", None)
    return (
        tuple(round(float(v), 6) for v in fig.get_size_inches()),
        float(fig.dpi),
        axes,
        suptitle is not None,
        len(fig.legends),
    )


def _cell(ax: Axes) -> tuple[int, int, int, int] | None:
    spec = ax.get_subplotspec()
    return None if spec is None else spec.get_geometry()


def capture(fig: Figure) -> Layout:
    """The layout ``fig`` has now (after its engine ran)."""
    suptitle = getattr(fig, "_suptitle", None)
    positions = []
    for ax in fig.axes:
        x0, y0, w, h = (float(v) for v in ax.get_position(original=True).bounds)
        positions.append((x0, y0, w, h))
    at = None
    if suptitle is not None:
        x, y = suptitle.get_position()
        at = (float(x), float(y))
    return Layout(
        positions=tuple(positions),
        anchors=tuple(ax.get_anchor() for ax in fig.axes),
        box_aspects=tuple(ax.get_box_aspect() for ax in fig.axes),
        suptitle=at,
    )


def apply(fig: Figure, layout: Layout) -> None:
    """Put ``fig``'s axes (and title) where ``layout`` says; each axes stays in the layout or out of it as it was
    (``set_position`` takes it out)."""
    for ax, pos, anchor, aspect in zip(fig.axes, layout.positions, layout.anchors, layout.box_aspects):
        in_layout = ax.get_in_layout()
        ax.set_position(pos, which="both")
        ax.set_in_layout(in_layout)
        ax.set_anchor(anchor)
        ax.set_box_aspect(aspect)
    suptitle = getattr(fig, "_suptitle", None)
    if suptitle is not None and layout.suptitle is not None:
        suptitle.set_position(layout.suptitle)


def laid_out_boxes(fig: Figure, renderer: RendererBase) -> list[Bbox]:
    """The boxes a layout keeps apart (pixels): each visible axes with its decorations as the constrained layout
    measures them (a title by its height only), each figure text and each figure legend."""
    out = [
        ax.get_tightbbox(renderer, for_layout_only=True) for ax in fig.axes if ax.get_visible() and ax.get_in_layout()
    ]
    out += [t.get_window_extent(renderer) for t in fig.texts if t.get_visible() and t.get_text()]
    out += [leg.get_window_extent(renderer) for leg in fig.legends if leg.get_visible()]
    return [b for b in out if b is not None]


def fits(fig: Figure, renderer: RendererBase) -> bool:
    """Whether every box of :func:`laid_out_boxes` lies inside the figure and no two come closer than
    :data:`GAP_PX`."""
    boxes = np.array([b.extents for b in laid_out_boxes(fig, renderer)], dtype=float).reshape(-1, 4)
    x0, y0, x1, y1 = fig.bbox.extents
    if (boxes[:, 0] < x0).any() or (boxes[:, 1] < y0).any() or (boxes[:, 2] > x1).any() or (boxes[:, 3] > y1).any():
        return False
    for i, j in itertools.combinations(range(len(boxes)), 2):
        a, b = boxes[i], boxes[j]
        if a[0] < b[2] + GAP_PX and b[0] < a[2] + GAP_PX and a[1] < b[3] + GAP_PX and b[1] < a[3] + GAP_PX:
            return False
    return True


def reuse(fig: Figure, layouts: Layouts, renderer: RendererBase, aspects: Callable[[], None]) -> bool:
    """Lay ``fig`` out as the first figure of its make-up in ``layouts`` was, where that fits (:func:`fits`; the
    axes' aspects applied by ``aspects`` in the new places); False, and ``fig`` as it was, where it has no such
    figure or the layout does not fit it (the engine lays it out then)."""
    layout = layouts.by_make_up.get(make_up(fig))
    if layout is None:
        return False
    before = capture(fig)
    limits = [(ax.get_xbound(), ax.get_ybound()) for ax in fig.axes]
    apply(fig, layout)
    aspects()
    if fits(fig, renderer):
        return True
    apply(fig, before)  # as the engine would have found it: the same layout as without a try
    for ax, (x, y) in zip(fig.axes, limits):
        ax.set_xbound(*x)
        ax.set_ybound(*y)
    return False


def remember(fig: Figure, layouts: Layouts) -> None:
    """Keep the layout the engine just gave ``fig`` for the next figures of its make-up (the first one stays; none
    where ``layouts`` is closed)."""
    if not layouts.closed:
        layouts.by_make_up.setdefault(make_up(fig), capture(fig))
