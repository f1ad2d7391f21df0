"""field.pdf: the field sheet to print (matplotlib's PDF backend).

Page 1: the plan figure of field.html (:func:`planner.field.figure.figure`) on A4 landscape, or on A3 landscape where it
is large (:func:`map_paper`: the plan would print at a scale smaller than 1:500 on A4, or it has more than
:data:`A3_SETUPS` setups). Then the setup table on A4 landscape pages, drawn as text rows (:func:`rows_per_page` rows a
page, from the page height; the header repeated on each page; a row never split), and the totals under the last row. The
space of the totals is kept free on every page, so the table takes exactly ceil(setups / rows_per_page) pages.

The file is written uncompressed (``pdf.compression`` 0, so the page text can be read back by a test) and without a
creation date, so the same sheet gives the same bytes.
"""

from __future__ import annotations

import itertools
import math
import textwrap
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.figure import Figure

from planner import __version__
from planner.field.crossing import advice
from planner.field.figure import figure
from planner.field.record import rows, totals
from planner.field.run import FieldPlan
from planner.field.storeys import stairs_line
from planner.figures.base import drop_frozen_layout

#: paper sizes in inches, (width, height) landscape
A4 = (11.69, 8.27)
A3 = (16.54, 11.69)
#: the plan goes on A3 where on A4 it would print smaller than 1:MAP_SCALE ...
MAP_SCALE = 500.0
#: ... or where it has more setups than this (numbered circles crowd)
A3_SETUPS = 40
#: the share of an A4 landscape page the plan's drawing gets (axes labels, title and legend take the rest)
_DRAWN = (0.80, 0.78)
#: the table: font size (pt), line height (in font sizes), margins (in)
FONT_PT = 8.0
LINE = 1.5
MARGIN_IN = 0.5
#: lines at the top of a table page (title, blank) and reserved at its foot (totals, sessions, advice x 3, blank)
TOP_LINES = 2
FOOT_LINES = 6
#: the PDF's column heads (shorter than field.html's; a note under the title says what they are)
HEADS = ("no.", "station", "x m", "y m", "zone", "side", "height m", "setting", "walk m", "min", "targets seen", "ses.")
#: what the short heads mean, in each page's title
KEY = "(height: instrument height; min: minutes with the walk to the setup; ses.: session)"
_LEFT = {1, 4, 5, 7, 10}  # text columns, left-aligned
_CHAR = 0.64  # a character's width in font sizes (DejaVu Sans: digits 0.636, most letters under it)


def map_paper(fp: FieldPlan) -> tuple[str, tuple[float, float]]:
    """("A4" or "A3", landscape size in inches) for the plan page (see the module text)."""
    pts = [p for leg in fp.legs for p in leg] + [q for w in fp.space.solid_walls for q in w]
    pts += [(t.x, t.y) for t in fp.targets] + [fp.start_xy]
    xy = np.asarray(pts, dtype=float).reshape(-1, 2)
    w, h = (xy.max(axis=0) - xy.min(axis=0)) if len(xy) else (0.0, 0.0)
    scale = max(w / (A4[0] * 0.0254 * _DRAWN[0]), h / (A4[1] * 0.0254 * _DRAWN[1]))
    return ("A3", A3) if scale > MAP_SCALE or len(fp.order) > A3_SETUPS else ("A4", A4)


def rows_per_page(page_height_in: float = A4[1], font_pt: float = FONT_PT) -> int:
    """Table rows on one page ``page_height_in`` high (A4 landscape): the lines between the margins, less the
    title, the header row and the totals' reserved lines."""
    lines = math.floor((page_height_in - 2 * MARGIN_IN) * 72.0 / (font_pt * LINE))
    return lines - TOP_LINES - 1 - FOOT_LINES


def _columns(cells: list[list[str]], width_chars: int) -> tuple[list[int], list[int]]:
    """Column widths in characters (the widest cell or head, plus 2) and their left edges; the targets column
    takes what is left of the page's width."""
    widths = [max([len(HEADS[c])] + [len(r[c]) for r in cells]) + 2 for c in range(len(HEADS))]
    rest = width_chars - (sum(widths) - widths[10])
    widths[10] = max(len(HEADS[10]) + 2, min(widths[10], rest))
    return widths, [0, *itertools.accumulate(widths[:-1])]


def _fit(text: str, width: int) -> str:
    """``text`` cut to ``width`` characters at a space, "+N" saying how many words were left off."""
    if len(text) <= width:
        return text
    words = text.split()
    for keep in range(len(words) - 1, 0, -1):
        cut = " ".join(words[:keep]) + f" +{len(words) - keep}"
        if len(cut) <= width:
            return cut
    return text[: max(width - 1, 1)] + "~"


def _row(fig: Figure, y: float, values: list[str], widths: list[int], edges: list[int], bold: bool = False) -> None:
    """One text row at height ``y`` (figure fraction)."""
    pw, _ = fig.get_size_inches()
    char = FONT_PT * _CHAR / 72.0 / pw  # one character in figure fraction
    x0 = MARGIN_IN / pw
    weight = "bold" if bold else None
    for c, v in enumerate(values):
        v = _fit(v, widths[c] - 2)
        left = c in _LEFT
        x = x0 + (edges[c] if left else edges[c] + widths[c] - 2) * char
        fig.text(x, y, v, ha="left" if left else "right", va="baseline", fontsize=FONT_PT, fontweight=weight)


def _table_pages(fp: FieldPlan) -> list[Figure]:
    """The setup table on A4 landscape pages (see the module text)."""
    pw, ph = A4
    line = FONT_PT * LINE / 72.0 / ph  # one line in figure fraction
    width_chars = int((pw - 2 * MARGIN_IN) * 72.0 / (FONT_PT * _CHAR))
    cells = [[f"{v}" for v in r] for r in rows(fp)]
    widths, edges = _columns([*cells, ["", *[f"{v}" for v in totals(fp)[1:]]]], width_chars)
    per = rows_per_page(ph)
    n_pages = max(1, math.ceil(len(cells) / per))
    pages = []
    for page in range(n_pages):
        fig = Figure(figsize=(pw, ph))
        y = 1.0 - MARGIN_IN / ph - line
        title = f"Field sheet {fp.site.name}: setups, page {page + 2} of {n_pages + 1} " + KEY
        fig.text(MARGIN_IN / pw, y, title, fontsize=FONT_PT, va="baseline")
        y -= TOP_LINES * line
        _row(fig, y, list(HEADS), widths, edges, bold=True)
        for r in cells[page * per : (page + 1) * per]:
            y -= line
            _row(fig, y, r, widths, edges)
        if page == n_pages - 1:
            _foot(fig, fp, y - line, line, widths, edges, width_chars)
        pages.append(fig)
    return pages


def _foot(
    fig: Figure, fp: FieldPlan, y: float, line: float, widths: list[int], edges: list[int], width_chars: int
) -> None:
    """The totals row, the sessions and the advice on legs through walls, under the last row."""
    tot: list[Any] = totals(fp)
    _row(fig, y, ["", *[f"{v}" for v in tot[1:]]], widths, edges, bold=True)
    x0 = MARGIN_IN / fig.get_size_inches()[0]
    fig.text(x0, y, str(tot[0]), fontsize=FONT_PT, fontweight="bold", va="baseline")
    sessions = "; ".join(s.label for s in fp.time.sessions)
    extra = textwrap.wrap(advice(fp.crossings), width_chars)
    if fp.spaces:  # across storeys: the stair legs first
        extra = textwrap.wrap(stairs_line(fp), width_chars) + extra
    extra = extra[: FOOT_LINES - 3]
    for k, text in enumerate([_fit(sessions, width_chars), *extra], 1):
        fig.text(x0, y - k * line, text, fontsize=FONT_PT, va="baseline")


def write_pdf(fp: FieldPlan, path: Path | str, plan: Figure | None = None) -> Path:
    """Write field.pdf (see the module text) and return its path; ``plan``: the plan figure drawn for the paper of
    :func:`map_paper` where the caller has it already (None: drawn here)."""
    out = Path(path)
    if plan is None:
        plan = figure(fp, map_paper(fp)[1])  # labels placed for the paper's size
    drop_frozen_layout(plan)  # laid out and frozen: drawn once into the file
    meta = {"Title": f"Field sheet {fp.site.name}", "Creator": f"tls-planner {__version__}", "CreationDate": None}
    with matplotlib.rc_context({"pdf.compression": 0, "pdf.fonttype": 3}), PdfPages(out, metadata=meta) as pdf:
        pdf.savefig(plan)
        for page in _table_pages(fp):
            pdf.savefig(page)
    return out
