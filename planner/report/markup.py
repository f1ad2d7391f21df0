"""The HTML pieces every section of report.html writes: escaped text, tables and embedded images."""

from __future__ import annotations

import base64
import html
from collections.abc import Iterable, Mapping, Sequence
from typing import Any


def esc(v: Any) -> str:
    """``v`` as HTML text (quotes escaped too: safe in attributes)."""
    return html.escape(str(v))


def scroll(inner: str) -> str:
    """``inner`` in a box that scrolls sideways on its own where it is wider than the screen (a phone), so that the
    page itself never does."""
    return f'<div class="scroll">{inner}</div>'


def table(
    header: Sequence[str],
    rows: Iterable[Sequence[Any]],
    left: int = 1,
    row_ids: Sequence[str] | None = None,
    row_data: Sequence[Mapping[str, Any]] | None = None,
) -> str:
    """An HTML table in a sideways-scrolling box (:func:`scroll`); the first ``left`` columns are left-aligned text,
    the cells are HTML; ``row_ids``: an HTML id per row (the site map links to the station table's rows);
    ``row_data``: per row its ``data-*`` attributes (name without ``data-``), machine-readable."""
    th = "".join(f'<th class="{"l" if k < left else ""}">{esc(h)}</th>' for k, h in enumerate(header))

    def attrs(n: int) -> str:
        out = f' id="{esc(row_ids[n])}"' if row_ids else ""
        return out + "".join(f' data-{k}="{esc(v)}"' for k, v in (row_data[n] if row_data else {}).items())

    body = "".join(
        f"<tr{attrs(n)}>"
        + "".join(f'<td class="{"l" if k < left else ""}">{c}</td>' for k, c in enumerate(r))
        + "</tr>"
        for n, r in enumerate(rows)
    )
    return scroll(f"<table><tr>{th}</tr>{body}</table>")


def image(png: bytes, alt: str) -> str:
    """A PNG embedded in the page as a figure, ``alt`` its caption too (it shrinks to the screen's width)."""
    src = f"data:image/png;base64,{base64.b64encode(png).decode()}"
    return f'<figure><img alt="{esc(alt)}" src="{src}"><figcaption>{esc(alt)}</figcaption></figure>'
