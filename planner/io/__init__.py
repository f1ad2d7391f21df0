"""Every reader and writer: sites in (JSON instance, table CSV, DXF, GeoJSON, IFC, AGPLIB polygons: :func:`load_site`),
control points and field observations in, plans out and back (plan.json), and a plan out to the field and to CAD/GIS
(station list CSV, GeoJSON, DXF) and the coverage problem out to other solvers.

The names load on first use (PEP 562), so that reading or writing one format does not import the others' libraries.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from planner import _lazy_getattr

EXPORTS = ("dxf", "geojson", "csv")

_LAZY = {
    "load_site": "planner.io.load",
    "write_plan": "planner.io.plan_json",
    "read_plan_stations": "planner.io.plan_json",
    "outcome_from_file": "planner.io.plan_file",
    "write_dxf": "planner.io.dxf_out",
    "outcome_geojson": "planner.io.geojson_out",
    "write_geojson": "planner.io.geojson_out",
    "write_stations_csv": "planner.io.stations_csv",
}


__getattr__ = _lazy_getattr("planner.io", _LAZY, globals())


if TYPE_CHECKING:
    from planner.io.dxf_out import write_dxf
    from planner.io.geojson_out import outcome_geojson, write_geojson
    from planner.io.load import load_site
    from planner.io.plan_file import outcome_from_file
    from planner.io.plan_json import read_plan_stations, write_plan
    from planner.io.stations_csv import write_stations_csv

__all__ = [
    "EXPORTS",
    "load_site",
    "outcome_from_file",
    "outcome_geojson",
    "read_plan_stations",
    "write_dxf",
    "write_geojson",
    "write_plan",
    "write_stations_csv",
]
