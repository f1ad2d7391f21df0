"""The HTML pieces every section of report.html writes: escaped text, tables and embedded images."""

from __future__ import annotations

import base64
import html
from collections.abc import Iterable, Sequence
from typing import Any


def esc(v: Any) -> str:
    return html.escape(str(v))


def table(
    header: Sequence[str], rows: Iterable[Sequence[Any]], left: int = 1, row_ids: Sequence[str] | None = None
) -> str:
    """An HTML table; the first ``left`` columns are left-aligned text, the cells are HTML; ``row_ids``: an HTML id per
    row (the site map links to the station table's rows)."""
    th = "".join(f'<th class="{"l" if k < left else ""}">{esc(h)}</th>' for k, h in enumerate(header))
    body = "".join(
        (f'<tr id="{esc(row_ids[n])}">' if row_ids else "<tr>")
        + "".join(f'<td class="{"l" if k < left else ""}">{c}</td>' for k, c in enumerate(r))
        + "</tr>"
        for n, r in enumerate(rows)
    )
    return f"<table><tr>{th}</tr>{body}</table>"


def image(png: bytes, alt: str) -> str:
    """A PNG embedded in the page as a figure, ``alt`` its caption too."""
    src = f"data:image/png;base64,{base64.b64encode(png).decode()}"
    return f'<figure><img alt="{esc(alt)}" src="{src}"><figcaption>{esc(alt)}</figcaption></figure>'
