"""The field sheet's files: ``field.html`` (print-ready: the interactive site map, the plan with numbered stations and
the route, one row per setup, totals; :mod:`planner.field.page`), ``field.csv`` (the same rows), ``field.geojson``
(stations in order, the route line, the targets; frame coordinates in metres), ``field.json`` (order, route, bound, gap,
mode, field time, sessions, targets, links, legs through walls; :mod:`planner.field.record`) and ``field.pdf`` (the
plan, then the setup table on A4 pages; :mod:`planner.field.pdf`)."""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Any

from planner.core.text import dumps
from planner.field.figure import figure
from planner.field.page import render_html
from planner.field.record import HEADER, rows, to_dict
from planner.field.run import FieldPlan
from planner.field.storeys import climbs
from planner.figures.base import png_bytes

__all__ = ["HEADER", "figure", "geojson", "render_html", "rows", "to_dict", "write_sheet"]


def _feature(geometry: str, coordinates: list, /, **properties: Any) -> dict[str, Any]:
    return {"type": "Feature", "geometry": {"type": geometry, "coordinates": coordinates}, "properties": properties}


def geojson(fp: FieldPlan) -> dict[str, Any]:
    """Stations in order (Points), the route (LineString) and targets, in the frame's metres."""
    feats: list[dict[str, Any]] = []
    numbering = fp.numbering
    for k in fp.order:
        s = fp.stations[k]
        props = {"role": "station", "number": numbering.number(s.id), "label": numbering.label(s.id), "id": s.id}
        props |= {"zone": s.zone, "side": s.side.value}
        props |= {"targets": fp.targets_of(s.id)} | ({"frame": s.frame} if fp.spaces else {})
        feats.append(_feature("Point", [s.x, s.y], **props))
    if fp.spaces:
        feats += _storey_route(fp)
    else:
        line: list[list[float]] = []
        for leg in fp.legs:
            for p in leg:
                if not line or line[-1] != list(p):
                    line.append(list(p))
        feats.append(_feature("LineString", line, role="route", length_m=fp.route_length_m, mode=fp.options.mode))
    for t in fp.targets:
        feats.append(_feature("Point", [t.x, t.y], role="target", id=t.id, kind=t.kind, seen_by=list(t.seen_by)))
    return {
        "type": "FeatureCollection",
        "name": f"{fp.site.name} field sheet",
        "frame": fp.space.frame,
        "features": feats,
    } | ({"frames": [sp.frame for sp in fp.spaces]} if fp.spaces else {})


def _storey_route(fp: FieldPlan) -> list[dict[str, Any]]:
    """Across storeys: the route as one LineString per stretch walked in one frame (property ``frame``, in walking
    order, ``part`` numbering them) and one per stair leg (role ``stair``, from the foot to the head's plan point)."""
    runs: list[tuple[str, list[list[float]]]] = []
    stairs: list[dict[str, Any]] = []
    for k, (leg, frs) in enumerate(zip(fp.legs, fp.leg_frames)):
        queue = [fl for kk, fl in fp.stair_legs if kk == k]
        for t, (p, f) in enumerate(zip(leg, frs)):
            if t and frs[t - 1] != f and queue:
                fl = queue.pop(0)
                climb = {"stair": fl.stair, "way": climbs(fl, frs), "leg": k, "run_m": fl.run_m, "rise_m": fl.rise_m}
                stairs.append(
                    _feature("LineString", [list(leg[t - 1]), list(p)], role="stair", **climb, length_m=fl.length_m)
                )
            if not runs or runs[-1][0] != f:
                runs.append((f, []))
            if not runs[-1][1] or runs[-1][1][-1] != list(p):
                runs[-1][1].append(list(p))
    out = [
        _feature("LineString", line, role="route", part=n, frame=f, mode=fp.options.mode)
        for n, (f, line) in enumerate(runs, 1)
        if len(line) > 1
    ]
    return out + stairs


def write_sheet(fp: FieldPlan, folder: Path | str) -> list[Path]:
    """Write the sheet's five files (see the module text) into ``folder``; return their paths."""
    from planner.field.pdf import map_paper, write_pdf  # here: its PDF backend and font subsetter cost 0.2 s to import

    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    paths = [out / f"field.{ext}" for ext in ("html", "csv", "geojson", "json", "pdf")]
    # one plan figure for field.pdf's first page and, on A4 (near the screen figure's size), for field.html's image;
    # a plan on A3 is large: field.html draws its own at the screen's size
    paper, size = map_paper(fp)
    plan = figure(fp, size)
    paths[0].write_text(render_html(fp, png_bytes(plan) if paper == "A4" else None))
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerows([HEADER, *rows(fp)])
    paths[1].write_text(buf.getvalue())
    paths[2].write_text(dumps(geojson(fp)))
    paths[3].write_text(dumps(to_dict(fp)))
    write_pdf(fp, paths[4], plan)
    return paths
