"""The interactive site map: one self-contained HTML fragment (inline SVG, style sheet and script; no library,
no address) to pan, zoom, switch layers and frames, and tap a station for what it covers.

- :mod:`~planner.figures.webmap.model`: the plain data (:class:`SiteMap` and its parts);
- :mod:`~planner.figures.webmap.build`: that data from a site, its stations, their coverage matrix and a
  field sheet's ``field.json`` dictionary (:func:`site_map_data`);
- :mod:`~planner.figures.webmap.render`: the fragment (:func:`render_site_map`), with ``site_map.js`` and
  ``site_map.css`` (package data) inlined.

It lives under :mod:`planner.figures` (below both :mod:`planner.report` and :mod:`planner.field`, which may not
import each other) so that report.html (:mod:`planner.report.site_map` fills it from an ``Outcome``) and the
field sheet both embed the same map. For a field sheet::

    from planner.field.sheet import to_dict
    from planner.figures.webmap import MapLink, render_site_map, site_map_data

    links = [MapLink(lk.a, lk.b, lk.shared_m, lk.fraction, lk.weak) for lk in fp.links]
    fragment = render_site_map(site_map_data(fp.site, fp.stations, links=links, field_sheet=to_dict(fp)))

(add ``runs=coverage_runs(sight.of_stations(fp.stations))`` for the coverage layer).
"""

from planner.figures.webmap.build import coverage_runs, field_layers, site_map_data, wall_lines
from planner.figures.webmap.model import MapLine, MapLink, MapPoint, MapStation, Run, SiteMap
from planner.figures.webmap.render import render_site_map

__all__ = [
    "MapLine",
    "MapLink",
    "MapPoint",
    "MapStation",
    "Run",
    "SiteMap",
    "coverage_runs",
    "field_layers",
    "render_site_map",
    "site_map_data",
    "wall_lines",
]
