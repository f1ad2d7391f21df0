"""From printed zone tables to zones: corrections first, then range checks, then closure."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import replace
from typing import Any

from planner.core.errors import InputError
from planner.site.model import Correction, ScanSide, Zone
from planner.site.params import ClosureTolerance
from planner.site.traverse import AcceptedMisclosure, ZoneTable, reconstruct

VERTEX_FIELDS = ("interior_angle_deg", "vertex_height_m")
SIDE_FIELDS = ("side_length_m", "wall_height_m")


def apply_corrections(table: ZoneTable, corrections: Iterable[Correction], file: str | None) -> ZoneTable:
    """The table with each correction's value put in place of the printed one.

    A correction must name an existing row and a field of the right kind, and its ``printed`` value must be what the
    table holds: a correction is a record of a change to printed data, never a blind overwrite.
    """
    rows = list(table.rows)
    for c in corrections:
        where: dict[str, Any] = dict(file=file, zone=c.zone, row=c.row, field=c.field)
        if not 1 <= c.row <= len(rows):
            raise InputError(f"correction names {c.target}, the zone has {len(rows)} rows", **where)
        old = rows[c.row - 1]
        found = getattr(old, c.field)
        if abs(found - c.printed) > 1e-9 * max(1.0, abs(found)):
            raise InputError(
                f"correction says printed {c.printed:g} but the table holds {found:g}", **where, value=c.printed
            )
        rows[c.row - 1] = replace(old, **{c.field: c.corrected})  # type: ignore[arg-type]
    return replace(table, rows=tuple(rows))


def zone_from_table(
    table: ZoneTable,
    tolerance: ClosureTolerance,
    corrections: Iterable[Correction] = (),
    accepted: AcceptedMisclosure | None = None,
) -> Zone:
    """A zone in its own table frame, closed and adjusted (see :func:`reconstruct`)."""
    file = table.file
    table = apply_corrections(table, corrections, file)
    for r in table.rows:
        r.check_ranges(table.zone, file)
    vertices, closure = reconstruct(table, tolerance, accepted)
    try:
        return Zone(
            id=table.zone,
            scan_side=ScanSide(table.scan_side),
            vertices=tuple((float(x), float(y)) for x, y in vertices),
            vertex_heights_m=tuple(r.vertex_height_m for r in table.rows),
            printed_wall_heights_m=tuple(r.wall_height_m for r in table.rows),
            frame=table.zone,
            closure=closure,
        )
    except InputError as exc:
        raise (exc.located(file) if file else exc) from None
