"""The interactive site map of field.html (:func:`field_map_html`): the same map as report.html's
(:mod:`planner.figures.webmap`), filled from a :class:`~planner.field.run.FieldPlan` (:func:`field_site_map`).

What it shows, by layer: the zones' walls and openings, obstacles, no-go areas and the boundary; per station the runs of
wall it covers (the coverage the sheet was made from, :attr:`FieldPlan.coverage <planner.field.run.FieldPlan.coverage>`,
hidden until the station is selected); the registration links of the sheet's chain (weak ones dashed); the walking route
from its start, the legs through a wall (where the model has no opening, :mod:`planner.field.crossing`) in their own
dash; the registration targets. Stations are numbered in visiting order (:attr:`FieldPlan.numbering
<planner.field.run.FieldPlan.numbering>`, as the setup table, the report and the exports number them), and each links
to its row of that table (:func:`setup_row_id`): a tap on a station marks its row, a click on a row shows its station.

The map has an edit mode (:mod:`planner.figures.webmap.edit`; report.html's map has none): the crew marks stations
done, blocked or moved, draws closed areas and obstacles, closes zones, sets where it stands and the hours left, and
the page saves ``edits.json`` (stations by the numbers this sheet prints) for ``planner replan``.
"""

from __future__ import annotations

from planner.field.record import to_dict
from planner.field.run import FieldPlan
from planner.figures.webmap import MapLink, SiteMap, coverage_runs, render_site_map, site_map_data

#: the HTML id of field.html's map
MAP_ID = "field-map"


def setup_row_id(n: int) -> str:
    """The HTML id of the row of setup ``n`` (1-based, visiting order) in field.html's setup table."""
    return f"setup-{n}"


def field_site_map(fp: FieldPlan) -> SiteMap:
    """The map data of a field sheet (see the module text; any station the order leaves out follows in plan order,
    the route and targets are those of :func:`~planner.field.record.to_dict`); no coverage layer where ``fp``
    carries no coverage (a plan built by hand without one)."""
    seen = set(fp.order)
    visiting = [*fp.order, *(k for k in range(len(fp.stations)) if k not in seen)]
    stations = [fp.stations[k] for k in visiting]
    runs = None
    if fp.coverage is not None:
        every = coverage_runs(fp.coverage)
        runs = [every[k] for k in visiting]
    links = [MapLink(lk.a, lk.b, lk.shared_m, lk.fraction, lk.weak) for lk in fp.links]
    numbering = fp.numbering
    rows = {s.id: setup_row_id(numbering.number(s.id)) for s in stations[: len(fp.order)]}
    return site_map_data(
        fp.site, stations, runs=runs, links=links, field_sheet=to_dict(fp), rows=rows, numbering=numbering
    )


def field_map_html(fp: FieldPlan) -> str:
    """The map of :func:`field_site_map` as a self-contained HTML fragment (id :data:`MAP_ID`; no address), with the
    edit mode (:mod:`planner.figures.webmap.edit`): the crew marks on it what changed on site and saves
    ``edits.json``, stations by the numbers this sheet prints, for ``planner replan``."""
    return render_site_map(field_site_map(fp), dom_id=MAP_ID, table="setup table", edit=True)
