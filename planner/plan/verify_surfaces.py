"""Verification of floors and ceilings, point by point, independent of :mod:`planner.coverage.surface_sight`.

Each floor and ceiling of each zone is sampled on a grid (cell centres every ``spacing_m``, the verify spacing;
coarsened where a surface would pass :data:`MAX_POINTS` points, and the report says so). A point counts as covered
when some planned station sees it:

- the station stands on the same zone's floor (scanned from inside, outside every block);
- the slant range from the instrument (the floor level plus the instrument height) to the point is <= S_max;
- the incidence, the angle between the ray and the surface's normal, atan(d / |dz|) for horizontal distance d and
  height difference dz, is <= the surface's limit (``theta_max_floor_deg``, else theta_max), with the floor below
  the instrument and the ceiling above it;
- the ray is outside the blind cone: its angle from the nadir (floors) or the zenith (ceilings) is >= the model's
  half angle;
- in plan, the segment from the station to the point keeps inside the zone's outline and out of its blocks (every
  block for a floor, those above the instrument for a ceiling), shapely ``covered_by`` vectorised.

It shares with planning only the surfaces' areas (what is a target) and the limits' values. What the plan left out is
never counted as covered: a point inside a patch no candidate sees whole (left out of the cover) counts as uncovered
even where the planned stations happen to see it, so the share and the "complete" claim hold only for what was planned;
a surface type asked for that the site does not have is named, and claims nothing.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from planner.core import progress
from planner.core.text import table
from planner.coverage.surfaces import CEILING, FLOOR, KIND_CODE, surface_areas, zone_blocks
from planner.plan.surfaces import SurfaceCover, SurfaceSetup
from planner.site.candidate import Candidate
from planner.site.model import ScanSide, Site

#: the most sample points of one zone's surface; a finer grid is coarsened to it
MAX_POINTS = 4_000_000
#: slack of the plan-view test (a segment grazing a wall or block corner is clear)
EPS_M = 1e-6
#: seconds between two progress reports of the verification
PROGRESS_S = 2.0


@dataclass(frozen=True)
class SurfaceCoverage:
    """Sample points of one zone's floor or ceiling and how many some station sees (``spacing_m``: the grid's);
    ``left_out``: the points in patches no candidate sees, counted as not covered (``covered`` holds none of them)."""

    zone: str
    kind: str
    points: int
    covered: int
    spacing_m: float
    left_out: int = 0

    @property
    def percent(self) -> float:
        return 100.0 * self.covered / self.points if self.points else 100.0


@dataclass(frozen=True, kw_only=True)
class SurfaceReport:
    """The floors and ceilings of a plan: the kinds planned, the patches and their area, the patches no candidate
    saw (left out of the cover, and not covered), the point-wise verification per zone and kind, and the kinds asked
    for that the site has none of (``absent``: they plan and verify nothing)."""

    kinds: tuple[str, ...]
    patches: int
    patch_area_m2: float
    instrument_height_m: float
    theta_max_floor_deg: float
    unseen: dict[str, Any] | None
    spacing_m: float
    rows: tuple[SurfaceCoverage, ...]
    notes: tuple[str, ...] = field(default_factory=tuple)
    absent: tuple[str, ...] = ()

    @property
    def percent(self) -> float:
        pts = sum(r.points for r in self.rows)
        return 100.0 * sum(r.covered for r in self.rows) / pts if pts else 0.0

    @property
    def left_out(self) -> dict[str, Any]:
        """The patches left out of the plan (no candidate sees them whole): count, area (m2) and zones."""
        return dict(self.unseen or {"count": 0, "area_m2": 0.0, "zones": []})

    @property
    def complete(self) -> bool:
        """Something was verified, every sample point of every surface is covered, and no patch was left out."""
        return bool(self.rows) and all(r.covered == r.points for r in self.rows) and not self.left_out["count"]

    @property
    def state(self) -> str:
        """The claim in one word: ``complete``, ``INCOMPLETE``, or ``nothing verified`` (no asked surface exists)."""
        return "nothing verified" if not self.rows else "complete" if self.complete else "INCOMPLETE"

    def warnings(self) -> list[str]:
        """A line per surface type asked for that the site has none of."""
        return [f"warning: the site has no {k}s: --surfaces {k}s plans nothing" for k in self.absent]

    def to_dict(self) -> dict[str, Any]:
        return {
            "types": ["walls", *(k + "s" for k in self.kinds)],
            "patches": self.patches,
            "patch_area_m2": self.patch_area_m2,
            "instrument_height_m": self.instrument_height_m,
            "theta_max_floor_deg": self.theta_max_floor_deg,
            "unseen_patches": self.unseen,
            "absent_types": [k + "s" for k in self.absent],
            "verification": {
                "spacing_m": self.spacing_m,
                "percent": self.percent,
                "complete": self.complete,
                "state": self.state,
                "left_out": self.left_out,
                "zones": [{"zone": r.zone, "type": r.kind, **_counts(r)} for r in self.rows],
                "notes": list(self.notes),
            },
        }

    def lines(self) -> list[str]:
        """The surfaces' verification for the terminal: the warnings, a line, a table per zone and kind, the patches
        left out, the notes."""
        if not self.rows:
            return [*self.warnings(), "surfaces verified: no floor or ceiling to verify (nothing verified)"]
        head = [
            f"surfaces verified at {self.spacing_m:g} m: {self.percent:.3f} % of floor/ceiling points covered "
            f"({self.state})"
        ]
        rows = [(r.zone, r.kind, r.points, r.covered, r.left_out, f"{r.percent:.3f}") for r in self.rows]
        out = self.warnings() + head + table(["zone", "surface", "points", "covered", "left out", "covered %"], rows)
        u = self.left_out
        if u["count"]:
            out.append(
                f"surface patches seen by no candidate: {u['count']}, {u['area_m2']:.2f} m2 NOT covered (left out of "
                f"the plan, their points counted uncovered) in {', '.join(u['zones'])}"
            )
        return out + list(self.notes)


def _counts(r: SurfaceCoverage) -> dict[str, Any]:
    return {
        "points": r.points,
        "covered": r.covered,
        "left_out": r.left_out,
        "percent": r.percent,
        "spacing_m": r.spacing_m,
    }


def _grid(area: shapely.Geometry, spacing_m: float) -> tuple[NDArray[np.float64], float]:
    """Cell centres of a grid of ``spacing_m`` over ``area``'s bounds that lie in it (the spacing coarsened so
    that the grid holds at most :data:`MAX_POINTS` points)."""
    x0, y0, x1, y1 = area.bounds
    h = max(spacing_m, math.sqrt((x1 - x0) * (y1 - y0) / MAX_POINTS))
    xs = x0 + h * (np.arange(max(1, math.ceil((x1 - x0) / h))) + 0.5)
    ys = y0 + h * (np.arange(max(1, math.ceil((y1 - y0) / h))) + 0.5)
    gx, gy = np.meshgrid(xs, ys)
    pts = np.column_stack([gx.ravel(), gy.ravel()])
    inside = shapely.contains_xy(area, pts[:, 0], pts[:, 1])
    return pts[inside], h


def _seen_by(
    station: NDArray[np.float64], pts: NDArray[np.float64], dz: float, setup: SurfaceSetup, kind: int, clear: Any
) -> NDArray[np.bool_]:
    """Which points one station sees (dz: the surface's height less the instrument's; ``clear`` None: no plan-view
    test, the caller knows every segment is clear)."""
    lim = setup.limits
    d = np.hypot(pts[:, 0] - station[0], pts[:, 1] - station[1])
    slant = np.hypot(d, dz)
    angle = np.degrees(np.arctan2(d, abs(dz)))  # from the normal, and from the nadir or zenith alike
    half = lim.nadir_blind_half_angle_deg if kind == FLOOR else lim.zenith_blind_half_angle_deg
    ok = (slant <= lim.max_slant_range_m + 1e-9) & (angle <= lim.theta_for(kind) + 1e-9)
    if half:
        ok &= angle >= half - 1e-9
    idx = np.flatnonzero(ok)
    if idx.size and clear is not None:
        segs = shapely.linestrings(np.stack([np.broadcast_to(station, (idx.size, 2)), pts[idx]], axis=1))
        ok[idx] = shapely.covered_by(segs, clear)
    return np.asarray(ok, dtype=bool)


def _covered(
    pts: NDArray[np.float64], stations: list[NDArray[np.float64]], dz: float, setup: SurfaceSetup, kind: int, clear: Any
) -> NDArray[np.bool_]:
    """Which of ``pts`` some station sees (:func:`_seen_by`'s rules). Each station tests only the points a k-d tree
    finds within its reach (range and incidence: no point farther is seen), and skips the plan-view test where its
    whole reach disc lies in ``clear`` (every segment from the centre to a point of a disc stays in the disc): the
    work grows with the points in reach, not with stations x points."""
    covered = np.zeros(len(pts), dtype=bool)
    if not stations or len(pts) == 0:
        return covered
    lim = setup.limits
    reach = math.sqrt(max(lim.max_slant_range_m**2 - dz**2, 0.0))
    theta = lim.theta_for(kind)
    if theta < 90.0:
        reach = min(reach, abs(dz) * math.tan(math.radians(theta)))
    reach += 1e-6
    tree = cKDTree(pts)
    rim = shapely.boundary(clear)
    shapely.prepare(clear)
    last = time.monotonic()
    for k, xy in enumerate(stations):
        near = np.asarray(tree.query_ball_point(xy, reach), dtype=np.int64)
        todo = near[~covered[near]]
        if todo.size:
            open_disc = bool(shapely.contains_xy(clear, *xy)) and shapely.distance(shapely.Point(xy), rim) > reach
            covered[todo] = _seen_by(xy, pts[todo], dz, setup, kind, None if open_disc else clear)
        if time.monotonic() - last >= PROGRESS_S:
            progress.report("verifying floors and ceilings", k + 1, len(stations))
            last = time.monotonic()
    return covered


def verify_surfaces(
    site: Site, setup: SurfaceSetup, cover: SurfaceCover | None, stations: Sequence[Candidate], spacing_m: float
) -> SurfaceReport:
    """The point-wise verification of the floors and ceilings of ``setup`` by ``stations``; ``cover``: the plan's
    patch columns, whose unseen patches the report lists (None: a plan checked alone, no pool)."""
    lim = setup.limits
    rows: list[SurfaceCoverage] = []
    notes: list[str] = []
    left = _left_out(setup, cover)
    for zi, zone in enumerate(site.zones):
        if ScanSide.INSIDE not in zone.scan_side.sides:
            continue
        outline = shapely.Polygon(zone.xy)
        blocks = zone_blocks(site, zi)
        stand = outline.difference(shapely.union_all([b for b, _ in blocks])) if blocks else outline
        stand = stand.buffer(EPS_M, join_style="mitre")
        here = [
            s
            for s in stations
            if s.side is ScanSide.INSIDE and s.frame == zone.frame and stand.covers(shapely.Point(s.xy))
        ]
        eye = zone.floor_level_m + lim.instrument_height_m
        for kind_name, area in surface_areas(site, zi).items():
            name = {FLOOR: "floor", CEILING: "ceiling"}[kind_name]
            if name not in setup.kinds or area.is_empty:
                continue
            kind = KIND_CODE[name]
            pts, h = _grid(area, spacing_m)
            if h > spacing_m:
                notes.append(
                    f"{zone.id}/{name}: sampled every {h:.3f} m, not {spacing_m:g} m ({MAX_POINTS:,} points at most)"
                )
            height = zone.floor_level_m + ((zone.ceiling_height_m or 0.0) if kind == CEILING else 0.0)
            dz = height - eye
            covered = np.zeros(len(pts), dtype=bool)
            progress.note(f"verifying {zone.id}/{name}: {len(pts):,} points every {h:g} m, {len(here)} stations")
            hiding = [b for b, top in blocks if kind == FLOOR or top > lim.instrument_height_m]
            clear = (outline.difference(shapely.union_all(hiding)) if hiding else outline).buffer(
                EPS_M, join_style="mitre"
            )
            if (dz < 0) if kind == FLOOR else (dz > 0):
                covered = _covered(pts, [np.asarray(s.xy, dtype=float) for s in here], dz, setup, kind, clear)
            out = left.get((zi, kind))
            gone = shapely.contains_xy(out, pts[:, 0], pts[:, 1]) if out is not None else np.zeros(len(pts), bool)
            if np.any(covered & gone):
                notes.append(
                    f"{zone.id}/{name}: {int((covered & gone).sum()):,} point(s) of patches left out are seen by the "
                    "stations but not counted (no candidate sees those patches whole)"
                )
            rows.append(SurfaceCoverage(zone.id, name, len(pts), int((covered & ~gone).sum()), h, int(gone.sum())))
    return SurfaceReport(
        kinds=setup.kinds,
        patches=len(setup.patches),
        patch_area_m2=float(setup.patches.total_area_m2()),
        instrument_height_m=lim.instrument_height_m,
        theta_max_floor_deg=lim.theta_for(FLOOR),
        unseen=None if cover is None else cover.unseen_dict(setup),
        spacing_m=spacing_m,
        rows=tuple(rows),
        notes=tuple(notes),
        absent=setup.absent,
    )


def _left_out(setup: SurfaceSetup, cover: SurfaceCover | None) -> dict[tuple[int, int], shapely.Geometry]:
    """The patches no candidate sees (left out of the cover), merged per (zone index, kind code)."""
    if cover is None or cover.unseen.size == 0:
        return {}
    p = setup.patches
    groups: dict[tuple[int, int], list[int]] = {}
    for t in cover.unseen:
        groups.setdefault((int(p.zone[t]), int(p.kind[t])), []).append(int(t))
    return {key: shapely.union_all(p.polygon[ts]) for key, ts in groups.items()}
