"""Reading input files safely: size limit, encoding, JSON that the parser chokes on or reads loosely (keys
given twice), numbers that must be finite."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import Any

from planner.core.errors import InputError

#: Instance files larger than this are refused before they are read (64 MiB).
MAX_INPUT_BYTES = 64 * 1024 * 1024


def check_size(path: Path) -> None:
    """Refuse a file that cannot be read or is larger than ``MAX_INPUT_BYTES``, before it is read."""
    try:
        size = path.stat().st_size
    except OSError as exc:
        raise InputError(f"cannot read file: {exc.strerror}", file=str(path)) from None
    if size > MAX_INPUT_BYTES:
        raise InputError(f"file too large ({size:,} bytes; limit {MAX_INPUT_BYTES:,})", file=str(path), value=size)


def read_text(path: Path) -> str:
    """The file's text (UTF-8, BOM allowed); refuses missing, huge, binary or empty files."""
    name = str(path)
    check_size(path)
    if not path.is_file():
        raise InputError("not a file", file=name)
    try:
        text = path.read_bytes().decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"not UTF-8 text (byte {exc.start})", file=name) from None
    except OSError as exc:  # unreadable (permissions, a device that fails)
        raise InputError(f"cannot read file: {exc.strerror or exc}", file=name) from None
    if not text.strip():
        raise InputError("empty file", file=name)
    return text


def read_json(path: Path | str) -> Any:
    """The parsed JSON of a file read with :func:`read_text`. ``json`` builds plain data only: nothing in the file is
    evaluated. Refused as an InputError naming the file and the line (or the key): invalid JSON, nesting deeper than the
    parser can follow, an integer beyond the float range (``json`` would stop at 4300 digits or hand on a number no
    float holds), a key given twice in one object (``json`` keeps the last silently), and text that is not valid Unicode
    (a lone surrogate escape such as ``\\ud800``, which no output can print)."""
    name = str(path)
    text = read_text(Path(path))
    try:
        data = json.loads(text, parse_int=_integer, object_pairs_hook=lambda pairs: _object(pairs, name))
    except json.JSONDecodeError as exc:
        raise InputError(f"invalid JSON: {exc.msg}", file=name, row=f"line {exc.lineno} column {exc.colno}") from None
    except RecursionError:
        raise InputError(
            f"invalid JSON: nested too deeply (over {MAX_JSON_DEPTH} levels of [ and {{)",
            file=name,
            row=_line_column(text, _too_deep_at(text)),
        ) from None
    except _OutOfRange as exc:
        raise InputError(
            "invalid JSON: number out of range (beyond +-1.8e308)",
            file=name,
            field="number",
            row=_line_column(text, _number_at(text, exc.literal)),
            value=_shortened(exc.literal),
        ) from None
    if re.search(_SURROGATE_ESCAPE, text):  # rare: only then is the parsed data searched
        _refuse_surrogates(data, name)
    return data


#: nesting reported as too deep (instances nest about 6 levels; Python's parser gives up near 1000)
MAX_JSON_DEPTH = 100

#: an escape of a UTF-16 surrogate, paired or not (``\\ud83d\\ude00`` is one emoji, ``\\ud800`` alone no character)
_SURROGATE_ESCAPE = r"\\u[dD][89a-fA-F][0-9a-fA-F]{2}"
_LONE_SURROGATE = "[\ud800-\udfff]"
#: a JSON string or a bracket, for counting the nesting outside strings (the loop is unrolled: no backtracking)
_TOKEN = r'"[^"\\]*(?:\\.[^"\\]*)*"|[][{}]'


class _OutOfRange(Exception):
    """An integer literal beyond the float range, carried out of ``json.loads`` to be located."""

    def __init__(self, literal: str) -> None:
        super().__init__(literal)
        self.literal = literal


def _integer(literal: str) -> int:
    """``parse_int`` of :func:`read_json`: the integer, if a float can hold it (at most 309 digits)."""
    if len(literal) > 400:  # int() itself refuses over 4300 digits
        raise _OutOfRange(literal)
    value = int(literal)
    if len(literal) > 300:
        try:
            float(value)
        except OverflowError:
            raise _OutOfRange(literal) from None
    return value


def _object(pairs: list[tuple[str, Any]], file: str) -> dict[str, Any]:
    """``object_pairs_hook`` of :func:`read_json`: a dict, refusing a key given twice with both its values."""
    data = dict(pairs)
    if len(data) == len(pairs):
        return data
    seen: dict[str, Any] = {}
    for key, value in pairs:
        if key in seen:
            raise InputError(
                f"key given twice in one object ({_brief(seen[key])} and {_brief(value)}); give it once",
                file=file,
                field=_printable(key),
            )
        seen[key] = value
    return data


def _brief(value: Any) -> str:
    """A value as JSON text (ASCII), cut to 40 characters."""
    text = json.dumps(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _shortened(text: str, unit: str = "digits") -> str:
    """Up to 20 characters of a long number (or text), with its length in digits (or characters)."""
    return text if len(text) <= 20 else f"{text[:12]}... ({len(text.lstrip('-') if unit == 'digits' else text)} {unit})"


def _line_column(text: str, pos: int | None) -> str | None:
    """``line L column C`` (1-based, as ``json`` counts them) of a character offset."""
    if pos is None:
        return None
    return f"line {text.count(chr(10), 0, pos) + 1} column {pos - text.rfind(chr(10), 0, pos)}"


def _too_deep_at(text: str) -> int | None:
    """Offset of the first bracket outside strings that opens level ``MAX_JSON_DEPTH + 1``."""
    depth = 0
    for m in re.finditer(_TOKEN, text):
        token = m.group()
        if token in "[{":
            depth += 1
            if depth > MAX_JSON_DEPTH:
                return m.start()
        elif token in "]}":
            depth -= 1
    return None


def _number_at(text: str, literal: str) -> int | None:
    """Offset of the first number token ``literal`` in the text (not part of a longer number)."""
    m = re.search(r"(?<![0-9.eE+-])" + re.escape(literal) + r"(?![0-9.eE])", text)
    return m.start() if m else None


def _printable(text: str) -> str:
    """``text`` with any lone surrogate written as its escape (``\\ud800``), so that it can be printed."""
    return text.encode("utf-8", "backslashreplace").decode("utf-8")


def _refuse_surrogates(data: Any, file: str) -> None:
    """Refuse the first text (value or key) holding a lone surrogate, naming where it is (e.g. ``zones[1].id``)."""
    stack: list[tuple[Any, str]] = [(data, "")]
    while stack:
        item, where = stack.pop()
        texts: list[tuple[str, str]] = []
        if isinstance(item, str):
            texts = [(item, where or "text")]
        elif isinstance(item, dict):
            texts = [(key, f"key in {where}" if where else "key") for key in item]
            stack += [(v, f"{where}.{k}" if where else k) for k, v in reversed(item.items())]
        elif isinstance(item, list):
            stack += [(v, f"{where}[{k}]") for k, v in reversed(list(enumerate(item, 1)))]
        bad = next(((t, w) for t, w in texts if re.search(_LONE_SURROGATE, t)), None)
        if bad is not None:
            raise InputError(
                "not valid Unicode (a lone surrogate escape: half of a character pair)",
                file=file,
                field=bad[1],
                value=_shortened(bad[0], "characters"),
            )


def to_float(
    raw: Any,
    *,
    field: str,
    file: str | None = None,
    zone: str | None = None,
    row: int | str | None = None,
    text: bool = False,
) -> float:
    """A finite float from a JSON number, or with ``text=True`` from a CSV cell (plain decimal text: no
    Python digit grouping such as ``6_0``); NaN, inf, booleans, and text in JSON are refused."""
    where: dict[str, Any] = {"file": file, "zone": zone, "row": row, "field": field}
    if isinstance(raw, bool):
        raise InputError("must be a number", value=raw, **where)
    if isinstance(raw, str):
        if not text:  # JSON has numbers: "9" is a typo or a unit mix-up, not a number to guess at
            raise InputError("must be a number, not text", value=raw, **where)
        cell = raw.strip()
        if not cell:
            raise InputError("missing value", **where)
        try:
            if "_" in cell:
                raise ValueError(cell)
            value = float(cell)
        except ValueError:
            raise InputError("not a number", value=raw, **where) from None
    elif isinstance(raw, (int, float)):
        try:
            value = float(raw)
        except OverflowError:  # an integer no float holds (from a caller; read_json refuses it in the file)
            raise InputError("number out of range (beyond +-1.8e308)", **where) from None
    else:
        raise InputError("must be a number", value=type(raw).__name__ if raw is not None else "null", **where)
    if not math.isfinite(value):
        raise InputError("must be finite", value=raw, **where)
    return value


def to_int(
    raw: Any, *, field: str, file: str | None = None, zone: str | None = None, row: int | str | None = None
) -> int:
    """A whole number from JSON: an integer, or a number with no fraction (``2.0``, as a JSON writer may put
    it); 1.9 is refused (it was read as 1), and so are booleans and text."""
    if isinstance(raw, float) and raw.is_integer() and abs(raw) <= 2.0**53:
        return int(raw)
    if isinstance(raw, bool) or not isinstance(raw, int):
        shown = raw if isinstance(raw, (int, float, str)) else type(raw).__name__ if raw is not None else "null"
        raise InputError("must be a whole number", file=file, zone=zone, row=row, field=field, value=shown)
    return raw


def known_keys(data: dict[str, Any], known: set[str], **where: Any) -> None:
    """Refuse a key outside ``known`` (a typo must not drop a value silently), naming it and its value."""
    unknown = sorted(set(data) - known)
    if unknown:
        raise InputError(
            f"unknown key (known: {', '.join(sorted(known))})", field=unknown[0], value=data[unknown[0]], **where
        )
