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
from pathlib import Path
from typing import Any

from planner.core.checks import argument
from planner.figures.base import png_bytes
from planner.figures.site_fig import site_figure
from planner.figures.webmap import MapLine, MapLink, MapPoint, SiteMap, coverage_runs, render_site_map, site_map_data
from planner.plan.outcome import Outcome
from planner.report.markup import image
from planner.report.surfaces_section import station_areas


def station_row_id(k: int) -> str:
    """The HTML id of the k-th (1-based) row of report.html's station table, which the map links to."""
    return f"station-{k}"


def _links(o: Outcome) -> list[MapLink]:
    g = o.registration.relation(o.stations, o.coverage.problem)
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


def outcome_site_map(o: Outcome, field_sheet: Mapping[str, Any] | None = None) -> SiteMap:
    """The map data of a plan's outcome; ``field_sheet``: its field sheet as ``field.json`` holds it (None: no
    route and targets). Stations link to the rows :func:`station_row_id` names."""
    argument(o, Outcome, "outcome")
    control, traverse = _control(o)
    return site_map_data(
        o.site,
        o.stations,
        runs=coverage_runs(o.coverage.problem),
        links=_links(o),
        field_sheet=field_sheet,
        control=control,
        traverse=traverse,
        rows={s.id: station_row_id(k) for k, s in enumerate(o.stations, 1)},
        areas=station_areas(o),
    )


def read_field_sheet(folder: Path | str) -> dict[str, Any] | None:
    """``folder/field.json`` as a dictionary, or None where there is none (or it is not a field sheet)."""
    path = Path(folder) / "field.json"
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) and isinstance(data.get("order"), list) else None


def site_map_html(o: Outcome, field_sheet: Mapping[str, Any] | None = None) -> str:
    """The report's map fragment (see :func:`planner.figures.webmap.render_site_map`)."""
    return render_site_map(outcome_site_map(o, field_sheet))


def site_plan_html(o: Outcome, field_sheet: Mapping[str, Any] | None) -> str:
    """The whole site on one figure (:func:`planner.figures.site_fig.site_figure`): every zone in its frame,
    stations numbered in the field sheet's walking order where one was written (else the plan's order),
    registration links, control points, scale bar and north. The per-zone plans follow under "Plans"."""
    ids = {s.id for s in o.stations}
    order = [str(s) for s in (field_sheet or {}).get("order", []) if str(s) in ids] or None
    how = "numbered in walking order (field sheet)" if order else "numbered in the plan's order"
    alt = f"the whole site: stations {how}, registration links, control points, scale bar and north"
    return image(png_bytes(site_figure(o, order=order)), alt)
