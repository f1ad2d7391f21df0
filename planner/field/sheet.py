"""The field sheet's files: ``field.html`` (print-ready: the plan with numbered stations and the route, one
row per setup, totals; :mod:`planner.field.page`), ``field.csv`` (the same rows), ``field.geojson`` (stations
in order, the route line, the targets; frame coordinates in metres), ``field.json`` (order, route, bound, gap,
mode, field time, sessions, targets, links, legs through walls) and ``field.pdf`` (the plan, then the setup
table on A4 pages; :mod:`planner.field.pdf`)."""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Any

from planner import __version__
from planner.core.text import dumps
from planner.field.crossing import advice, closed_parts
from planner.field.figure import figure
from planner.field.page import render_html
from planner.field.pdf import write_pdf
from planner.field.run import FieldPlan
from planner.field.spread import MIN_ANGLE_DEG, MIN_SPREAD_M
from planner.field.tables import HEADER, rows

__all__ = ["HEADER", "figure", "geojson", "render_html", "rows", "to_dict", "write_sheet"]


def to_dict(fp: FieldPlan) -> dict[str, Any]:
    """field.json."""
    o = fp.options
    return {
        "instance": fp.site.name,
        "mode": o.mode,
        "closed": o.closed,
        "start": fp.start_label,
        "start_xy": list(fp.start_xy),
        "order": [fp.stations[k].id for k in fp.order],
        "route_length_m": fp.route_length_m,
        "lower_bound_m": fp.lower_bound_m,
        "bound_method": fp.bound_method,
        "bound_scope": fp.certified.scope if fp.certified else "shortest route",
        "bounds": {m: b for m, b in fp.certified.bounds} if fp.certified else {},
        "gap": fp.gap,
        "nearest_neighbour_m": fp.nearest_neighbour_m,
        "registration_order_honoured": fp.registration_ok,
        "search_capped": fp.capped,
        "legs": [[list(p) for p in leg] for leg in fp.legs],
        "field_time_s": fp.time.total_s,
        "time": fp.time.to_dict(),
        "sessions": fp.time.to_dict()["sessions"],
        "setups": [dict(zip(HEADER, r)) for r in rows(fp)],
        "targets": [
            {
                "id": t.id,
                "kind": t.kind,
                "x": t.x,
                "y": t.y,
                "where": t.where,
                "seen_by": list(t.seen_by),
                "links": [list(p) for p in t.links],
            }
            for t in fp.targets
        ],
        "links": [
            {
                "a": lk.a,
                "b": lk.b,
                "shared_m": lk.shared_m,
                "fraction": lk.fraction,
                "weak": lk.weak,
                "targets": list(lk.targets),
                "target_places": lk.places,
                "apart_m": lk.apart_m,
                "weak_reason": lk.reason,
                "target_spread_m": lk.spread_m,
                "target_min_angle_deg": lk.min_angle_deg,
                "target_geometry_note": lk.spread_note,
            }
            for lk in fp.links
        ],
        "target_geometry": {"min_spread_m": MIN_SPREAD_M, "min_angle_deg": MIN_ANGLE_DEG},
        "legs_crossing_walls": [
            {
                "leg": c.leg,
                "setup": c.setup,
                "from": c.start,
                "to": c.end,
                "length_m": c.length_m,
                "zones": list(c.zones),
                "parts": list(c.parts),
            }
            for c in fp.crossings
        ],
        "wall_crossing": "straight line from setup to setup, through the walls it meets",
        "no_opening_between": list(closed_parts(fp.crossings)),
        "walls_advice": advice(fp.crossings),
        "instrument_height_m": fp.instrument_height_m,
        "solve_s": fp.solve_s,
        "version": __version__,
    }


def geojson(fp: FieldPlan) -> dict[str, Any]:
    """Stations in order (Points), the route (LineString) and targets, in the frame's metres."""
    feats: list[dict[str, Any]] = []
    for n, k in enumerate(fp.order, 1):
        s = fp.stations[k]
        feats.append(
            {
                "type": "Feature",
                "geometry": {"type": "Point", "coordinates": [s.x, s.y]},
                "properties": {
                    "role": "station",
                    "number": n,
                    "id": s.id,
                    "zone": s.zone,
                    "side": s.side.value,
                    "targets": fp.targets_of(s.id),
                },
            }
        )
    line: list[list[float]] = []
    for leg in fp.legs:
        for p in leg:
            if not line or line[-1] != list(p):
                line.append(list(p))
    feats.append(
        {
            "type": "Feature",
            "geometry": {"type": "LineString", "coordinates": line},
            "properties": {"role": "route", "length_m": fp.route_length_m, "mode": fp.options.mode},
        }
    )
    for t in fp.targets:
        feats.append(
            {
                "type": "Feature",
                "geometry": {"type": "Point", "coordinates": [t.x, t.y]},
                "properties": {"role": "target", "id": t.id, "kind": t.kind, "seen_by": list(t.seen_by)},
            }
        )
    return {
        "type": "FeatureCollection",
        "name": f"{fp.site.name} field sheet",
        "frame": fp.space.frame,
        "features": feats,
    }


def write_sheet(fp: FieldPlan, folder: Path | str) -> list[Path]:
    """Write field.html, field.csv, field.geojson, field.json and field.pdf into ``folder``; return their
    paths."""
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    paths = [out / f"field.{ext}" for ext in ("html", "csv", "geojson", "json", "pdf")]
    paths[0].write_text(render_html(fp))
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(HEADER)
    w.writerows(rows(fp))
    paths[1].write_text(buf.getvalue())
    paths[2].write_text(dumps(geojson(fp)))
    paths[3].write_text(dumps(to_dict(fp)))
    write_pdf(fp, paths[4])
    return paths
