"""Targets: every wall face on a zone's scan side, cut into pieces of at most ``spacing_m``."""

from __future__ import annotations

import math
from collections import defaultdict
from dataclasses import dataclass, fields

import numpy as np
from numpy.typing import NDArray

from planner.coverage.openings import opening_segments, solid_intervals, wall_gaps
from planner.site.geometry import read_only
from planner.site.model import ScanSide, Site

SIDE_CODE = {ScanSide.INSIDE: 0, ScanSide.OUTSIDE: 1}
SIDE_NAME = {0: "inside", 1: "outside"}


@dataclass(frozen=True, eq=False)
class PieceArrays:
    """Targets as parallel arrays, one entry per piece; ``zone`` indexes ``site.zones``, ``frame`` indexes ``frames``
    (the zones' frames in site order). Every array field is stored read-only (the target arrays are shared, never
    changed)."""

    zone: NDArray[np.int32]
    frame: NDArray[np.int32]
    frames: tuple[str, ...]
    zone_ids: tuple[str, ...]

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if isinstance(value, np.ndarray):
                object.__setattr__(self, f.name, read_only(value))

    def __len__(self) -> int:
        return len(self.zone)


@dataclass(frozen=True, eq=False)
class Targets(PieceArrays):
    """Wall-face pieces as parallel read-only arrays (one entry per piece). ``side`` is 0 inside / 1 outside; ``wall``
    the 1-based wall index; ``s0_m``/``s1_m`` the piece's offsets along the wall; ``a``/``b`` its end points;
    ``ha_m``/``hb_m`` the top heights there; ``normal`` the unit normal to the scanning side; ``frame`` indexes
    ``frames``. A piece with ``a == b`` is a point (verify)."""

    side: NDArray[np.int8]
    wall: NDArray[np.int32]
    s0_m: NDArray[np.float64]
    s1_m: NDArray[np.float64]
    a: NDArray[np.float64]
    b: NDArray[np.float64]
    ha_m: NDArray[np.float64]
    hb_m: NDArray[np.float64]
    normal: NDArray[np.float64]

    def label(self, t: int) -> str:
        """A readable id: zone/side/wall and the piece's offsets."""
        return (
            f"{self.zone_ids[self.zone[t]]}/{SIDE_NAME[int(self.side[t])]}/wall {self.wall[t]}"
            f" {self.s0_m[t]:.2f}-{self.s1_m[t]:.2f} m"
        )

    def midpoint(self, t: int) -> tuple[float, float]:
        m = (self.a[t] + self.b[t]) / 2.0
        return float(m[0]), float(m[1])


def _cuts(
    length_m: float, gaps: list[tuple[float, float]], spacing_m: float, points: bool
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Piece ends (fractions of the wall) over the solid parts of a wall: each part cut into equal pieces."""
    t0, t1 = [], []
    for lo, hi in solid_intervals(length_m, gaps):
        m = max(1, math.ceil((hi - lo) / spacing_m - 1e-9))
        cuts = np.linspace(lo, hi, m + 1) / length_m
        t0.append(cuts if points else cuts[:-1])
        t1.append(cuts if points else cuts[1:])
    if not t0:
        return np.zeros(0), np.zeros(0)
    return np.concatenate(t0), np.concatenate(t1)


def make_targets(site: Site, spacing_m: float, points: bool = False) -> Targets:
    """Cut every scanned wall face into equal pieces no longer than ``spacing_m``; each solid part between openings is
    cut on its own. With ``points=True``: the pieces' end points instead (zero-length pieces), the fine sampling of
    verification."""
    if not math.isfinite(spacing_m) or spacing_m <= 0:
        raise ValueError(f"target spacing must be > 0, got {spacing_m}")
    frames = tuple(dict.fromkeys(z.frame for z in site.zones))
    cols: defaultdict[str, list] = defaultdict(list)  # Targets' array fields
    openings = {f: opening_segments(site, f) for f in frames}
    for zi, zone in enumerate(site.zones):
        for wall in zone.walls:
            length = wall.length_m
            t0, t1 = _cuts(length, wall_gaps(site, zi, wall, openings[zone.frame]), spacing_m, points)
            start, end = np.asarray(wall.start), np.asarray(wall.end)
            tangent = (end - start) / length
            left = np.array([-tangent[1], tangent[0]])
            for side in zone.scan_side.sides:
                k = len(t0)
                cols["zone"].append(np.full(k, zi, np.int32))
                cols["side"].append(np.full(k, SIDE_CODE[side], np.int8))
                cols["wall"].append(np.full(k, wall.index, np.int32))
                cols["s0_m"].append(t0 * length)
                cols["s1_m"].append(t1 * length)
                cols["a"].append(start + np.outer(t0, end - start))
                cols["b"].append(start + np.outer(t1, end - start))
                cols["ha_m"].append(wall.height_at(t0))
                cols["hb_m"].append(wall.height_at(t1))
                cols["normal"].append(np.tile(left if side is ScanSide.INSIDE else -left, (k, 1)))
                cols["frame"].append(np.full(k, frames.index(zone.frame), np.int32))
    cat = {k: np.concatenate(v) for k, v in cols.items()}
    return Targets(**cat, frames=frames, zone_ids=tuple(z.id for z in site.zones))
