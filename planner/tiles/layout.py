"""Tiles of a large site: square cores that partition the targets, each with a margin of S_max.

Every target (wall piece) belongs to the one tile whose core holds its zone's anchor (the centre of the zone's bounding
box), so an object is never cut between tiles. A station that sees a piece stands within the horizontal reach of it,
which is at most the slant range S_max, so the candidates within S_max of the bounding box of a tile's pieces (its
margin) are all the candidates that can see any of them: the coverage columns of a tile, built from those candidates
only, are exactly the site's columns of those pieces, and the tiles' columns together are the site's matrix.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from planner.core.errors import UsageError
from planner.coverage.targets import Targets
from planner.site.model import Site


@dataclass(frozen=True)
class Tile:
    """Core square ``[x0_m, x0_m + size_m) x [y0_m, y0_m + size_m)`` with a margin of ``margin_m``."""

    index: int
    row: int
    col: int
    x0_m: float
    y0_m: float
    size_m: float
    margin_m: float

    @property
    def name(self) -> str:
        return f"tile r{self.row}c{self.col}"

    def in_core(self, xy: NDArray[np.float64]) -> NDArray[np.bool_]:
        x, y = xy[:, 0], xy[:, 1]
        return (x >= self.x0_m) & (x < self.x0_m + self.size_m) & (y >= self.y0_m) & (y < self.y0_m + self.size_m)

    def in_margin(self, xy: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Points within ``margin_m`` (Euclidean) of the core square."""
        dx = np.maximum(np.maximum(self.x0_m - xy[:, 0], xy[:, 0] - self.x0_m - self.size_m), 0.0)
        dy = np.maximum(np.maximum(self.y0_m - xy[:, 1], xy[:, 1] - self.y0_m - self.size_m), 0.0)
        return np.hypot(dx, dy) <= self.margin_m


@dataclass(frozen=True)
class TileJob:
    """A tile with the global indices of its candidates (those within the margin) and of its core targets."""

    tile: Tile
    candidates: NDArray[np.int64]
    targets: NDArray[np.int64]


def make_tiles(points: NDArray[np.float64], size_m: float, margin_m: float) -> list[Tile]:
    """Square tiles of ``size_m`` over the bounding box of ``points`` (the pieces' zone anchors), row by row; a tile
    holding no point is dropped."""
    if not (math.isfinite(size_m) and size_m > 0):
        raise UsageError("must be > 0", field="tile_m", value=size_m)
    if margin_m < 0:
        raise UsageError("tile size must be > 0 and margin >= 0", field="tile_m", value=size_m)
    lo = points.min(axis=0)
    hi = points.max(axis=0)
    nx = max(1, math.floor((hi[0] - lo[0]) / size_m) + 1)
    ny = max(1, math.floor((hi[1] - lo[1]) / size_m) + 1)
    tiles: list[Tile] = []
    for r in range(ny):
        for c in range(nx):
            t = Tile(len(tiles), r, c, float(lo[0] + c * size_m), float(lo[1] + r * size_m), size_m, margin_m)
            if t.in_core(points).any():
                tiles.append(replace(t, index=len(tiles)))
    return tiles


def zone_anchors(site: Site, targets: Targets) -> NDArray[np.float64]:
    """Per piece, the centre of its zone's bounding box (the point that decides its tile)."""
    centres = np.array([[(b[0] + b[2]) / 2, (b[1] + b[3]) / 2] for b in (z.polygon.bounds for z in site.zones)])
    return centres[np.asarray(targets.zone)]


def tile_job(
    tile: Tile, anchor: NDArray[np.float64], targets: Targets, xy: NDArray[np.float64], usable: NDArray[np.bool_]
) -> TileJob:
    """The tile's pieces (anchor in its core) and the usable candidates within ``margin_m`` of their box."""
    ti = np.flatnonzero(tile.in_core(anchor))
    ends = np.vstack([np.asarray(targets.a)[ti], np.asarray(targets.b)[ti]])
    (x0, y0), (x1, y1) = ends.min(axis=0), ends.max(axis=0)
    box = replace(tile, x0_m=float(x0), y0_m=float(y0), size_m=float(max(x1 - x0, y1 - y0, 1e-9)))
    # in_margin of a square: a box of unequal sides is widened to a square; still a superset (exact margin)
    return TileJob(tile, np.flatnonzero(box.in_margin(xy) & usable), ti)
