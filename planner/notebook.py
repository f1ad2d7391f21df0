"""Notebook display: every result's ``_repr_html_`` is its ``summary()`` in a titled block."""

from __future__ import annotations

import html
from typing import Protocol


class HasSummary(Protocol):
    def summary(self) -> str: ...


def summary_html(obj: HasSummary, title: str) -> str:
    """``<div><b>title</b><pre>summary</pre></div>``, escaped."""
    return (f'<div class="tls-planner"><b>{html.escape(title)}</b>'
            f'<pre style="font-size:90%">{html.escape(obj.summary())}</pre></div>')
