"""The site: zones with walls and height profiles, obstacles, no-go areas, boundary, control.

All value objects are frozen and validated on construction. Coordinates are metres in the zone's
``frame``: a table zone lives in its own frame, zones given by coordinates share the frame ``"site"``
with the obstacles, no-go areas, boundary and control points.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from enum import Enum
from functools import cached_property
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.core.checks import finite_number, no_repeats
from planner.core.errors import InputError
from planner.site.features import SITE_FRAME, ControlPoint, Correction, NoGoArea, Obstacle, Opening
from planner.site.geometry import check_simple_polygon, read_only, ring_key, side_lengths, signed_area
from planner.site.params import HEIGHT_RULE, MAX_HEIGHT_M, Parameters, height_ok
from planner.site.stairs import Stair
from planner.site.traverse import AcceptedMisclosure, ClosureReport

#: printed wall heights are given to 0.001 m
HEIGHT_CHECK_TOL_M = 0.0005


class ScanSide(str, Enum):
    """Where the stations of a zone stand."""

    INSIDE = "inside"  # rooms, courts
    OUTSIDE = "outside"  # the outer outline
    BOTH = "both"  # the theoretical polygons A, B, C

    @property
    def sides(self) -> tuple[ScanSide, ...]:
        """The single sides this stands for (BOTH -> INSIDE, OUTSIDE)."""
        return (ScanSide.INSIDE, ScanSide.OUTSIDE) if self is ScanSide.BOTH else (self,)


@dataclass(frozen=True)
class Wall:
    """Wall ``index`` (1-based) of a zone: from vertex ``index`` to the next, counter-clockwise (the zone to
    its left); the top edge runs linearly from ``h_start_m`` to ``h_end_m``."""

    zone: str
    index: int
    start: tuple[float, float]
    end: tuple[float, float]
    h_start_m: float
    h_end_m: float
    printed_height_m: float | None = None

    @property
    def length_m(self) -> float:
        return math.hypot(self.end[0] - self.start[0], self.end[1] - self.start[1])

    @property
    def height_m(self) -> float:
        """The highest point of the top edge."""
        return max(self.h_start_m, self.h_end_m)

    def height_at(self, t: NDArray[np.float64] | float) -> NDArray[np.float64]:
        """Top height at fraction ``t`` (0 at start, 1 at end) along the wall."""
        return self.h_start_m + (self.h_end_m - self.h_start_m) * np.asarray(t, dtype=float)

    @property
    def height_check_ok(self) -> bool:
        """True when the printed wall height is the max of its vertex heights (or none printed)."""
        return self.printed_height_m is None or abs(self.printed_height_m - self.height_m) <= HEIGHT_CHECK_TOL_M


@dataclass(frozen=True)
class Zone:
    """A simple polygon, stored counter-clockwise, scanned from ``scan_side``. ``holes``: free-standing blocks inside an
    inside-scanned zone (piers), each a ring stored clockwise so that the zone is to the left of its walls too; their
    walls are numbered after the outline's. ``floor_level_m``: the floor's height in the site's vertical datum;
    ``ceiling_height_m``: the ceiling's height above that floor (None: no ceiling). Both serve the floor and ceiling
    targets; wall and instrument heights stay measured from the zone's own floor."""

    id: str
    scan_side: ScanSide
    vertices: tuple[tuple[float, float], ...]
    vertex_heights_m: tuple[float, ...]
    printed_wall_heights_m: tuple[float | None, ...] = ()
    frame: str = SITE_FRAME
    closure: ClosureReport | None = None
    notes: tuple[str, ...] = ()
    holes: tuple[tuple[tuple[float, float], ...], ...] = ()
    hole_heights_m: tuple[tuple[float, ...], ...] = ()
    openings: tuple[Opening, ...] = ()
    floor_level_m: float = 0.0
    ceiling_height_m: float | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.id, str) or not self.id:
            raise InputError("a zone needs a non-empty text id", field="id", value=self.id)
        if not isinstance(self.scan_side, ScanSide):  # "inside" from a script: read it as the enum, or refuse
            try:
                object.__setattr__(self, "scan_side", ScanSide(self.scan_side))
            except ValueError:
                raise self._bad(
                    f"must be one of {', '.join(s.value for s in ScanSide)}", "scan_side", self.scan_side
                ) from None
        xy = np.asarray(self.vertices, dtype=float).reshape(-1, 2)
        check_simple_polygon(xy, what="polygon", zone=self.id)
        if signed_area(xy) <= 0:
            raise self._bad("vertices must be counter-clockwise", "polygon")
        n = len(xy)
        if len(self.vertex_heights_m) != n:
            raise self._bad(f"needs {n} vertex heights", "vertex_heights_m", len(self.vertex_heights_m))
        for k, h in enumerate(self.vertex_heights_m, start=1):
            if not height_ok(h):
                raise self._bad(HEIGHT_RULE, "vertex_height_m", h, row=k)
        if self.printed_wall_heights_m and len(self.printed_wall_heights_m) != n:
            raise self._bad(f"needs {n} wall heights", "wall_heights_m", len(self.printed_wall_heights_m))
        if self.holes:
            self._check_holes()
        self._check_openings()
        self._check_levels()

    def _bad(self, message: str, field: str, value: Any = None, **where: Any) -> InputError:
        """The error of a zone's value: ``message``, naming this zone, ``field`` and ``value``."""
        return InputError(message, zone=self.id, field=field, value=value, **where)

    def _check_levels(self) -> None:
        """The floor level within +-MAX_HEIGHT_M, the ceiling (when given) above the floor and at most MAX_HEIGHT_M."""
        f = self.floor_level_m
        if not finite_number(f) or abs(f) > MAX_HEIGHT_M:
            raise self._bad(f"must be a finite level within +-{MAX_HEIGHT_M:g} m", "floor_level_m", f)
        c = self.ceiling_height_m
        if c is None:
            return
        if not finite_number(c) or not 0 < c <= MAX_HEIGHT_M:
            raise self._bad(f"{HEIGHT_RULE} above the floor (or null: no ceiling)", "ceiling_height_m", c)

    def _check_openings(self) -> None:
        walls = self.walls
        for op in self.openings:
            if not 1 <= op.wall <= len(walls):
                raise self._bad(f"wall index out of 1..{len(walls)}", "opening wall", op.wall)
            length = walls[op.wall - 1].length_m
            if op.s1_m > length + 1e-9:
                raise self._bad(f"runs past the end of wall {op.wall} ({length:.3f} m)", "opening s1_m", op.s1_m)

    def _check_holes(self) -> None:
        if self.scan_side is not ScanSide.INSIDE:
            raise self._bad("only a zone scanned inside can hold holes", "scan_side", self.scan_side.value)
        if len(self.hole_heights_m) != len(self.holes):
            raise self._bad(f"needs heights for {len(self.holes)} holes", "hole_heights_m")
        for k, (ring, hs) in enumerate(zip(self.holes, self.hole_heights_m), 1):
            xy = np.asarray(ring, dtype=float).reshape(-1, 2)
            check_simple_polygon(xy, what=f"hole {k}", zone=self.id)
            if signed_area(xy) >= 0:
                raise self._bad("hole vertices must be clockwise", f"hole {k}")
            if len(hs) != len(xy) or not all(height_ok(h) for h in hs):
                raise self._bad(f"needs {len(xy)} finite heights > 0 and <= {MAX_HEIGHT_M:g} m", f"hole {k} heights")
        poly = self.polygon
        if not poly.is_valid:
            why = f"holes and outline do not form a valid polygon ({shapely.is_valid_reason(poly)})"
            raise self._bad(why, "holes")

    @cached_property
    def xy(self) -> NDArray[np.float64]:
        """Vertices as a read-only (n, 2) array."""
        return read_only(np.asarray(self.vertices, dtype=float))

    @cached_property
    def outer_walls(self) -> tuple[Wall, ...]:
        """The walls of the outline, wall i from vertex i (what the closed-form geometry plans)."""
        v, h, n = self.vertices, self.vertex_heights_m, len(self.vertices)
        printed = self.printed_wall_heights_m or (None,) * n
        return tuple(Wall(self.id, i + 1, v[i], v[(i + 1) % n], h[i], h[(i + 1) % n], printed[i]) for i in range(n))

    @cached_property
    def walls(self) -> tuple[Wall, ...]:
        """Every scanned wall: the outline's, then each hole's."""
        out = list(self.outer_walls)
        for ring, hs in zip(self.holes, self.hole_heights_m):
            m = len(ring)
            first = len(out) + 1  # hole walls are numbered on after the outline's (and earlier holes')
            out += [Wall(self.id, first + i, ring[i], ring[(i + 1) % m], hs[i], hs[(i + 1) % m]) for i in range(m)]
        return tuple(out)

    @property
    def rings(self) -> tuple[NDArray[np.float64], ...]:
        """Outline and hole rings as (n, 2) arrays."""
        return (self.xy,) + tuple(np.asarray(r, dtype=float) for r in self.holes)

    @property
    def perimeter_m(self) -> float:
        return float(sum(side_lengths(r).sum() for r in self.rings))

    @property
    def area_m2(self) -> float:
        return signed_area(self.xy) + sum(signed_area(np.asarray(r, float)) for r in self.holes)

    @cached_property
    def polygon(self) -> shapely.Polygon:
        return shapely.Polygon(self.xy, [np.asarray(r, float) for r in self.holes])

    @property
    def misclosed(self) -> bool:
        """A traverse that does not close, accepted as printed (its sides and vertices are uncertain)."""
        return self.closure is not None and self.closure.accepted_reason is not None

    def height_check_failures(self) -> tuple[Wall, ...]:
        """Walls whose printed height is not the max of their two vertex heights."""
        return tuple(w for w in self.walls if not w.height_check_ok)


@dataclass(frozen=True)
class Site:
    """Everything the planner knows about the object and the survey asked for."""

    name: str
    zones: tuple[Zone, ...]
    parameters: Parameters = field(default_factory=Parameters)
    instrument: str = "leica-p30"
    obstacles: tuple[Obstacle, ...] = ()
    no_go_areas: tuple[NoGoArea, ...] = ()
    boundary: tuple[tuple[float, float], ...] | None = None
    control_points: tuple[ControlPoint, ...] = ()
    corrections: tuple[Correction, ...] = ()
    accepted_misclosures: tuple[AcceptedMisclosure, ...] = ()
    source: str = ""
    #: vertical connections between zones of two storeys (read from a building model; none elsewhere)
    stairs: tuple[Stair, ...] = ()

    def __post_init__(self) -> None:
        file = self.source or None
        if not self.zones:
            raise InputError("a site needs at least one zone", file=file, field="zones", value=0)
        seen: set[str] = set()
        for z in self.zones:
            if z.id in seen:
                raise InputError("duplicate zone id", file=file, zone=z.id, field="id", value=z.id)
            seen.add(z.id)
        names = (c.name for c in self.control_points)
        no_repeats(names, what="control point name", field="name", row="control_points[{}]", file=file)
        self._check_drawn_twice()
        for stair in self.stairs:
            for zid in (z for z in stair.zones if z not in seen):
                raise InputError(
                    "a stair names a zone the site does not have", file=file, field=f"stair {stair.name}", value=zid
                )
        if self.boundary is not None:
            check_simple_polygon(np.asarray(self.boundary, float), what="boundary")

    def _check_drawn_twice(self) -> None:
        """Refuse a zone drawn twice (the same outline and holes, scanned from the same side in the same frame):
        its walls would count twice in every report. Inside and outside zones on one outline are two zones, and
        so are alike rooms in different frames; a ``both`` zone repeats an ``inside`` or ``outside`` one."""
        first: dict[tuple[object, ...], str] = {}
        for z in self.zones:
            shape = (
                z.frame,
                ring_key(np.asarray(z.vertices, float)),
                tuple(sorted(ring_key(np.asarray(h, float)) for h in z.holes)),
            )
            for side in z.scan_side.sides:
                key = (side.value, *shape)
                if key in first:
                    raise InputError(
                        f"drawn twice: the same outline as zone {first[key]!r}, both scanned from {side.value}",
                        file=self.source or None,
                        zone=z.id,
                        field="outline",
                    )
                first[key] = z.id

    def with_parameters(self, **changes: object) -> Site:
        """The same site with some parameters changed (validated), e.g. ``site.with_parameters(theta_max_deg=60)``."""
        return replace(self, parameters=replace(self.parameters, **changes))  # type: ignore[arg-type]

    def zone(self, zone_id: str) -> Zone:
        return {z.id: z for z in self.zones}[zone_id]

    @property
    def walls(self) -> tuple[Wall, ...]:
        return tuple(w for z in self.zones for w in z.walls)
