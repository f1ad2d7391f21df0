"""Site geometry: zones with walls and heights, obstacles, no-go areas, control points, traverse closure and
assembly (the readers that make a :class:`Site` from a file are in :mod:`planner.io`)."""

from planner.site.model import ControlPoint, Correction, NoGoArea, Obstacle, ScanSide, Site, Wall, Zone
from planner.site.traverse import AcceptedMisclosure, ClosureReport, TableRow, ZoneTable, reconstruct

__all__ = [
    "AcceptedMisclosure",
    "ClosureReport",
    "ControlPoint",
    "Correction",
    "NoGoArea",
    "Obstacle",
    "ScanSide",
    "Site",
    "TableRow",
    "Wall",
    "Zone",
    "ZoneTable",
    "reconstruct",
]
