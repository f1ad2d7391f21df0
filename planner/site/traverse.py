"""Zones given as closed traverses (tables 3.1 and 4.3): closure, Bowditch adjustment.

Frame of a table zone: vertex 1 at (0, 0), side 1 along +x, walking counter-clockwise; row i gives side i
and the interior angle and height of vertex i (the START of side i); the walk turns left by 180 deg - angle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from planner.core.errors import ClosureError, InputError
from planner.site.params import ClosureTolerance

SCAN_SIDES = ("inside", "outside", "both")


@dataclass(frozen=True)
class TableRow:
    """One row of a zone table: side ``index`` and the vertex at its start."""

    index: int
    side_length_m: float
    wall_height_m: float
    interior_angle_deg: float
    vertex_height_m: float
    line: int | None = None  # line in the source file, for messages

    def check_ranges(self, zone: str, file: str | None) -> None:
        """Refuse zero/negative lengths and heights and angles outside (0, 360)."""
        for name in ("side_length_m", "wall_height_m", "vertex_height_m"):
            v = getattr(self, name)
            if v <= 0:
                raise InputError("must be > 0", file=file, zone=zone, row=self.index, field=name, value=v)
        a = self.interior_angle_deg
        if not 0.0 < a < 360.0:
            raise InputError(
                "outside (0, 360) degrees", file=file, zone=zone, row=self.index, field="interior_angle_deg", value=a
            )


@dataclass(frozen=True)
class ZoneTable:
    """A zone as printed: id, scan side and its rows in index order."""

    zone: str
    scan_side: str
    rows: tuple[TableRow, ...]
    file: str | None = None


@dataclass(frozen=True)
class AcceptedMisclosure:
    """An instance's explicit acceptance of a zone that does not close, with its reason; its figures must
    match what the loader computes (to 0.001 deg and 1 mm), so it never covers data it was not written for."""

    zone: str
    angular_misclosure_deg: float
    linear_misclosure_m: float
    reason: str

    def matches(self, angular_deg: float, linear_m: float) -> bool:
        return (
            abs(angular_deg - self.angular_misclosure_deg) <= 0.001
            and abs(linear_m - self.linear_misclosure_m) <= 0.001
        )


@dataclass(frozen=True)
class ClosureReport:
    """How a traverse closed and what the adjustment did."""

    n: int
    angle_sum_deg: float
    angular_misclosure_deg: float
    misclosure_dx_m: float
    misclosure_dy_m: float
    perimeter_m: float
    max_vertex_shift_m: float
    accepted_reason: str | None = None

    @property
    def linear_misclosure_m(self) -> float:
        return math.hypot(self.misclosure_dx_m, self.misclosure_dy_m)

    @property
    def relative_precision(self) -> float:
        """N of 1:N (perimeter / linear misclosure); inf when it closes exactly."""
        lin = self.linear_misclosure_m
        return math.inf if lin == 0 else self.perimeter_m / lin

    def summary(self) -> str:
        n = self.relative_precision
        ratio = "exact" if math.isinf(n) or n > 1e9 else f"1:{n:,.0f}"
        linear = f"linear {self.linear_misclosure_m * 1000:.1f} mm ({ratio})"
        return f"angles {self.angular_misclosure_deg:+.4f} deg, {linear}" + (
            " [accepted]" if self.accepted_reason else ""
        )


def walk(lengths: NDArray[np.float64], angles_deg: NDArray[np.float64]) -> NDArray[np.float64]:
    """Vertices 1..n+1 of the open walk (vertex n+1 should coincide with vertex 1)."""
    turns = 180.0 - angles_deg
    turns[0] = 0.0  # side 1 along +x
    heading = np.radians(np.cumsum(turns))
    steps = lengths[:, None] * np.stack([np.cos(heading), np.sin(heading)], axis=1)
    return np.vstack([np.zeros((1, 2)), np.cumsum(steps, axis=0)])


def reconstruct(
    table: ZoneTable, tolerance: ClosureTolerance, accepted: AcceptedMisclosure | None = None
) -> tuple[NDArray[np.float64], ClosureReport]:
    """Vertices (n, 2) of a table zone and its closure report. The angular misclosure is spread equally over the angles,
    the linear one by the compass rule (vertex k moves by -misclosure * (length walked to k) / perimeter). Beyond
    tolerance a ClosureError names the zone and the figures, unless ``accepted`` records exactly these figures."""
    rows = table.rows
    n = len(rows)
    if n < 3:
        raise InputError("a zone needs at least 3 sides", file=table.file, zone=table.zone, field="rows", value=n)
    lengths = np.array([r.side_length_m for r in rows])
    angles = np.array([r.interior_angle_deg for r in rows])
    angle_sum = float(angles.sum())
    ang_mis = angle_sum - (n - 2) * 180.0
    points = walk(lengths, angles - ang_mis / n)
    dx, dy = points[-1] - points[0]
    perimeter = float(lengths.sum())
    lin = math.hypot(dx, dy)
    rel = math.inf if lin == 0 else perimeter / lin
    why = ""
    if abs(ang_mis) > tolerance.angular_deg and accepted is None:
        why = (
            f"angular misclosure {ang_mis:+.3f} deg (sum {angle_sum:.3f} vs {(n - 2) * 180:.0f} for {n} vertices), "
            f"tolerance {tolerance.angular_deg:g} deg"
        )
    elif rel < tolerance.min_relative_precision and accepted is None:
        why = (
            f"linear misclosure {lin:.3f} m (dx {dx:+.3f}, dy {dy:+.3f}), relative 1:{rel:.0f}, "
            f"required 1:{tolerance.min_relative_precision:.0f}"
        )
    elif accepted is not None and not accepted.matches(ang_mis, lin):
        why = (
            f"accepted misclosure ({accepted.angular_misclosure_deg:+.3f} deg, {accepted.linear_misclosure_m:.3f} m) "
            f"does not match the data ({ang_mis:+.3f} deg, {lin:.3f} m)"
        )
    if why:
        raise ClosureError(why, file=table.file, zone=table.zone)
    walked = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
    shift = -np.outer(walked / perimeter, [dx, dy])
    vertices = points[:-1] + shift
    report = ClosureReport(
        n=n,
        angle_sum_deg=angle_sum,
        angular_misclosure_deg=ang_mis,
        misclosure_dx_m=float(dx),
        misclosure_dy_m=float(dy),
        perimeter_m=perimeter,
        max_vertex_shift_m=float(np.hypot(*shift.T).max()),
        accepted_reason=accepted.reason if accepted else None,
    )
    return vertices, report


def table_from_polygon(xy: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Side lengths and interior angles (deg) of a counter-clockwise polygon, the inverse of :func:`walk`. Angle i is at
    vertex i, between side i-1 (arriving) and side i (leaving)."""
    d = np.roll(xy, -1, axis=0) - xy
    lengths = np.hypot(d[:, 0], d[:, 1])
    heading = np.degrees(np.arctan2(d[:, 1], d[:, 0]))
    turn = (heading - np.roll(heading, 1) + 180.0) % 360.0 - 180.0  # left turn at vertex i
    return lengths, 180.0 - turn
