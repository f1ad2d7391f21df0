"""Complete candidates: no wall piece is refused while some position sees it.

A sampled pool can miss the only places from which a piece is seen (a narrow wing, a niche). Before any refusal, every
piece that no candidate sees gets a candidate from its own coverage region R_t: the pole (the point farthest from the
boundary) of R_t intersected with as many regions of the nearby unseen pieces as keep it non-empty, so that one
candidate serves a whole unseen stretch. The coverage test then decides; a piece still unseen after that gets the pole
of its own region alone. A piece is refused only when R_t is empty, with the rule that emptied it
(:func:`planner.coverage.regions.why_empty`), or when even the pole of R_t fails the coverage test (a region thinner
than the test's tolerance).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import shapely

from planner.candidates.closed_form import side_candidate
from planner.candidates.from_regions import largest_part_pole
from planner.coverage.matrix import CoverageProblem, merge_problems
from planner.coverage.regions import (
    FrameSpace,
    coverage_regions,
    frame_space,
    why_empty,
)
from planner.coverage.sight import Sight
from planner.site.candidate import CandidateKind
from planner.site.model import ScanSide

#: unseen pieces tried together (nearest first) when one candidate is sought for a stretch
NEIGHBOURS = 64
#: a region thinner than this (area) gives no usable pole
MIN_AREA_M2 = 1e-12
#: what a piece whose region is not empty but whose pole fails the coverage test is refused for
TOO_THIN = "its coverage region is thinner than the coverage test's tolerance"


def _stretch_poles(
    problem: CoverageProblem, unseen: Sequence[int] | np.ndarray, regions: dict[int, shapely.Geometry], alone: bool
) -> list[tuple[int, tuple[float, float]]]:
    """(owner piece, pole) for the unseen pieces with a region: each grouped with the nearest other unseen pieces of its
    zone-side whose regions still meet (``alone``: one pole per piece)."""
    t = problem.targets
    todo = [int(k) for k in unseen if not regions[int(k)].is_empty and regions[int(k)].area > MIN_AREA_M2]
    left = set(todo)
    mid = np.array([t.midpoint(k) for k in todo]).reshape(-1, 2)
    index = {k: i for i, k in enumerate(todo)}
    out = []
    for k in todo:
        if k not in left:
            continue
        left.discard(k)
        common = regions[k]
        if not alone:
            same = [u for u in todo if u in left and t.zone[u] == t.zone[k] and t.side[u] == t.side[k]]
            near = sorted(same, key=lambda u: float(np.hypot(*(mid[index[u]] - mid[index[k]]))))[:NEIGHBOURS]
            for u in near:
                both = common.intersection(regions[u])
                if both.area > MIN_AREA_M2:
                    common = both
                    left.discard(u)
        p = largest_part_pole(common, min_tolerance_m=1e-7)
        out.append((k, (float(p.x), float(p.y))))
    return out


def complete_candidates(
    sight: Sight,
    problem: CoverageProblem,
    spaces: dict[str, FrameSpace] | None = None,
    cache: dict[int, shapely.Geometry] | None = None,
) -> tuple[CoverageProblem, dict[int, str]]:
    """``problem`` with a candidate from the coverage regions of every piece no candidate saw, and the pieces still
    unseen afterwards with the reason (a piece index -> why, in words)."""
    site, limits = sight.site, sight.limits
    spaces = {} if spaces is None else spaces
    cache = {} if cache is None else cache
    t = problem.targets
    unseen = problem.uncoverable()
    if unseen.size == 0:
        return problem, {}
    cache.update(coverage_regions(site, t, limits, [int(k) for k in unseen if int(k) not in cache], spaces))
    for alone, tag in ((False, "U"), (True, "V")):
        poles = _stretch_poles(problem, unseen, cache, alone)
        new = []
        for n, (k, (x, y)) in enumerate(poles, 1):
            zone = t.zone_ids[int(t.zone[k])]
            side = ScanSide.INSIDE if int(t.side[k]) == 0 else ScanSide.OUTSIDE
            new.append(side_candidate(zone, side, t.frames[int(t.frame[k])], f"{tag}{n}", x, y, CandidateKind.REGION))
        if new:
            problem = merge_problems(problem, sight.coverage(new, t))
        unseen = problem.uncoverable()
        if unseen.size == 0:
            return problem, {}
    reasons = {}
    for k in unseen:
        frame = t.frames[int(t.frame[k])]
        if frame not in spaces:
            spaces[frame] = frame_space(site, frame, limits)
        reasons[int(k)] = why_empty(t, int(k), limits, spaces[frame]) or TOO_THIN
    return problem, reasons
