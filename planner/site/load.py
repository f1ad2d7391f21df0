"""One entry point for every site format: ``load_site(path)``."""

from __future__ import annotations

from pathlib import Path

from planner.errors import InputError
from planner.params import ClosureTolerance, Parameters
from planner.site.instance_json import load_instance_json
from planner.site.model import Site
from planner.site.table_csv import read_table_csv
from planner.site.tables import zone_from_table

READERS = {".json": "JSON instance", ".csv": "table CSV"}


def load_site(path: Path | str, tolerance: ClosureTolerance | None = None) -> Site:
    """Read a site from a JSON instance or a table CSV (chosen by the file's extension).

    A table CSV carries no parameters: the dissertation's defaults apply
    (:class:`~planner.params.Parameters`), with S_max derived from the
    instrument. ``tolerance`` sets the closure tolerance of a CSV's zones (a
    JSON instance carries its own).
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".json":
        return load_instance_json(path)
    if suffix == ".csv":
        tol = tolerance or ClosureTolerance()
        zones = tuple(zone_from_table(t, tol) for t in read_table_csv(path))
        return Site(name=path.stem, zones=zones, parameters=Parameters(), source=str(path))
    known = ", ".join(f"{k} ({v})" for k, v in READERS.items())
    raise InputError(f"unknown input format (known: {known})", file=str(path), value=suffix or "no extension")
