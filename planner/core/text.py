"""Results as text for front ends: strict JSON (plan.json, network.json, field.json) and notebook HTML.

**JSON.** Python's ``json`` writes ``NaN`` and ``Infinity`` for non-finite floats, which JavaScript's
``JSON.parse`` and strict parsers refuse. Here a non-finite float becomes ``null``; where that hides a
meaning (a piece whose stations are not tied to control has an infinite error), the writer of the
data states it in a field of its own (``untied``).

**Notebooks.** Every result's ``_repr_html_`` is its ``summary()`` in a titled block (:func:`summary_html`).
"""

from __future__ import annotations

import html
import json
import math
from typing import Any, Protocol


def finite_or_none(value: float) -> float | None:
    """``value``, or ``None`` when it is NaN or infinite."""
    return value if math.isfinite(value) else None


def _plain(o: Any) -> Any:
    """``o`` as plain JSON data: numpy scalars and arrays to Python, sets sorted, non-finite floats to None."""
    import numpy as np

    if isinstance(o, dict):
        return {k: _plain(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_plain(v) for v in o]
    if isinstance(o, (set, frozenset)):
        return [_plain(v) for v in sorted(o)]
    if isinstance(o, np.ndarray):
        return _plain(o.tolist())
    if isinstance(o, (np.integer, np.floating, np.bool_)):
        return _plain(o.item())
    if isinstance(o, float):
        return finite_or_none(o)
    return o


def dumps(data: Any, indent: int | None = 2) -> str:
    """Strict JSON text of ``data`` (see the module docstring), with a final newline."""
    return json.dumps(_plain(data), indent=indent, allow_nan=False) + "\n"


class HasSummary(Protocol):
    def summary(self) -> str: ...


def summary_html(obj: HasSummary, title: str) -> str:
    """``<div><b>title</b><pre>summary</pre></div>``, escaped."""
    return (
        f'<div class="tls-planner"><b>{html.escape(title)}</b>'
        f'<pre style="font-size:90%">{html.escape(obj.summary())}</pre></div>'
    )
