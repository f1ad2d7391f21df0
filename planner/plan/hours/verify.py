"""Independent check of the point spacing a plan gives every wall.

Verification samples points every ``spacing_m`` along every wall face (as :mod:`planner.plan.verify` does) and,
for each point, takes the finest spacing any station that sees it gives it at that station's setting, over the
wall's whole height at that point (:func:`planner.coverage.spacing.point_spacing_m`: the point's own geometry,
not the planning pieces' bound). A point meets the spacing when that is at most the asked maximum.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict, dataclass

import numpy as np

from planner.core.text import table
from planner.coverage.sight import Sight
from planner.coverage.spacing import point_spacing_m
from planner.coverage.targets import SIDE_NAME, make_targets
from planner.instrument.field_table import FieldProperties
from planner.plan.hours.columns import REL_TOL
from planner.site.candidate import Candidate


@dataclass(frozen=True)
class WallSpacing:
    """One wall face: its sample points, how many meet the spacing, and the coarsest spacing among the points
    (each point's finest over the stations that see it; inf where a point is seen by none)."""

    zone: str
    side: str
    wall: int
    points: int
    meeting: int
    worst_m: float


@dataclass(frozen=True, kw_only=True)
class SpacingReport:
    max_spacing_m: float
    spacing_m: float
    walls: tuple[WallSpacing, ...]

    @property
    def points(self) -> int:
        return sum(w.points for w in self.walls)

    @property
    def percent(self) -> float:
        n = self.points
        return 100.0 * sum(w.meeting for w in self.walls) / n if n else 100.0

    @property
    def worst_m(self) -> float:
        return max((w.worst_m for w in self.walls), default=0.0)

    @property
    def complete(self) -> bool:
        return all(w.meeting == w.points for w in self.walls)

    def to_dict(self) -> dict[str, object]:
        return {
            "max_point_spacing_m": self.max_spacing_m,
            "sampling_m": self.spacing_m,
            "percent": self.percent,
            "complete": self.complete,
            "worst_m": _finite(self.worst_m),
            "walls": [{**asdict(w), "worst_m": _finite(w.worst_m)} for w in self.walls],
        }

    def lines(self) -> list[str]:
        """The check for the terminal: the share of points meeting, the coarsest spacing, the walls that miss."""
        lines = [
            f"point spacing verified at {self.spacing_m:g} m: {self.percent:.3f} % of {self.points:,} points at most "
            f"{1e3 * self.max_spacing_m:g} mm (coarsest reached {_mm(self.worst_m)})"
        ]
        missing = [w for w in self.walls if w.meeting < w.points]
        if missing:
            rows = [(w.zone, w.side, w.wall, w.points - w.meeting, _mm(w.worst_m)) for w in missing[:30]]
            lines += table(["zone", "side", "wall", "points over", "coarsest"], rows)
        return lines


def verify_spacing(
    sight: Sight,
    stations: Sequence[Candidate],
    settings: Sequence[str],
    props: FieldProperties,
    max_spacing_m: float,
    spacing_m: float = 0.1,
) -> SpacingReport:
    """The spacing every wall point gets from ``stations`` at their ``settings`` (aligned), checked against
    ``max_spacing_m``, sampled every ``spacing_m``."""
    if len(settings) != len(stations):
        raise ValueError(f"{len(settings)} settings for {len(stations)} stations")
    site = sight.site
    pts = make_targets(site, spacing_m, points=True)
    best = np.full(len(pts), np.inf)
    if stations:
        cov = sight.coverage(list(stations), pts, step="spacing verification")
        m = cov.by_candidate.tocsr()
        rows = np.repeat(np.arange(m.shape[0]), np.diff(m.indptr))
        cols = m.indices
        steps = np.array([props.step_rad(s) for s in settings], dtype=float)
        xy = np.array([s.xy for s in stations], dtype=float).reshape(-1, 2)
        top = np.maximum(pts.ha_m, pts.hb_m)
        ih = sight.limits.instrument_height_m
        values = point_spacing_m(xy[rows], pts.a[cols], pts.normal[cols], top[cols], ih, steps[rows])
        np.minimum.at(best, cols, values)
    meets = best <= max_spacing_m * (1 + REL_TOL)
    walls = []
    key = np.stack([pts.zone, pts.side, pts.wall], axis=1)
    for z, s, w in np.unique(key, axis=0):
        mask = (pts.zone == z) & (pts.side == s) & (pts.wall == w)
        n, meeting, worst = int(mask.sum()), int(meets[mask].sum()), float(best[mask].max())
        walls.append(WallSpacing(pts.zone_ids[int(z)], SIDE_NAME[int(s)], int(w), n, meeting, worst))
    return SpacingReport(max_spacing_m=max_spacing_m, spacing_m=spacing_m, walls=tuple(walls))


def _finite(v: float) -> float | None:
    return float(v) if np.isfinite(v) else None


def _mm(v: float) -> str:
    return f"{1e3 * v:.2f} mm" if np.isfinite(v) else "unseen"
