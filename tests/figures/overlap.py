"""What the label tests check on a drawn figure: every text's box, and the pairs of boxes that overlap."""

from __future__ import annotations

import itertools

import numpy as np
from matplotlib.figure import Figure
from matplotlib.text import Text
from numpy.typing import NDArray


def drawn_texts(fig: Figure) -> list[Text]:
    """Every visible, non-empty text of the figure's axes (labels, scale bar, north arrow, room names), after a
    draw at the figure's dpi (layout, aspect and text positions as any draw makes them; no pixels)."""
    fig.draw_without_rendering()
    return [t for ax in fig.axes for t in ax.texts if t.get_visible() and t.get_text()]


def boxes(fig: Figure, texts: list[Text]) -> NDArray[np.float64]:
    """Window extents ``(x0, y0, x1, y1)`` of ``texts`` in pixels."""
    renderer = fig.canvas.get_renderer()
    return np.array([t.get_window_extent(renderer).extents for t in texts], dtype=float).reshape(-1, 4)


def overlapping(fig: Figure) -> list[tuple[str, str, float]]:
    """Pairs of texts whose boxes overlap with a positive area (touching allowed), with the area in px^2."""
    texts = drawn_texts(fig)
    b = boxes(fig, texts)
    out = []
    for i, j in itertools.combinations(range(len(texts)), 2):
        w = min(b[i, 2], b[j, 2]) - max(b[i, 0], b[j, 0])
        h = min(b[i, 3], b[j, 3]) - max(b[i, 1], b[j, 1])
        if w > 0 and h > 0:
            out.append((texts[i].get_text(), texts[j].get_text(), float(w * h)))
    return out


def labels(fig: Figure, prefix: str = "label:") -> dict[str, Text]:
    """The placed labels by ``gid`` (``label:station:ID``, ``label:control:NAME``)."""
    return {t.get_gid(): t for ax in fig.axes for t in ax.texts if (t.get_gid() or "").startswith(prefix)}
