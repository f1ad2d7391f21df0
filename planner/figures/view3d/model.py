"""The plain data the 3-D view draws (:class:`Scene3D`): walls as vertical quads, floors and ceilings as polygons at
their levels, stations as points at instrument height, each with the wall it covers.

Frozen dataclasses of numbers and text in world metres: x, y in the frame named by the zone (a building's storeys share
one plan frame; table zones each have their own), z in the site's vertical datum (a zone's ``floor_level_m`` plus
heights measured from that floor). The renderer (:mod:`planner.figures.view3d.render`) depends on nothing else of the
planner's.
"""

from __future__ import annotations

from dataclasses import dataclass

Point = tuple[float, float]


@dataclass(frozen=True)
class WallQuad:
    """Wall ``wall`` (1-based, as the zone numbers them) of zone ``zone`` (index into :attr:`Scene3D.zones`): a vertical
    quad from ``a`` to ``b`` (plan, m), from ``floor_m`` up to its top edge, ``top_a_m`` at ``a`` and ``top_b_m`` at
    ``b`` (absolute heights, m; the top edge runs linearly between them)."""

    zone: int
    wall: int
    a: Point
    b: Point
    floor_m: float
    top_a_m: float
    top_b_m: float

    @property
    def length_m(self) -> float:
        return float(((self.b[0] - self.a[0]) ** 2 + (self.b[1] - self.a[1]) ** 2) ** 0.5)

    def corners(self, s0_m: float = 0.0, s1_m: float | None = None) -> tuple[tuple[float, float, float], ...]:
        """The quad's corners (bottom at s0, bottom at s1, top at s1, top at s0) of the part from ``s0_m`` to ``s1_m``
        along the wall (None: its end), in world metres."""
        n = self.length_m or 1.0
        s1 = n if s1_m is None else s1_m
        out = []
        for s, up in ((s0_m, False), (s1, False), (s1, True), (s0_m, True)):
            t = s / n
            x, y = self.a[0] + t * (self.b[0] - self.a[0]), self.a[1] + t * (self.b[1] - self.a[1])
            out.append((x, y, self.top_a_m + t * (self.top_b_m - self.top_a_m) if up else self.floor_m))
        return tuple(out)


@dataclass(frozen=True)
class Surface:
    """A floor or ceiling of zone ``zone``: its outline and holes (plan, m) at height ``level_m``."""

    zone: int
    kind: str
    level_m: float
    rings: tuple[tuple[Point, ...], ...]


@dataclass(frozen=True)
class Covered:
    """Consecutive wall pieces one station covers on one wall face: wall ``wall`` (index into :attr:`Scene3D.walls`)
    from ``s0_m`` to ``s1_m`` along it; ``pieces``: how many pieces the run merges."""

    wall: int
    s0_m: float
    s1_m: float
    pieces: int


@dataclass(frozen=True)
class Station3D:
    """A station where the scanner stands: plan position, ``z_m`` its instrument's height in the datum (floor level plus
    instrument height), ``floor_m`` the floor it stands on; ``covered`` the wall it covers."""

    id: str
    label: str
    zone: int
    x: float
    y: float
    floor_m: float
    z_m: float
    covered: tuple[Covered, ...] = ()

    @property
    def pieces(self) -> int:
        """Wall pieces covered, summed over the runs."""
        return sum(c.pieces for c in self.covered)


@dataclass(frozen=True)
class Zone3D:
    """A zone as the view lists it: its id, frame, scan side and floor level (m)."""

    id: str
    frame: str
    side: str
    floor_m: float


@dataclass(frozen=True)
class View:
    """One choice of the storey filter: a name and the zones (indices) it shows."""

    name: str
    zones: tuple[int, ...]


@dataclass(frozen=True)
class Scene3D:
    """Everything the 3-D view draws. ``views``: the storey filter's choices, the first shown first (one per frame, an
    "all" first where the frames are storeys of one building, one per level where one frame has several); ``covered``:
    the wall some station covers (shown while no station is selected); ``instrument_height_m``: the height above the
    floor the stations are drawn at."""

    title: str
    zones: tuple[Zone3D, ...]
    walls: tuple[WallQuad, ...]
    surfaces: tuple[Surface, ...]
    stations: tuple[Station3D, ...]
    views: tuple[View, ...]
    covered: tuple[Covered, ...] = ()
    instrument_height_m: float = 0.0
