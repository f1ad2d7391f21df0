"""Reading input files safely: size limit, encoding, numbers that must be finite."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from planner.errors import InputError

#: Instance files larger than this are refused before they are read (64 MiB).
MAX_INPUT_BYTES = 64 * 1024 * 1024


def read_text(path: Path) -> str:
    """The file's text (UTF-8, BOM allowed); refuses missing, huge, binary or empty files."""
    name = str(path)
    try:
        size = path.stat().st_size
    except OSError as exc:
        raise InputError(f"cannot read file: {exc.strerror}", file=name) from None
    if not path.is_file():
        raise InputError("not a file", file=name)
    if size > MAX_INPUT_BYTES:
        raise InputError(f"file too large ({size:,} bytes; limit {MAX_INPUT_BYTES:,})", file=name, value=size)
    try:
        text = path.read_bytes().decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"not UTF-8 text (byte {exc.start})", file=name) from None
    if not text.strip():
        raise InputError("empty file", file=name)
    return text


def read_json(path: Path | str) -> Any:
    """The parsed JSON of a file read with :func:`read_text`; invalid JSON is an InputError naming
    the line and column. ``json`` builds plain data only: nothing in the file is evaluated."""
    try:
        return json.loads(read_text(Path(path)))
    except json.JSONDecodeError as exc:
        raise InputError(f"invalid JSON: {exc.msg}", file=str(path), row=f"line {exc.lineno} column {exc.colno}") from None


def to_float(raw: Any, *, field: str, file: str | None = None, zone: str | None = None,
             row: int | str | None = None, text: bool = False) -> float:
    """A finite float from a JSON number, or with ``text=True`` from a CSV cell (plain decimal text: no
    Python digit grouping such as ``6_0``); NaN, inf, booleans, and text in JSON are refused."""
    if isinstance(raw, bool):
        raise InputError("must be a number", file=file, zone=zone, row=row, field=field, value=raw)
    if isinstance(raw, str):
        if not text:  # JSON has numbers: "9" is a typo or a unit mix-up, not a number to guess at
            raise InputError("must be a number, not text", file=file, zone=zone, row=row, field=field, value=raw)
        cell = raw.strip()
        if not cell:
            raise InputError("missing value", file=file, zone=zone, row=row, field=field)
        try:
            if "_" in cell:
                raise ValueError(cell)
            value = float(cell)
        except ValueError:
            raise InputError("not a number", file=file, zone=zone, row=row, field=field, value=raw) from None
    elif isinstance(raw, (int, float)):
        value = float(raw)
    else:
        raise InputError("must be a number", file=file, zone=zone, row=row, field=field,
                         value=type(raw).__name__ if raw is not None else "null")
    if not math.isfinite(value):
        raise InputError("must be finite", file=file, zone=zone, row=row, field=field, value=raw)
    return value


def known_keys(data: dict[str, Any], known: set[str], **where: Any) -> None:
    """Refuse a key outside ``known`` (a typo must not drop a value silently), naming it and its value."""
    unknown = sorted(set(data) - known)
    if unknown:
        raise InputError(f"unknown key (known: {', '.join(sorted(known))})", field=unknown[0], value=data[unknown[0]],
                         **where)
