"""A plan out to the field and to CAD/GIS: station list CSV, GeoJSON and DXF; the coverage problem for other solvers.

Sites come in through :mod:`planner.site` (JSON, table CSV, DXF, GeoJSON, IFC, AGPLIB); plans go out here.
The names load on first use (PEP 562), so that writing one format does not import the others' libraries.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from planner import _lazy_getattr

EXPORTS = ("dxf", "geojson", "csv")

_LAZY = {
    "write_dxf": "planner.exchange.dxf_out",
    "outcome_geojson": "planner.exchange.geojson_out",
    "write_geojson": "planner.exchange.geojson_out",
    "write_stations_csv": "planner.exchange.stations_csv",
}


__getattr__ = _lazy_getattr("planner.exchange", _LAZY, globals())


if TYPE_CHECKING:
    from planner.exchange.dxf_out import write_dxf
    from planner.exchange.geojson_out import outcome_geojson, write_geojson
    from planner.exchange.stations_csv import write_stations_csv

__all__ = ["EXPORTS", "outcome_geojson", "write_dxf", "write_geojson", "write_stations_csv"]
