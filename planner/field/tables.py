"""The field sheet's setup table, shared by field.html, field.csv, field.json and field.pdf: one row per setup in
visiting order (:data:`HEADER`, :func:`rows`) and the totals line (:func:`totals`)."""

from __future__ import annotations

from typing import Any

from planner.field.run import FieldPlan

HEADER = (
    "no.",
    "station",
    "x m",
    "y m",
    "zone",
    "side",
    "instrument height m",
    "scan setting",
    "walk m",
    "minutes",
    "targets seen",
    "session",
)


def rows(fp: FieldPlan) -> list[list[Any]]:
    """One row per setup in visiting order (the columns of :data:`HEADER`)."""
    out = []
    for setup, k in zip(fp.time.setups, fp.order):
        s = fp.stations[k]
        out.append(
            [
                setup.number,
                s.id,
                round(s.x, 3),
                round(s.y, 3),
                s.zone,
                s.side.value,
                fp.instrument_height_m,
                setup.setting or fp.time.setting,
                round(setup.walk_m, 1),
                round(setup.total_s / 60.0, 1),
                " ".join(fp.targets_of(s.id)),
                setup.session,
            ]
        )
    return out


def totals(fp: FieldPlan) -> list[Any]:
    """The totals under the table, in the columns of :data:`HEADER` (blank where nothing adds up)."""
    t = fp.time
    return [
        f"total: {len(fp.order)} setups",
        *[""] * 7,
        round(fp.route_length_m, 1),
        round(t.total_s / 60.0, 1),
        f"{len(fp.targets)} targets",
        len(t.sessions),
    ]
