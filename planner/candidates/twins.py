"""k positions in every coverage region a k-view plan may use: twins of the pool's undominated candidates.

With k views a piece needs k distinct stations. Where one position sees everything a plan needs (a room whose middle
sees every wall), a pool that holds one candidate there makes the second view cost a station elsewhere, though a
second position a few centimetres off sees the same. So for k >= 2 every candidate that no other candidate's view
holds (undominated, by the pieces it sees) gets up to k - 1 twins: poles of the intersection of the coverage regions
of the pieces it sees (every point of it sees at least those pieces), with discs of :data:`TWIN_SEPARATION_M` about
the candidate and the twins placed before it cut out, so that the k positions are distinct stations. The coverage
test then decides what each twin sees. A region too small to hold a twin that far off gets none.
"""

from __future__ import annotations

import numpy as np
import shapely

from planner.candidates.closed_form import side_candidate
from planner.candidates.from_regions import largest_part_pole
from planner.coverage.matrix import CoverageProblem, merge_problems
from planner.coverage.regions import FrameSpace, coverage_regions
from planner.coverage.sight import Sight
from planner.site.candidate import CandidateKind

#: two positions closer than this are not distinct stations (m): twice the tripod disc's resolution (0.05 m), the
#: smallest move a plan tells apart
TWIN_SEPARATION_M = 0.1
#: candidates twinned at most (the undominated ones seeing the most pieces first)
MAX_TWINNED = 400
#: the largest k twinned: k - 1 twins per candidate beyond it would cost more than any plan needs (a k of hundreds is a
#: refusal to count, not a plan to draw)
MAX_K = 4
#: a region smaller than this (m^2) holds no twin
MIN_AREA_M2 = 1e-10


def undominated(problem: CoverageProblem, limit: int = MAX_TWINNED) -> list[int]:
    """Candidates whose seen pieces no other candidate's hold (of equal sets, the first), most pieces first, at most
    ``limit``."""
    a = problem.by_candidate.astype(bool).tocsr()
    sizes = np.diff(a.indptr)
    order = np.argsort(-sizes, kind="stable")
    sets = [frozenset(a.indices[a.indptr[i] : a.indptr[i + 1]].tolist()) for i in range(a.shape[0])]
    kept: list[int] = []
    for i in order:
        if sizes[i] == 0:
            break
        if any(sets[i] <= sets[j] for j in kept):
            continue
        kept.append(int(i))
        if len(kept) >= limit:
            break
    return kept


def twin_candidates(
    sight: Sight,
    problem: CoverageProblem,
    k: int,
    spaces: dict[str, FrameSpace] | None = None,
    cache: dict[int, shapely.Geometry] | None = None,
) -> tuple[CoverageProblem, str]:
    """``problem`` with up to k - 1 twins of each undominated candidate (module docstring) and a log line (empty for
    k = 1, where nothing is added; for k above :data:`MAX_K`, the pool as it is, said in the line)."""
    if k < 2:
        return problem, ""
    if k > MAX_K:
        return problem, f"k = {k} views: no twin positions added (twins are made for k up to {MAX_K})"
    spaces = {} if spaces is None else spaces
    cache = {} if cache is None else cache
    t = problem.targets
    a = problem.by_candidate.astype(bool).tocsr()
    chosen = undominated(problem)
    new = []
    for i in chosen:
        seen = a.indices[a.indptr[i] : a.indptr[i + 1]]
        missing = [int(p) for p in seen if int(p) not in cache]
        if missing:
            cache.update(coverage_regions(sight.site, t, sight.limits, missing, spaces))
        region = shapely.intersection_all([cache[int(p)] for p in seen])
        c = problem.candidates[i]
        taken = [shapely.Point(c.x, c.y)]
        for n in range(k - 1):
            left = region.difference(shapely.union_all([q.buffer(TWIN_SEPARATION_M, 32) for q in taken]))
            if left.is_empty or left.area <= MIN_AREA_M2:
                break
            p = largest_part_pole(left, min_tolerance_m=1e-7)
            taken.append(p)
            new.append(side_candidate(c.zone, c.side, c.frame, f"K{i}.{n + 1}", p.x, p.y, CandidateKind.REGION))
    if new:
        problem = merge_problems(problem, sight.coverage(new, t))
    return problem, (
        f"k = {k} views: {len(new)} twin positions (at least {TWIN_SEPARATION_M:g} m apart) for {len(chosen)} "
        "undominated candidates, in the regions that see what each sees"
    )
