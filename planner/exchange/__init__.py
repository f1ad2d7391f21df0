"""Exchange with the field and with CAD/GIS: station list CSV, GeoJSON and DXF out; DXF, GeoJSON and IFC in.

The names load on first use (PEP 562), so that reading one format does not import the others'
libraries (ezdxf, the report stack).
"""

from __future__ import annotations

from planner._lazy import lazy_getattr
from typing import TYPE_CHECKING, Any

EXPORTS = ("dxf", "geojson", "csv")

_LAZY = {
    "DxfOptions": "planner.exchange.dxf_in", "read_dxf_site": "planner.exchange.dxf_in",
    "write_dxf": "planner.exchange.dxf_out", "read_geojson_site": "planner.exchange.geojson_in",
    "outcome_geojson": "planner.exchange.geojson_out", "write_geojson": "planner.exchange.geojson_out",
    "write_stations_csv": "planner.exchange.stations_csv",
}


__getattr__ = lazy_getattr("planner.exchange", _LAZY, globals())


if TYPE_CHECKING:
    from planner.exchange.dxf_in import DxfOptions, read_dxf_site
    from planner.exchange.dxf_out import write_dxf
    from planner.exchange.geojson_in import read_geojson_site
    from planner.exchange.geojson_out import outcome_geojson, write_geojson
    from planner.exchange.stations_csv import write_stations_csv

__all__ = ["EXPORTS", "DxfOptions", "outcome_geojson", "read_dxf_site", "read_geojson_site", "write_dxf",
           "write_geojson", "write_stations_csv"]
