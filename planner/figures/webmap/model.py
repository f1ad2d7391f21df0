"""The plain data an interactive site map draws (:class:`SiteMap`): polylines, stations with the runs of wall they
cover, links, route legs and points, each tagged with the frame it is drawn in.

Plain frozen dataclasses of numbers and text, so that any page (report.html, field.html) can fill them from what it has,
and the renderer (:mod:`planner.figures.webmap.render`) depends on nothing of the planner's. Coordinates are in metres
in the frame named by ``frame`` (the site's own frame, or a zone's local frame for table zones); the renderer rounds
them to centimetres.
"""

from __future__ import annotations

from dataclasses import dataclass, field

Point = tuple[float, float]


@dataclass(frozen=True)
class MapLine:
    """A polyline of the map: a wall ring, an obstacle, a no-go area, an opening, a route leg, a traverse leg.

    ``kind`` picks the style and the layer (``wall``, ``opening``, ``obstacle``, ``nogo``, ``boundary``, ``route``,
    ``through``: a route leg through a wall, ``traverse``); ``closed``: a ring (drawn as a polygon); ``label``: a
    tooltip.
    """

    id: str
    frame: str
    kind: str
    points: tuple[Point, ...]
    closed: bool = False
    label: str = ""


@dataclass(frozen=True)
class Run:
    """Consecutive wall pieces one station covers on one wall face: drawn as one segment from ``a`` to ``b``.

    ``pieces``: how many pieces the run merges (what the highlight count adds up); ``length_m``: their length;
    ``label``: zone/side/wall and the offsets along the wall.
    """

    a: Point
    b: Point
    pieces: int
    length_m: float
    label: str = ""


@dataclass(frozen=True)
class MapArea:
    """Floor or ceiling one station covers in one zone, merged into one shape: drawn filled (even-odd).

    ``rings``: the exterior rings and holes of its polygons; ``kind``: ``floor`` or ``ceiling``; ``patches``: how many
    surface patches it merges; ``area_m2``: their area; ``label``: zone and kind.
    """

    rings: tuple[tuple[Point, ...], ...]
    kind: str
    patches: int
    area_m2: float
    label: str = ""


@dataclass(frozen=True)
class Located:
    """Something drawn at a point: its id, the frame it is drawn in, and where."""

    id: str
    frame: str
    x: float
    y: float


@dataclass(frozen=True)
class MapStation(Located):
    """A station as the map shows it: where it stands, what it covers, and where it is listed.

    ``label``: the short text drawn beside it (its number); ``number`` and ``name``: its one number and label
    (:class:`~planner.plan.plan_dict.StationNumbering`), written on it as ``data-station-number`` and
    ``data-station-label``; ``row``: the HTML id of its row in the page's station table ("" where the page has
    none); ``visit``: its place in the field visiting order (0: no order);
    ``runs``: the wall it covers (empty where the page has no coverage to show); ``areas``: the floor and ceiling it
    covers (empty: walls only).
    """

    label: str = ""
    zone: str = ""
    side: str = ""
    kind: str = ""
    row: str = ""
    visit: int = 0
    runs: tuple[Run, ...] = ()
    areas: tuple[MapArea, ...] = ()
    number: int = 0
    name: str = ""

    @property
    def pieces(self) -> int:
        """Wall pieces covered, summed over the runs."""
        return sum(r.pieces for r in self.runs)

    @property
    def covered_m(self) -> float:
        """Wall covered, in metres."""
        return sum(r.length_m for r in self.runs)


@dataclass(frozen=True)
class MapLink:
    """A registration link between stations ``a`` and ``b`` (ids): ``shared_m`` of wall both see (0: a link through an
    opening, as :func:`planner.coverage.overlap.overlap_graph` makes them; None: not known) and the ``fraction`` of the
    smaller station's wall; ``weak``: a link the field sheet marks weak (drawn dashed)."""

    a: str
    b: str
    shared_m: float | None = None
    fraction: float | None = None
    weak: bool = False


@dataclass(frozen=True)
class MapPoint(Located):
    """A point drawn with a marker: a registration target (``kind`` checkerboard, sphere, control) or a control point
    (``control``, ``proposed``: a control point the network check proposed)."""

    kind: str
    label: str = ""


@dataclass(frozen=True)
class SiteMap:
    """Everything one interactive map shows, by layer.

    ``frames``: the frames in the order the selector lists them (the first with the most stations is shown first);
    ``walls``: zones' walls and openings, obstacles, no-go areas and the boundary; ``route``: the field walking route,
    one line per leg, with ``start`` where it begins; ``targets``: registration targets; ``control``: control points,
    ``traverse``: the control traverse legs; ``numbering``: how the stations are numbered, in words (the legend);
    ``zones``: the site's zone ids (what the field sheet's edit mode offers to close) and ``site_frame``: the frame
    whose coordinates are the site's, the one frame that edit mode takes positions in (the site's own frame; the only
    frame where there is one, as a site of one table zone has: its coordinates are those of plan.json).
    """

    title: str
    frames: tuple[str, ...]
    walls: tuple[MapLine, ...]
    stations: tuple[MapStation, ...]
    links: tuple[MapLink, ...] = ()
    route: tuple[MapLine, ...] = ()
    start: MapPoint | None = None
    targets: tuple[MapPoint, ...] = ()
    control: tuple[MapPoint, ...] = ()
    traverse: tuple[MapLine, ...] = field(default=())
    numbering: str = ""
    zones: tuple[str, ...] = ()
    site_frame: str = "site"
