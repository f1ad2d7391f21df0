"""The "3-D view" section of report.html: the site's walls, floors and ceilings and the plan's stations in 3-D
(:mod:`planner.figures.view3d`), each station's covered wall from the outcome's recomputed coverage, highlighted when it
is selected.

Every plan shows it (every site has walls); it matters most for a building read from IFC with several storeys. A site of
more than :data:`MAX_WALL_PIECES` wall pieces gets a one-line note instead, to keep report.html small.
"""

from __future__ import annotations

from collections.abc import Mapping

from planner.core.checks import argument
from planner.figures.view3d import Scene3D, render_view3d, scene_3d
from planner.plan.outcome import Outcome
from planner.plan.plan_dict import StationNumbering

#: above this many wall pieces (coverage targets) the report says so in one line instead of drawing the view
MAX_WALL_PIECES = 20_000


def instrument_height_m(o: Outcome) -> float:
    """The height above its floor each station is drawn at: the plan's surfaces instrument height where the plan has one
    (plan.json ``surfaces.instrument_height_m``), else the site's ``instrument_height_m``."""
    s = o.meta.get("surfaces")
    if isinstance(s, Mapping) and isinstance(s.get("instrument_height_m"), (int, float)):
        return float(s["instrument_height_m"])
    return float(o.site.parameters.instrument_height_m)


def outcome_scene(o: Outcome, numbering: StationNumbering | None = None) -> Scene3D:
    """The 3-D scene of a plan's outcome: its site, its stations (numbered by ``numbering``, as every table and
    figure of the report; None: as the plan records) and the wall each covers."""
    argument(o, Outcome, "outcome")
    numbering = numbering or StationNumbering.recorded(o.meta, o.stations)
    return scene_3d(o.site, o.stations, o.coverage.problem, instrument_height_m(o), numbering)


def view3d_section(o: Outcome, numbering: StationNumbering | None = None) -> str:
    """The "3-D view" section (heading included), or its heading and a one-line note on a site too large."""
    argument(o, Outcome, "outcome")
    n = len(o.coverage.targets)
    if n > MAX_WALL_PIECES:
        return (
            f"<h2>3-D view</h2><p>Not drawn: {n:,} wall pieces, more than the {MAX_WALL_PIECES:,} the report draws "
            "in 3-D (to keep report.html small); the site map and plans above show the stations and their coverage."
            "</p>"
        )
    return "<h2>3-D view</h2>" + render_view3d(outcome_scene(o, numbering))
