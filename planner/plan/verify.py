"""Independent re-verification of any plan on a fine sampling of every wall.

The planner covers wall *pieces* (``target_spacing_m``); verification instead samples *points* every ``spacing_m``
(0.1 m by default) along every scanned wall face and asks, point by point, whether some station sees it within the
limits. It shares only the low-level sight test with planning, so a plan made elsewhere (or the published one) is
checked the same way. In combined precision (``limits.precision.combined``) a point counts as covered only when
the views that see it add up to sigma_req (:mod:`planner.solve.combined`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict, dataclass

import numpy as np

from planner.candidates.final_step import misplacement
from planner.core.checks import SAMPLING_M, argument
from planner.core.errors import InputError
from planner.core.text import table
from planner.coverage.sight import Sight
from planner.coverage.targets import SIDE_NAME, make_targets
from planner.site.candidate import Candidate, check_unique_ids, stations_argument


@dataclass(frozen=True)
class ZoneSideCoverage:
    zone: str
    side: str
    points: int
    covered: int

    @property
    def percent(self) -> float:
        return 100.0 * self.covered / self.points if self.points else 100.0


@dataclass(frozen=True)
class Gap:
    """An uncovered stretch of a wall face, in metres from the wall's first vertex."""

    zone: str
    side: str
    wall: int
    from_m: float
    to_m: float


@dataclass(frozen=True, kw_only=True)
class VerifyReport:
    spacing_m: float
    zones: tuple[ZoneSideCoverage, ...]
    gaps: tuple[Gap, ...]
    misplaced: tuple[tuple[str, str], ...]  # (station id, reason)
    precision: str = "single"  # how the point error was judged: single view, combined views, or off

    @property
    def percent(self) -> float:
        pts = sum(z.points for z in self.zones)
        return 100.0 * sum(z.covered for z in self.zones) / pts if pts else 100.0

    @property
    def complete(self) -> bool:
        return not self.gaps and not self.misplaced

    def to_dict(self) -> dict:
        return {
            "spacing_m": self.spacing_m,
            "percent": self.percent,
            "complete": self.complete,
            "precision": self.precision,
            "zones": [{**asdict(z), "percent": z.percent} for z in self.zones],
            "gaps": [asdict(g) for g in self.gaps],
            "misplaced": [{"station": s, "reason": r} for s, r in self.misplaced],
        }

    def _repr_html_(self) -> str:
        from planner.core.text import summary_html

        return summary_html(self, "Verification")

    def summary(self) -> str:
        """The verification for the terminal: covered share, a table of zone-sides (in the order of the site's
        zones), the uncovered stretches (30 at most) and the misplaced stations."""
        mode = " (combined precision)" if self.precision == "combined" else ""
        lines = [f"verification at {self.spacing_m:g} m{mode}: {self.percent:.3f} % covered"]
        rows = [(z.zone, z.side, z.points, z.covered, f"{z.percent:.3f}") for z in self.zones]
        lines += table(["zone", "side", "points", "covered", "covered %"], rows)
        if self.gaps:
            lines.append(f"uncovered stretches ({len(self.gaps)}), in metres from the wall's first vertex:")
            shown = [(g.zone, g.side, g.wall, f"{g.from_m:.2f}", f"{g.to_m:.2f}") for g in self.gaps[:30]]
            lines += table(["zone", "side", "wall", "from m", "to m"], shown)
            if len(self.gaps) > 30:
                lines.append(f"  ... and {len(self.gaps) - 30} more")
        lines += [f"misplaced station {s}: {r}" for s, r in self.misplaced]
        return "\n".join(lines)


def verify_stations(sight: Sight, stations: Sequence[Candidate], spacing_m: float = 0.1) -> VerifyReport:
    """Coverage of every wall face of ``sight.site`` by ``stations`` under ``sight.limits``, sampled every
    ``spacing_m``, with gaps and misplaced stations."""
    argument(sight, Sight, "sight")
    site, limits = sight.site, sight.limits
    stations_argument(stations)
    check_unique_ids(stations)
    if not (isinstance(spacing_m, (int, float)) and SAMPLING_M[0] <= spacing_m <= SAMPLING_M[1]):  # as --spacing
        raise InputError(
            "sampling must be 0.001 .. 10 m (finer is no survey resolution, coarser checks little)",
            field="spacing_m",
            value=spacing_m,
        )
    misplaced = tuple((s.id, why) for s in stations if (why := misplacement(site, s, s.x, s.y)))
    bad = {m for m, _ in misplaced}
    usable = [s for s in stations if s.id not in bad]
    pts = make_targets(site, spacing_m, points=True)
    cov = sight.coverage(usable, pts, step="verification")
    seen = np.diff(cov.by_target.indptr) > 0
    rule = limits.precision
    if rule is not None and rule.combined:  # views add information: seen is not enough
        from planner.solve.combined import information, information_met

        seen &= information_met(information(cov, rule), list(range(len(usable))))
    zones, gaps = [], []
    for zi, zid in enumerate(pts.zone_ids):
        for side in (0, 1):
            mask = (pts.zone == zi) & (pts.side == side)
            if not mask.any():
                continue
            zones.append(ZoneSideCoverage(zid, SIDE_NAME[side], int(mask.sum()), int(seen[mask].sum())))
            for wall in np.unique(pts.wall[mask]):
                idx = np.flatnonzero(mask & (pts.wall == wall))
                gaps += _runs(zid, SIDE_NAME[side], int(wall), pts.s0_m[idx], ~seen[idx])
    mode = "off" if rule is None else "combined" if rule.combined else "single"
    return VerifyReport(spacing_m=spacing_m, zones=tuple(zones), gaps=tuple(gaps), misplaced=misplaced, precision=mode)


def _runs(zone: str, side: str, wall: int, s: np.ndarray, miss: np.ndarray) -> list[Gap]:
    """Merge consecutive uncovered sample points into stretches."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], miss.astype(np.int8), [0]])))
    return [Gap(zone, side, wall, float(s[a]), float(s[b - 1])) for a, b in zip(edges[::2], edges[1::2])]
