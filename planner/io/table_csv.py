"""Reader of the table CSV: one row per side, the columns of tables 3.1 and 4.3.

Columns (exactly these, any order)::

    zone,scan_side,index,side_length_m,wall_height_m,interior_angle_deg,vertex_height_m

Row ``index`` i gives side i and the interior angle and height of vertex i, the vertex at the START of side i. The
reader checks form (columns, numbers, consecutive indices); value ranges are checked after corrections are applied.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from planner.core.errors import InputError
from planner.core.fileio import read_text, to_float
from planner.site.traverse import SCAN_SIDES, TableRow, ZoneTable

COLUMNS = ("zone", "scan_side", "index", "side_length_m", "wall_height_m", "interior_angle_deg", "vertex_height_m")
NUMBER_COLUMNS = COLUMNS[3:]


def read_table_csv(path: Path | str) -> list[ZoneTable]:
    """Zones of a table CSV, in order of first appearance."""
    path = Path(path)
    name = str(path)
    text = read_text(path)
    reader = _rows(csv.reader(io.StringIO(text)), name)
    header = [h.strip() for h in next(reader)]
    missing = [c for c in COLUMNS if c not in header]
    if missing:
        raise InputError(f"missing column (need {','.join(COLUMNS)})", file=name, row="line 1", field=missing[0])
    unknown = [h for h in header if h not in COLUMNS]
    if unknown:
        raise InputError("unknown column", file=name, row="line 1", field=unknown[0])
    if len(set(header)) != len(header):
        raise InputError("duplicate column", file=name, row="line 1", field=header[0])
    zones: dict[str, tuple[str, list[TableRow]]] = {}
    for line_no, cells in enumerate(reader, start=2):
        if not any(c.strip() for c in cells):
            continue
        if len(cells) != len(header):
            raise InputError(
                f"{len(cells)} fields, the header has {len(header)} (decimal comma?)", file=name, row=f"line {line_no}"
            )
        rec = dict(zip(header, (c.strip() for c in cells)))
        zone, side = rec["zone"], rec["scan_side"]
        where = dict(file=name, zone=zone or None, row=f"line {line_no}")
        if not zone:
            raise InputError("missing zone id", **where, field="zone")
        if side not in SCAN_SIDES:
            raise InputError(f"must be one of {', '.join(SCAN_SIDES)}", **where, field="scan_side", value=side)
        try:
            index = int(rec["index"])
        except ValueError:
            raise InputError("must be a whole number", **where, field="index", value=rec["index"]) from None
        nums = {c: to_float(rec[c], field=c, text=True, **where) for c in NUMBER_COLUMNS}
        row = TableRow(index=index, line=line_no, **nums)
        if zone in zones and zones[zone][0] != side:
            first = zones[zone][0]
            raise InputError(
                f"scan side differs from the zone's first row ({first})", **where, field="scan_side", value=side
            )
        zones.setdefault(zone, (side, []))[1].append(row)
    if not zones:
        raise InputError("no data rows", file=name)
    _ends_with_line_end(text, name)
    return [_zone_table(z, side, rows, name) for z, (side, rows) in zones.items()]


def _ends_with_line_end(text: str, file: str) -> None:
    """Refuse a file whose last row has no line end: a row cut short reads as a row of shorter numbers (``3.05`` cut
    to ``3.0``), so a table that does not end with a newline cannot be told from one cut mid-row."""
    if not text.rstrip(" \t").endswith(("\n", "\r")):
        last = text.rstrip().rsplit("\n", 1)[-1]
        raise InputError(
            "the last row has no line end: the file may be cut short mid-row; end the file with a newline",
            file=file,
            row=f"line {text.count(chr(10)) + 1}",
            field="text",
            value=last if len(last) <= 40 else last[:37] + "...",
        )


def _rows(reader: Any, file: str) -> Iterator[list[str]]:
    """The rows of a ``csv.reader`` (``Any``: its type is private to ``_csv``); a row it cannot read, e.g. a cell over
    its 131072-character limit, is an InputError naming the line."""
    while True:
        try:
            row = next(reader)
        except StopIteration:
            return
        except csv.Error as exc:
            raise InputError(f"not a readable CSV row ({exc})", file=file, row=f"line {reader.line_num}") from None
        yield row


def _zone_table(zone: str, side: str, rows: list[TableRow], file: str) -> ZoneTable:
    rows = sorted(rows, key=lambda r: r.index)
    for expected, r in enumerate(rows, start=1):
        if r.index != expected:
            where: dict[str, Any] = dict(file=file, zone=zone, row=f"line {r.line}", field="index", value=r.index)
            raise InputError(f"indices must run 1..{len(rows)} without gaps or repeats", **where)
    return ZoneTable(zone=zone, scan_side=side, rows=tuple(rows), file=file)
