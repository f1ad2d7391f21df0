"""A fresh plan of the problem a re-plan solves, built independently of planner.replan: the edited site (its
obstacles) with every forbidden place a no-go area (the blocked discs, the closed areas and zones), its pool built
from scratch, the done stations added and forced by a column each, the pieces nothing sees left out, and the
planner's MILP at its default work. The re-plan's count and bound are compared with its count."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import scipy.sparse as sp

from planner.coverage.matrix import merge_problems
from planner.plan.methods import with_columns
from planner.plan.problem import resolve, with_recorded_registration
from planner.plan.run import coverage_problem
from planner.site.features import NoGoArea
from planner.solve.instance import cover_instance
from planner.solve.milp import MilpOptions, solve


def disc(xy: tuple[float, float], r: float, n: int = 32) -> tuple[tuple[float, float], ...]:
    """A polygon round the disc of radius ``r`` (its sides outside the circle)."""
    big = r / math.cos(math.pi / n) + 1e-6
    return tuple(
        (xy[0] + big * math.cos(t), xy[1] + big * math.sin(t)) for t in np.linspace(0, 2 * math.pi, n + 1)[:-1]
    )


def fresh_rest_count(r) -> int:  # type: ignore[no-untyped-def]
    """The count of stations to go of a fresh plan of ``r``'s constrained problem (``r``: a planner.Replan)."""
    edited = r.problem.site
    no_go = [NoGoArea(f"blocked {e.entry}", disc(e.station.xy, e.radius_m)) for e in r.edits.blocked if e.radius_m > 0]
    no_go += [NoGoArea(a.entry, a.polygon) for a in r.edits.areas if a.kind == "closed"]
    no_go += [NoGoArea(f"closed {z}", tuple(map(tuple, edited.zone(z).vertices))) for z in r.edits.closed_zones]
    site = replace(edited, no_go_areas=edited.no_go_areas + tuple(no_go))
    problem = with_recorded_registration(resolve(site, r.source.problem.options), r.source.meta)
    pool, _, _ = coverage_problem(problem)
    done = r.problem.sight.coverage(list(r.done), problem.targets)  # where they stood, on the edited site
    cov = merge_problems(pool, done)
    need = np.flatnonzero(np.diff(cov.by_target.indptr) > 0)
    groups, links = problem.registration.groups(cov.candidates)
    inst = cover_instance(cov, groups=groups, links=links)
    inst = replace(inst, by_candidate=inst.by_candidate[:, need].tocsr(), target_length_m=inst.lengths_m[need])
    d, n = len(r.done), cov.shape[0]
    force = sp.csr_matrix((np.ones(d, dtype=bool), (np.arange(n - d, n), np.arange(d))), shape=(n, d))
    result = solve(with_columns(inst, force), MilpOptions(overlap=problem.rule))
    assert set(range(n - d, n)) <= set(result.selected), "the done stations are forced"
    return len(result.selected) - d
