"""Pricing appends its rounds' candidates to the pool once, at the end (:func:`planner.bounds.plane._merged`): the same
pool, array for array, as appending each round's in turn."""

from __future__ import annotations

import numpy as np

from planner.bounds.plane import _merged
from planner.coverage.matrix import CoverageProblem, merge_problems
from planner.plan import PlanOptions, coverage_problem, resolve
from planner.site.model import ScanSide, Site, Zone
from planner.site.params import Parameters


def _rows(p: CoverageProblem, rows: np.ndarray) -> CoverageProblem:
    by = p.by_candidate[rows]
    return CoverageProblem(
        candidates=tuple(p.candidates[int(i)] for i in rows),
        targets=p.targets,
        by_candidate=by,
        by_target=by.T.tocsr(),
        slant_m=p.slant_m[rows],
        incidence_deg=p.incidence_deg[rows],
        excluded={},
        limits=p.limits,
    )


def _same(a: CoverageProblem, b: CoverageProblem) -> bool:
    mats = ("by_candidate", "by_target", "slant_m", "incidence_deg")
    return (
        a.candidates == b.candidates
        and a.excluded == b.excluded
        and all(
            np.array_equal(getattr(getattr(a, m), k), getattr(getattr(b, m), k))
            and getattr(getattr(a, m), k).dtype == getattr(getattr(b, m), k).dtype
            for m in mats
            for k in ("indptr", "indices", "data")
        )
    )


def test_merged_once_is_merged_each_round() -> None:
    room = ((0, 0), (9, 0), (9, 4), (4, 4), (4, 8), (0, 8))
    site = Site("merge", (Zone("A", ScanSide.INSIDE, room, (3.0,) * 6),), parameters=Parameters(overlap=0.3))
    problem, _, _ = coverage_problem(resolve(site, PlanOptions(method="greedy", precision=False)))
    n = len(problem.candidates)
    assert n > 12
    pool, rounds = _rows(problem, np.arange(n // 2)), np.array_split(np.arange(n // 2, n), 5)
    pieces = [_rows(problem, r) for r in rounds]
    each = pool
    for piece in pieces:
        each = merge_problems(each, piece)
    assert _same(_merged(pool, pieces), each)
    assert _merged(pool, []) is pool
