"""The 3-D view of report.html: the walls, floors, ceilings and stations of a site on a ``<canvas>``, drawn by a small
inlined script (no library, no address), with each station's covered wall highlighted on selection.

:mod:`~planner.figures.view3d.model` holds the plain data (:class:`Scene3D`), :mod:`~planner.figures.view3d.build` fills
it (:func:`scene_3d`), :mod:`~planner.figures.view3d.render` draws it (:func:`render_view3d`);
:mod:`planner.report.view3d_section` fills it from an ``Outcome``.
"""

from planner.figures.view3d.build import covered_runs, scene_3d, views, wall_quads
from planner.figures.view3d.model import Covered, Scene3D, Station3D, Surface, View, WallQuad, Zone3D
from planner.figures.view3d.render import render_view3d, scene_json

__all__ = [
    "Covered",
    "Scene3D",
    "Station3D",
    "Surface",
    "View",
    "WallQuad",
    "Zone3D",
    "covered_runs",
    "render_view3d",
    "scene_3d",
    "scene_json",
    "views",
    "wall_quads",
]
