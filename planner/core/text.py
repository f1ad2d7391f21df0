"""Results as text for front ends: strict JSON (plan.json, network.json, field.json), notebook HTML, and the building
blocks of the terminal summaries (aligned tables, ``key value`` lines, folded notes).

**JSON.** Python's ``json`` writes ``NaN`` and ``Infinity`` for non-finite floats, which JavaScript's ``JSON.parse`` and
strict parsers refuse. Here a non-finite float becomes ``null``; where that hides a meaning (a piece whose stations are
not tied to control has an infinite error), the writer of the data states it in a field of its own (``untied``).

**Notebooks.** Every result's ``_repr_html_`` is its ``summary()`` in a titled block (:func:`summary_html`).

**Terminal.** A summary is read by a person, so it shows no Python reprs (no ``{'key': ...}``, ``[...]``, ``None``,
``True``): :func:`table` aligns rows in columns as wide as their content, numbers right-aligned; :func:`key_values`
prints ``key  value`` lines; :func:`yes_no` and :func:`or_none` give the words; :func:`fold_alike` folds notes that
differ only in the names they mention into one line with a count.
"""

from __future__ import annotations

import html
import json
import math
import re
from collections.abc import Iterable, Sequence
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


#: a cell that reads as a number (with thousands separators, a sign, a ratio ``a/b`` or a unit): right-aligned
_NUMBER = re.compile(r"^[-+]?(?=[\d.])[\d,]*\.?\d*(/[\d,]*\.?\d*)?( ?(%|m|mm|s|deg))?$")
#: a word of a note: letters, digits and the joiners of names (``Z4-in-G4``, ``CP4.1``), no trailing punctuation
_WORD = re.compile(r"\w(?:[\w.\-/]*\w)?")


def yes_no(flag: bool) -> str:
    """``yes`` or ``no``: a truth value as a person writes it."""
    return "yes" if flag else "no"


def or_none(value: Any, fmt: str = "") -> str:
    """``value`` formatted with ``fmt``, or the word ``none`` where it is None."""
    return "none" if value is None else format(value, fmt)


def _cell(value: Any) -> str:
    if value is None:
        return "none"
    if isinstance(value, bool):
        return yes_no(value)
    if isinstance(value, int):
        return f"{value:,}"
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def _numeric(text: str) -> bool:
    return bool(_NUMBER.match(text)) and any(c.isdigit() for c in text)


def table(
    header: Sequence[str], rows: Iterable[Sequence[Any]], *, indent: str = "  ", right: Sequence[bool] | None = None
) -> list[str]:
    """The header line and one line per row, each column as wide as its widest cell, two spaces between columns,
    ``indent`` before every line, trailing spaces removed. Cells: None prints as ``none``, a bool as ``yes``/``no``, an
    int with thousands separators, a float by ``:g`` (format floats beforehand to fix their decimals). ``right``: which
    columns are right-aligned; by default those whose every non-empty cell reads as a number (``1,058``, ``3835/3835``,
    ``4.06 mm``)."""
    body = [[_cell(v) for v in row] for row in rows]
    n = len(header)
    if any(len(row) != n for row in body):
        raise ValueError(f"every row needs {n} cells")
    if right is None:
        right = [bool(col) and all(_numeric(c) for c in col if c) for col in ([r[k] for r in body] for k in range(n))]
    widths = [max([len(header[k])] + [len(r[k]) for r in body]) for k in range(n)]

    def line(cells: Sequence[str]) -> str:
        parts = [c.rjust(w) if r else c.ljust(w) for c, w, r in zip(cells, widths, right)]
        return (indent + "  ".join(parts)).rstrip()

    return [line(header)] + [line(r) for r in body]


def key_values(pairs: Iterable[tuple[str, Any]], *, indent: str = "  ") -> list[str]:
    """``key  value`` lines, the values starting in one column (None as ``none``, a bool as ``yes``/``no``)."""
    items = [(k, _cell(v)) for k, v in pairs]
    width = max((len(k) for k, _ in items), default=0)
    return [f"{indent}{k.ljust(width)}  {v}".rstrip() for k, v in items]


def natural_key(text: str) -> tuple[Any, ...]:
    """Sort key that orders the numbers inside names by value: Z2 before Z10, CP1.2 before CP1.10."""
    return tuple((0, int(t), "") if t.isdigit() else (1, 0, t) for t in re.split(r"(\d+)", text) if t)


def _names(line: str, names: frozenset[str]) -> list[tuple[int, int, str]]:
    """The names a note mentions, with their spans: words that hold both a letter and a digit (``Z4``,
    ``CP4.1``, ``outline-out-V18``) or are among ``names``. Bare numbers are measurements, never names."""
    out = []
    for m in _WORD.finditer(line):
        w = m.group()
        if w in names or (any(c.isdigit() for c in w) and any(c.isalpha() for c in w)):
            out.append((m.start(), m.end(), w))
    return out


def fold_alike(lines: Iterable[str], names: Iterable[str] = (), *, shown: int = 6) -> list[str]:
    """Notes that differ only in the names they mention, folded into one line with a count.

    Two notes are alike when they read the same once every name in them is blanked out (a name: a word with
    both letters and digits, such as ``Z4``, ``CP4.1`` or ``Z8-in-C``, or one of ``names``, such as zone names
    without digits). Numbers alone are not names, so notes that differ in a measured value stay apart. Each
    group of alike notes prints once, at the place of its first note: the note whose name comes first in
    natural order, then ``(same for N: A, B, ..., Z)`` naming the first name that differs between them
    (``shown`` names at most, the first ones and the last); identical notes print once with ``(N times)``.
    ``names``: further words to treat as names (zone ids without digits, station ids).
    """
    known = frozenset(names)
    groups: dict[str, list[tuple[str, list[str]]]] = {}
    for line in lines:
        spans = _names(line, known)
        key, at = [], 0
        for start, end, _ in spans:
            key += [line[at:start], "\0"]
            at = end
        key.append(line[at:])
        groups.setdefault("".join(key), []).append((line, [w for _, _, w in spans]))
    out = []
    for members in groups.values():
        if len(members) == 1:
            out.append(members[0][0])
            continue
        varying = next((k for k in range(len(members[0][1])) if len({m[1][k] for m in members}) > 1), None)
        if varying is None:
            out.append(f"{members[0][0]} ({len(members)} times)")
            continue
        labels = sorted({m[1][varying] for m in members}, key=natural_key)
        first = min(members, key=lambda m: natural_key(m[1][varying]))[0]
        listed = labels if len(labels) <= shown else labels[: shown - 1] + ["...", labels[-1]]
        out.append(f"{first} (same for {len(members)}: {', '.join(listed)})")
    return out
