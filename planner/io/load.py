"""One entry point for every site format: ``load_site(path)``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from planner.core.checks import path_argument
from planner.core.errors import InputError
from planner.io.file_kind import SITE_SUFFIXES
from planner.io.instance_json import load_instance_json
from planner.io.table_csv import read_table_csv
from planner.io.tables import zone_from_table
from planner.site.model import Site
from planner.site.params import ClosureTolerance, Parameters

#: the site formats read, by suffix (defined once, beside the check of a file's kind that needs them first)
READERS = SITE_SUFFIXES


def load_site(
    path: Path | str,
    tolerance: ClosureTolerance | None = None,
    *,
    dxf: Any = None,
    crs: str | None = None,
    ifc: Any = None,
) -> Site:
    """Read a site in any of the :data:`READERS` formats, by the file's extension. ``dxf``: which DXF layers hold what;
    ``crs``: the metric CRS a lon/lat GeoJSON is projected to; ``ifc``: which storeys of an IFC model to read.

    A table CSV carries no parameters: the dissertation's defaults apply (:class:`~planner.site.params.Parameters`),
    with S_max derived from the instrument. ``tolerance`` sets the closure tolerance of a CSV's zones (a JSON instance
    carries its own).
    """
    path_argument(path, "path")
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".json":
        return load_instance_json(path)
    if suffix == ".dxf":
        from planner.io.dxf_in import read_dxf_site

        return read_dxf_site(path, dxf)
    if suffix == ".geojson":
        from planner.io.geojson_in import read_geojson_site

        return read_geojson_site(path, crs=crs)
    if suffix == ".ifc":
        from planner.io.ifc_in import read_ifc_site

        return read_ifc_site(path, ifc)
    if suffix == ".pol":
        from planner.io.pol import read_pol

        return read_pol(path)
    if suffix == ".csv":
        tol = tolerance or ClosureTolerance()
        zones = tuple(zone_from_table(t, tol) for t in read_table_csv(path))
        return Site(name=path.stem, zones=zones, parameters=Parameters(), source=str(path))
    known = ", ".join(f"{k} ({v})" for k, v in READERS.items())
    raise InputError(f"unknown input format (known: {known})", file=str(path), value=suffix or "no extension")
