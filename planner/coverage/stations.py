"""What a set of stations does for the walls: per piece (how often seen, best incidence) and per station (covered wall,
worst incidence, longest range, worst predicted point error). Figures, the report and the exports all read this."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from planner.core.checks import argument
from planner.coverage.matrix import CoverageProblem
from planner.coverage.overlap import piece_lengths
from planner.coverage.sight import Sight
from planner.coverage.targets import Targets
from planner.instrument.accuracy import view_error_m
from planner.site.candidate import Candidate, stations_argument


@dataclass(frozen=True)
class StationStats:
    """One station's share of the plan (lengths in m, angles in degrees)."""

    id: str
    covered_m: float
    worst_incidence_deg: float
    longest_range_m: float
    worst_point_error_m: float


@dataclass(frozen=True, eq=False)
class StationCoverage:
    """Coverage of the wall pieces by a given list of stations. ``count[t]`` stations see piece t;
    ``best_incidence_deg[t]`` is the smallest (best) worst-over-the-piece incidence among them, NaN when none sees
    it."""

    stations: tuple[Candidate, ...]
    problem: CoverageProblem
    count: NDArray[np.int64]
    best_incidence_deg: NDArray[np.float64]
    per_station: tuple[StationStats, ...]

    @property
    def targets(self) -> Targets:
        return self.problem.targets

    @property
    def uncovered(self) -> NDArray[np.int64]:
        return np.flatnonzero(self.count == 0)

    @property
    def percent_length(self) -> float:
        """Covered share of the wall length, in %."""
        t = self.targets
        lengths = piece_lengths(t.s0_m, t.s1_m)
        total = float(lengths.sum())
        return 100.0 * float(lengths[self.count > 0].sum()) / total if total else 100.0


def station_coverage(sight: Sight, stations: Sequence[Candidate], spacing_m: float = 1.0) -> StationCoverage:
    """Build the coverage of ``stations`` alone on pieces of ``spacing_m`` under ``sight`` (its site's error budget, its
    scanner) and summarise it. Cost: one coverage build with len(stations) candidates, O(S x T) pair tests at most."""
    argument(sight, Sight, "sight")
    stations_argument(stations)
    st = tuple(stations)
    limits, scanner, budget = sight.limits, sight.scanner, sight.site.parameters.budget
    problem = sight.of_stations(st, spacing_m)
    t = problem.targets
    count = np.diff(problem.by_target.indptr).astype(np.int64)
    inc_t = problem.incidence_deg.T.tocsr()
    best = np.full(len(t), np.nan)
    for k in np.flatnonzero(count):
        best[k] = float(inc_t.data[inc_t.indptr[k] : inc_t.indptr[k + 1]].min())
    lengths = piece_lengths(t.s0_m, t.s1_m)
    stats = []
    for i, s in enumerate(st):
        lo, hi = problem.by_candidate.indptr[i], problem.by_candidate.indptr[i + 1]
        cols = problem.by_candidate.indices[lo:hi]
        if cols.size == 0:
            stats.append(StationStats(s.id, 0.0, float("nan"), float("nan"), float("nan")))
            continue
        slant = problem.slant_m.data[lo:hi]
        inc = problem.incidence_deg.data[lo:hi]
        e = view_error_m(slant, inc, scanner, budget, limits.precision.incidence_model if limits.precision else "none")
        stats.append(
            StationStats(s.id, float(lengths[cols].sum()), float(inc.max()), float(slant.max()), float(e.max()))
        )
    return StationCoverage(st, problem, count, best, tuple(stats))
