"""The interactive site map: one self-contained HTML fragment (inline SVG, style sheet and script; no library, no
address) to pan, zoom, switch layers and frames, and tap a station for what it covers.

:mod:`~planner.figures.webmap.model` holds the plain data (:class:`SiteMap`), :mod:`~planner.figures.webmap.build`
fills it (:func:`site_map_data`), :mod:`~planner.figures.webmap.render` draws it (:func:`render_site_map`, with
the package data ``site_map.js`` and ``site_map.css`` inlined). It lives below both :mod:`planner.report` and
:mod:`planner.field`, which may not import each other, so that report.html and the field sheet
(:mod:`planner.field.site_map`) embed the same map.
"""

from planner.figures.webmap.build import coverage_runs, field_layers, site_map_data, wall_lines
from planner.figures.webmap.model import MapArea, MapLine, MapLink, MapPoint, MapStation, Run, SiteMap
from planner.figures.webmap.render import render_site_map

__all__ = [
    "MapArea",
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
