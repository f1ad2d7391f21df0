"""The property both region test files check: regions R_t against the coverage test on given positions."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp
import shapely

from planner.coverage.matrix import build_coverage
from planner.coverage.targets import Targets
from planner.coverage.visibility import SightLimits
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import Site


def probe_candidates(site: Site, pts: np.ndarray) -> list[Candidate]:
    """Candidates at ``pts`` on the first zone's (first) scan side."""
    zone = site.zones[0]
    return [
        Candidate(f"p{i}", zone.id, zone.scan_side.sides[0], zone.frame, float(x), float(y), CandidateKind.GRID)
        for i, (x, y) in enumerate(pts)
    ]


def assert_regions_match(
    site: Site, targets: Targets, limits: SightLimits, regions: Sequence[shapely.Geometry], pts: np.ndarray, tol: float
) -> tuple[int, sp.csr_matrix]:
    """Inside R_t => the coverage test accepts; accepted and farther than ``tol`` from R_t's boundary => inside R_t.
    Returns how many (position, piece) pairs fell inside some R_t and the coverage by piece."""
    covered = build_coverage(site, probe_candidates(site, pts), targets, limits).by_target
    points = shapely.points(pts)
    seen_inside = 0
    for t in range(len(targets)):
        r = regions[t]
        inside = shapely.contains_xy(r, pts[:, 0], pts[:, 1]) if not r.is_empty else np.zeros(len(pts), bool)
        cov = np.zeros(len(pts), bool)
        cov[covered.indices[covered.indptr[t] : covered.indptr[t + 1]]] = True
        assert not np.any(inside & ~cov), f"{targets.label(t)}: a point of R_t fails the coverage test"
        far = shapely.distance(r.boundary, points) > tol if not r.is_empty else np.ones(len(pts), bool)
        assert not np.any(cov & ~inside & far), f"{targets.label(t)}: a covering point lies outside R_t"
        seen_inside += int(inside.sum())
    return seen_inside, covered
