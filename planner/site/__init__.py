"""Site geometry: zones with walls and heights, obstacles, no-go areas, control; the readers."""

from planner.site.load import load_site
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
    "load_site",
    "reconstruct",
]
