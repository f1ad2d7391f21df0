"""The interactive site map of report.html: :func:`outcome_site_map` fills a :class:`~planner.figures.webmap.SiteMap`
from an :class:`~planner.plan.outcome.Outcome` (and the plan's field sheet, where one was written), :func:`site_map_html`
renders it.

Coverage is the outcome's recomputed coverage; the registration links are the plan's overlap relation
(:func:`planner.coverage.relation.station_relation`) under the registration scope the plan was made with, whether or not
the network check ran; the control points and traverse legs are the network check's.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

from planner.core.checks import argument
from planner.figures.base import png_bytes
from planner.figures.site_fig import site_figure
from planner.figures.webmap import MapLine, MapLink, MapPoint, SiteMap, coverage_runs, render_site_map, site_map_data
from planner.plan.outcome import Outcome
from planner.plan.plan_dict import StationNumbering
from planner.report.markup import image
from planner.report.surfaces_section import station_areas


def station_row_id(number: int) -> str:
    """The HTML id of the row of station no. ``number`` in report.html's station table, which the map links to."""
    return f"station-{number}"


def field_order(field_sheet: Mapping[str, Any] | None) -> list[str] | None:
    """The station ids of a field sheet (``field.json``) in visiting order; None without a sheet."""
    order = [str(s) for s in (field_sheet or {}).get("order", [])]
    return order or None


def report_numbering(o: Outcome, field_sheet: Mapping[str, Any] | None = None) -> StationNumbering:
    """The numbering of the report's stations (:meth:`StationNumbering.decide
    <planner.plan.plan_dict.StationNumbering.decide>`): the linked field sheet's walking order, else the one the
    plan records (plan order where it records none)."""
    return StationNumbering.decide(o.meta, o.stations, field_order(field_sheet))


def _links(o: Outcome) -> list[MapLink]:
    g = o.registration.relation(o.stations, o.sight.of_stations(o.stations))  # on the station pieces, as the plan's
    return [
        MapLink(o.stations[u].id, o.stations[v].id, float(d["shared_m"]), float(d["fraction"]))
        for u, v, d in sorted(g.edges(data=True), key=lambda e: (min(e[0], e[1]), max(e[0], e[1])))
    ]


def _control(o: Outcome) -> tuple[list[MapPoint], list[MapLine]]:
    """The network check's control points and control traverse legs (none where it did not run)."""
    if o.network is None:
        return [], []
    g = o.network.graph
    points, legs = [], []
    for n, d in g.nodes(data=True):
        if d.get("kind") == "control":  # control points and the traverse's own points
            kind, note = ("proposed", " (proposed)") if d.get("proposed") else ("control", "")
            at = str(n), str(d["frame"]), float(d["x"]), float(d["y"])
            points.append(MapPoint(*at, kind, f"control point {n}{note}"))
    for u, v, d in g.edges(data=True):
        if "traverse" in d["kinds"]:
            ends = ((g.nodes[u]["x"], g.nodes[u]["y"]), (g.nodes[v]["x"], g.nodes[v]["y"]))
            label = f"traverse leg {u} - {v}, {d['length_m']:.1f} m"
            legs.append(MapLine(f"{u}-{v}", str(g.nodes[u]["frame"]), "traverse", ends, False, label))
    return points, legs


def outcome_site_map(
    o: Outcome, field_sheet: Mapping[str, Any] | None = None, numbering: StationNumbering | None = None
) -> SiteMap:
    """The map data of a plan's outcome; ``field_sheet``: its field sheet as ``field.json`` holds it (None: no
    route and targets); ``numbering``: the stations' numbers (None: :func:`report_numbering`). Stations link to the
    rows :func:`station_row_id` names."""
    argument(o, Outcome, "outcome")
    numbering = numbering or report_numbering(o, field_sheet)
    control, traverse = _control(o)
    return site_map_data(
        o.site,
        o.stations,
        runs=coverage_runs(o.coverage.problem),
        links=_links(o),
        field_sheet=field_sheet,
        control=control,
        traverse=traverse,
        rows={s.id: station_row_id(numbering.number(s.id)) for s in o.stations},
        areas=station_areas(o),
        numbering=numbering,
    )


def numbered_outcome(o: Outcome, numbering: StationNumbering | None) -> Outcome:
    """``o`` whose plan dictionary records ``numbering`` (each station's number and label), so that every writer of
    it (report, exports) shows those numbers; ``o`` itself where ``numbering`` is None."""
    return o if numbering is None else replace(o, meta=numbering.record(o.meta))


def read_field_sheet(folder: Path | str) -> dict[str, Any] | None:
    """``folder/field.json`` as a dictionary, or None where there is none (or it is not a field sheet)."""
    path = Path(folder) / "field.json"
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) and isinstance(data.get("order"), list) else None


def site_map_html(
    o: Outcome, field_sheet: Mapping[str, Any] | None = None, numbering: StationNumbering | None = None
) -> str:
    """The report's map fragment (see :func:`planner.figures.webmap.render_site_map`)."""
    return render_site_map(outcome_site_map(o, field_sheet, numbering))


def site_plan_html(o: Outcome, field_sheet: Mapping[str, Any] | None, numbering: StationNumbering | None = None) -> str:
    """The whole site on one figure (:func:`planner.figures.site_fig.site_figure`): every zone in its frame,
    stations numbered as everywhere in the report (:func:`report_numbering`), registration links, control points,
    scale bar and north. The per-zone plans follow under "Plans"."""
    numbering = numbering or report_numbering(o, field_sheet)
    alt = f"the whole site: {numbering.legend}, registration links, control points, scale bar and north"
    return image(png_bytes(site_figure(o, numbering=numbering)), alt)
