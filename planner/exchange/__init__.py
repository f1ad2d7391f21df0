"""Exchange with the field and with CAD/GIS: station list CSV, GeoJSON and DXF out; DXF and GeoJSON in."""

from planner.exchange.dxf_in import DxfOptions, read_dxf_site
from planner.exchange.dxf_out import write_dxf
from planner.exchange.geojson_in import read_geojson_site
from planner.exchange.geojson_out import outcome_geojson, write_geojson
from planner.exchange.stations_csv import write_stations_csv

EXPORTS = ("dxf", "geojson", "csv")

__all__ = ["EXPORTS", "DxfOptions", "outcome_geojson", "read_dxf_site", "read_geojson_site", "write_dxf",
           "write_geojson", "write_stations_csv"]
