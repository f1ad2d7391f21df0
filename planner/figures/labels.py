"""Point labels that never overlap: each other, the markers of the points, or the texts and legend already in the axes
(:func:`place_labels`; the geometry alone: :func:`arrange_boxes`).

The method, in display pixels: the figure is drawn once without rendering and frozen (:func:`freeze_layout`), so that a
later draw or ``savefig`` puts everything where it was measured; every label's box is measured; the obstacles are every
point's marker, the texts already in the axes and the legend. Labels are placed greedily, the most crowded point first
(:func:`crowding_order`): of its candidate boxes, in order of preference, the first inside the axes that meets no
obstacle and no label placed before (a gap of :data:`PAD_PX` kept) is taken. Candidates: the 8 compass positions on two
near rings next to the marker, then rings further out, with as many directions as fit half a label apart, to the axes'
diagonal; a label off the near rings gets a leader line. A label with no free candidate is left out
(:attr:`Placed.omitted`), never drawn over another. Same input, same placement.

Limits: leader lines may cross other leaders, lines and labels (only text boxes and markers are kept apart); a label is
placed for the figure's size as drawn (resizing afterwards voids the guarantee; another dpi keeps it).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from matplotlib import patheffects
from matplotlib.axes import Axes
from matplotlib.backend_bases import RendererBase
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.text import Annotation
from numpy.typing import NDArray

from planner.figures.base import scale_and_north
from planner.figures.layout import Layouts, remember, reuse

#: pixels kept free between any two boxes (labels, markers, obstacles)
PAD_PX = 2.0
#: gaps (pixels beyond the marker) of the near rings, where a label needs no leader line
NEAR_GAPS_PX = (1.0, 4.0)
#: the first gap of the far rings (pixels beyond the marker)
FAR_START_PX = 10.0
#: compass directions of the near rings, in order of preference: NE, NW, SE, SW, E, W, N, S
COMPASS_DEG = (45.0, 135.0, 315.0, 225.0, 0.0, 180.0, 90.0, 270.0)
_BLOCK = 256  # candidates tested at once


@dataclass(frozen=True)
class PointLabel:
    """A point to label: data coordinates, the text, a key it is known by (default: the text), the size of its marker
    (diameter in points, as matplotlib's ``ms``; 0: none), which no label may cover, and the text's size (points;
    ``None``: the size :func:`place_labels` is given)."""

    x: float
    y: float
    text: str
    key: str = ""
    marker_pt: float = 6.0
    fontsize: float | None = None


@dataclass(frozen=True)
class Placed:
    """What :func:`place_labels` drew: the label texts, the leader lines, and the keys left out for want of room."""

    texts: tuple[Annotation, ...]
    leaders: tuple[Line2D, ...]
    omitted: tuple[str, ...]


def freeze_layout(fig: Figure, axes: Sequence[Axes] = (), layouts: Layouts | None = None) -> RendererBase:
    """Lay ``fig`` out once (its layout engine run, every axes' aspect applied, as a draw does before and after the
    layout), switch its layout engine off and fix the limits of ``axes``; returns the renderer that measures text at
    the figure's dpi. No draw: nothing drawn is measured here, and a plan figure's draw costs as much as its layout.

    ``layouts``: the layouts of figures drawn before with it; a figure of the same make-up takes its layout where that
    fits, instead of the engine's (:mod:`planner.figures.layout`), and the first of a make-up leaves its own there."""
    if not hasattr(fig.canvas, "get_renderer"):
        FigureCanvasAgg(fig)
    renderer: RendererBase = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    _apply_aspects(fig, renderer)
    engine = fig.get_layout_engine()
    if fig.axes and engine is not None:
        if layouts is None or not reuse(fig, layouts, renderer, lambda: _apply_aspects(fig, renderer)):
            engine.execute(fig)
            _apply_aspects(fig, renderer)
            if layouts is not None:
                remember(fig, layouts)
    for ax in axes:
        ax.set_xlim(ax.get_xlim())
        ax.set_ylim(ax.get_ylim())
        if ax.get_aspect() != "auto":
            ax.set_adjustable("box")  # the limits now fit the box: keep both, and no warning about fixed limits
    if engine is not None:
        fig.set_layout_engine("none")
    return renderer


def _apply_aspects(fig: Figure, renderer: RendererBase) -> None:
    """Each axes' aspect applied in its place, as :meth:`Figure.draw` does before it lays out and draws."""
    for ax in fig.axes:
        locator = ax.get_axes_locator()
        ax.apply_aspect(None if locator is None else locator(ax, renderer))


def _candidates(
    anchor: NDArray[np.float64], size: NDArray[np.float64], reach_px: float, limit_px: float
) -> tuple[NDArray[np.float64], int]:
    """Candidate box centres around ``anchor`` in order of preference, and how many are near (no leader).

    ``reach_px``: the marker's half size plus the gap; ``limit_px``: the largest gap tried."""
    w, h = float(size[0]), float(size[1])
    angles: list[NDArray[np.floating]] = [np.array([a for _ in NEAR_GAPS_PX for a in COMPASS_DEG])]
    gaps: list[NDArray[np.floating]] = [np.array([g for g in NEAR_GAPS_PX for _ in COMPASS_DEG])]
    gap = FAR_START_PX
    while gap <= limit_px:
        ring = reach_px + gap + (w + h) / 4.0  # about the radius of the boxes' centres
        n = max(8, math.ceil(2.0 * math.pi * ring / max((w + h) / 2.0, 1.0)))
        turn = (360.0 / n) * np.arange(n)
        turn = turn[np.lexsort((turn, np.minimum(turn, 360.0 - turn)))]  # nearest NE first (then the smaller angle)
        angles.append((45.0 + turn) % 360.0)
        gaps.append(np.full(n, gap))
        gap += max(h, 0.25 * gap)
    th = np.radians(np.concatenate(angles))
    c, s = np.cos(th), np.sin(th)
    g = np.concatenate(gaps)
    # the box's side (or corner) that faces the point lies ``gap`` along the direction beyond the marker
    sx = np.where(np.abs(c) > 0.38, np.sign(c), 0.0)
    sy = np.where(np.abs(s) > 0.38, np.sign(s), 0.0)
    centres = np.column_stack(
        [anchor[0] + g * c + sx * (reach_px + w / 2.0), anchor[1] + g * s + sy * (reach_px + h / 2.0)]
    )
    return centres, len(NEAR_GAPS_PX) * len(COMPASS_DEG)


def crowding_order(anchors: NDArray[np.float64], sizes: NDArray[np.float64]) -> list[int]:
    """Indices, the most crowded point first: most other points within three of its label sizes (w + h); ties by
    index."""
    n = len(anchors)
    if n == 0:
        return []
    d = np.hypot(*(anchors[:, None, :] - anchors[None, :, :]).transpose(2, 0, 1))
    near = (d < 3.0 * sizes.sum(axis=1)[:, None]).sum(axis=1) - 1
    return sorted(range(n), key=lambda i: (-int(near[i]), i))


def arrange_boxes(
    anchors: NDArray[np.float64],
    sizes: NDArray[np.float64],
    frame: tuple[float, float, float, float],
    obstacles: NDArray[np.float64] | None = None,
    marker_half: NDArray[np.float64] | None = None,
    max_gap_px: float | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Box centres for labels of ``sizes`` (n x 2, width and height) at ``anchors`` (n x 2), all in pixels, and whether
    each needs a leader line; NaN where the label was left out.

    Every box stays inside ``frame`` ``(x0, y0, x1, y1)`` and meets none of the ``obstacles`` (m x 4 boxes) nor the
    markers (``marker_half``: half each point's marker size); ``max_gap_px``: the farthest a box is put from its marker
    (``None``: up to the frame's diagonal).
    """
    anchors = np.asarray(anchors, dtype=float).reshape(-1, 2)
    sizes = np.asarray(sizes, dtype=float).reshape(-1, 2)
    n = len(anchors)
    half = np.zeros(n) if marker_half is None else np.asarray(marker_half, dtype=float)
    marks = np.column_stack([anchors - half[:, None], anchors + half[:, None]])
    fixed = np.asarray(obstacles, dtype=float).reshape(-1, 4) if obstacles is not None else np.empty((0, 4))
    boxes = [fixed, marks]
    centres = np.full((n, 2), np.nan)
    leader = np.zeros(n, dtype=bool)
    x0, y0, x1, y1 = frame
    limit_px = math.hypot(x1 - x0, y1 - y0) if max_gap_px is None else float(max_gap_px)
    for i in crowding_order(anchors, sizes):
        taken = np.vstack(boxes)
        cand, near = _candidates(anchors[i], sizes[i], half[i] + PAD_PX, limit_px)
        hw, hh = sizes[i] / 2.0
        for lo in range(0, len(cand), _BLOCK):
            c = cand[lo : lo + _BLOCK]
            bx = np.column_stack([c[:, 0] - hw, c[:, 1] - hh, c[:, 0] + hw, c[:, 1] + hh])
            inside = (bx[:, 0] >= x0) & (bx[:, 1] >= y0) & (bx[:, 2] <= x1) & (bx[:, 3] <= y1)
            hit = (
                (bx[:, None, 0] < taken[None, :, 2] + PAD_PX)
                & (bx[:, None, 2] > taken[None, :, 0] - PAD_PX)
                & (bx[:, None, 1] < taken[None, :, 3] + PAD_PX)
                & (bx[:, None, 3] > taken[None, :, 1] - PAD_PX)
            ).any(axis=1)
            free = np.flatnonzero(inside & ~hit)
            if free.size:
                k = int(free[0])
                centres[i] = c[k]
                leader[i] = lo + k >= near
                boxes.append(bx[k : k + 1])
                break
    return centres, leader


def _fixed_boxes(ax: Axes, renderer: RendererBase) -> NDArray[np.float64]:
    """The boxes of the visible texts already in ``ax`` and of its legend (pixels)."""
    out = [t.get_window_extent(renderer) for t in ax.texts if t.get_visible() and t.get_text()]
    legend = ax.get_legend()
    if legend is not None and legend.get_visible():
        out.append(legend.get_window_extent(renderer))
    return np.array([b.extents for b in out], dtype=float).reshape(-1, 4)


def place_labels(
    ax: Axes,
    labels: Sequence[PointLabel],
    *,
    fontsize: float = 7.0,
    color: str = "black",
    leader_color: str = "0.45",
    gid: str = "label",
    max_gap_px: float | None = None,
    renderer: RendererBase | None = None,
) -> Placed:
    """Label ``labels`` in ``ax`` so that no two labels, no label and marker, and no label and earlier text or legend
    overlap (the module text gives the method and its limits).

    Call it last, once everything else of the figure is drawn: it freezes the layout (:func:`freeze_layout`), unless
    ``renderer`` is the one :func:`freeze_layout` returned for ``ax`` (and the figure's other axes to label), which
    saves one draw per panel. Each label is an annotation with ``gid`` ``"{gid}:{key}"``, a white halo, centred on its
    box, at most ``max_gap_px`` from its marker (``None``: anywhere in the axes).
    """
    fig = ax.get_figure(root=True)
    assert isinstance(fig, Figure)
    if renderer is None:
        renderer = freeze_layout(fig, [ax])
    fixed = _fixed_boxes(ax, renderer)
    arts = [_annotation(ax, p, fontsize, color, gid) for p in labels]
    sizes = np.array([a.get_window_extent(renderer).size for a in arts], dtype=float).reshape(-1, 2)
    anchors = ax.transData.transform(np.array([(p.x, p.y) for p in labels], dtype=float).reshape(-1, 2))
    half = np.array([p.marker_pt / 2.0 * fig.dpi / 72.0 for p in labels], dtype=float)
    frame = tuple(float(v) for v in ax.bbox.extents)
    centres, leader = arrange_boxes(anchors, sizes, (frame[0], frame[1], frame[2], frame[3]), fixed, half, max_gap_px)
    kept: list[Annotation] = []
    lines: list[Line2D] = []
    omitted: list[str] = []
    to_points = 72.0 / fig.dpi
    for p, a, c, lead, anchor, size, r in zip(labels, arts, centres, leader, anchors, sizes, half):
        if np.isnan(c[0]):
            a.remove()
            omitted.append(p.key or p.text)
            continue
        a.xyann = ((c[0] - anchor[0]) * to_points, (c[1] - anchor[1]) * to_points)
        kept.append(a)
        if lead:
            lines += _leader(ax, anchor, c, size, r, leader_color)
    return Placed(tuple(kept), tuple(lines), tuple(omitted))


def _annotation(ax: Axes, p: PointLabel, fontsize: float, color: str, gid: str) -> Annotation:
    """The label of ``p`` drawn on its point (moved to its box later), with a white halo."""
    return ax.annotate(
        p.text,
        (p.x, p.y),
        xytext=(0.0, 0.0),
        textcoords="offset points",
        ha="center",
        va="center",
        fontsize=fontsize if p.fontsize is None else p.fontsize,
        color=color,
        zorder=6,
        annotation_clip=False,
        path_effects=[patheffects.withStroke(linewidth=2.0, foreground="white")],
        gid=f"{gid}:{p.key or p.text}",
    )


def _leader(
    ax: Axes,
    anchor: NDArray[np.float64],
    centre: NDArray[np.float64],
    size: NDArray[np.float64],
    marker_half: float,
    color: str,
) -> list[Line2D]:
    """A thin line from the edge of the marker at ``anchor`` to the nearest point of the box (all in pixels)."""
    near = np.clip(anchor, centre - size / 2.0, centre + size / 2.0)
    v = near - anchor
    start = anchor + v * min(1.0, marker_half / max(float(np.hypot(*v)), 1e-9))
    (xa, ya), (xb, yb) = ax.transData.inverted().transform(np.array([start, near]))
    return ax.plot([xa, xb], [ya, yb], color=color, lw=0.5, zorder=5, scalex=False, scaley=False)


def note_omitted(ax: Axes, placed: Placed) -> None:
    """Say under ``ax`` (in its x label, whose room the layout has already kept) how many labels were left out."""
    if placed.omitted:
        n = len(placed.omitted)
        ax.set_xlabel(f"{ax.get_xlabel()}   ({n} label{'s' if n > 1 else ''} left out: no room)")


def finish_plans(
    fig: Figure,
    panels: Sequence[tuple[Axes, str, Sequence[PointLabel]]],
    fontsize: float = 7.0,
    max_gap_px: float | None = None,
    layouts: Layouts | None = None,
) -> list[Placed]:
    """The last step of a plan figure whose panels were set up by :func:`planner.figures.base.frame_axes`: freeze the
    layout once (``layouts``: as :func:`freeze_layout`), then in each panel ``(axes, frame, labels)`` draw the scale
    bar and north arrow in the final limits and place the labels (:func:`place_labels`), noting any left out
    (:func:`note_omitted`).

    Returns what :func:`place_labels` returned for each panel."""
    renderer = freeze_layout(fig, [ax for ax, _, _ in panels], layouts)
    out = []
    for ax, frame, labels in panels:
        scale_and_north(ax, frame)
        placed = place_labels(ax, labels, fontsize=fontsize, max_gap_px=max_gap_px, renderer=renderer)
        note_omitted(ax, placed)
        out.append(placed)
    return out
