"""A plan at the plane bound linked through openings, tried before the MILP over the whole pool.

Where registration joins spaces through openings (``site`` registration with doors) the plain bound over the plane
counts every space at its fewest stations, and a plan that meets it must link them all through doors from those very
stations: each room's one station where it sees the whole room, lined up through every door it links across. The pool
seldom holds such lines (baalbek_site_doors: the plan had 22 stations over a plane bound of 20, and no plan of 21 was
found over the pool with its cut loop, a floor probe, 300 work-s, or outside candidates on rays through the doors).

:func:`aligned_plan` solves the plain cover first (no registration; cheap). Where it meets the plane bound, the stations
of that cover may move within their regions (:func:`planner.candidates.aligned.aligned_candidates`) and the MILP with
registration is solved over the cover's stations and those candidates only. A plan of the same count is connected and
meets the plane bound, so it is optimal over the plane and the MILP over the whole pool is not run; otherwise nothing
is kept and the run goes on as before.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from planner.candidates.aligned import aligned_candidates
from planner.coverage.matrix import CoverageProblem, merge_problems
from planner.coverage.openings import opening_spaces
from planner.coverage.regions import FrameSpace, coverage_regions, regions_apply
from planner.coverage.relation import Registration
from planner.coverage.sight import Sight
from planner.solve.instance import cover_instance
from planner.solve.milp import MilpOptions, solve
from planner.solve.result import SolveResult

if TYPE_CHECKING:
    from planner.plan.methods import MethodInput


#: CP-SAT work (deterministic seconds) the solve over the aligned candidates may spend at most, without the stall rule
#: (it searches on where the whole pool's solve would stall: the temple's plan of 20 is proven after 0.66, 3 s with its cut loop)
ALIGNED_WORK = 10.0


@dataclass(frozen=True, kw_only=True)
class Aligned:
    """A connected plan at the plane bound found among aligned candidates: the result (rows of ``problem``), the pool
    with those candidates appended (``problem``) and the log line."""

    result: SolveResult
    problem: CoverageProblem
    line: str


def aligned_first(run: MethodInput, problem: CoverageProblem, plane_bound: int) -> tuple[Aligned | None, str | None]:
    """:func:`aligned_plan` of the run's pool ``problem`` (priced) where it applies: a registration rule, one view per
    piece, single precision, walls only, and the coverage regions in use; else (None, None)."""
    o = run.options
    if not (
        run.registration.rule is not None
        and o.milp.k == 1
        and o.milp.precision == "single"
        and run.surfaces is None
        and o.regions
        and regions_apply(run.limits)
    ):
        return None, None
    sight = Sight(site=run.site, limits=run.limits, scanner=run.validation.scanner)
    return aligned_plan(sight, problem, run.registration, o.milp, plane_bound, run.region_cache, run.spaces)


def aligned_plan(
    sight: Sight,
    problem: CoverageProblem,
    registration: Registration,
    options: MilpOptions,
    plane_bound: int,
    cache: dict[int, Any],
    spaces: dict[str, FrameSpace],
) -> tuple[Aligned | None, str | None]:
    """The plan of the module docstring where one is found, and a log line (None where the step does not apply: no
    link through an opening among the pool's candidates)."""
    _labels, links = registration.groups(problem.candidates)
    joined = any(a != b for _ends, a, b in opening_spaces(sight.site, passable_only=False))
    if links is None or not links.nnz or not joined:
        return None, None
    start = time.perf_counter()
    plain = solve(cover_instance(problem, name="plain cover"), replace(options, overlap=None))
    if plain.objective is None or round(plain.objective) != plane_bound:
        count = "none" if plain.objective is None else f"{plain.objective:g}"
        return (
            None,
            f"aligned through openings: not tried (the plain cover over the pool is {count}, the plane bound {plane_bound})",
        )
    t = problem.targets

    def regions(pieces: list[int]) -> dict[int, Any]:
        missing = [p for p in dict.fromkeys(pieces) if p not in cache]
        if missing:
            cache.update(coverage_regions(sight.site, t, sight.limits, missing, spaces))
        return cache

    new = aligned_candidates(sight.site, problem, plain.selected, regions, registration.reach_m)
    if not new:
        return None, (
            f"aligned through openings: the plain cover of {plane_bound} (the plane bound): no station's region sees "
            "another's through an opening, so the whole pool is solved"
        )
    merged = merge_problems(problem, sight.coverage(new, t))
    rows = [*plain.selected, *range(len(problem.candidates), len(merged.candidates))]
    sub = _rows(merged, rows)
    groups, sub_links = registration.groups(sub.candidates)
    work = options.work_limit if options.work_limit is None else min(options.work_limit, ALIGNED_WORK)
    got = solve(
        cover_instance(sub, name="aligned", groups=groups, links=sub_links),
        replace(options, stall_work=None, work_limit=work),
    )
    took = time.perf_counter() - start
    head = f"aligned through openings: the plain cover of {plane_bound} (the plane bound), {len(new):,} candidates"
    connected = got.stats is not None and got.stats.connected
    if got.objective is None or round(got.objective) != plane_bound or not connected:
        found = "no plan" if got.objective is None else f"{got.objective:g} stations"
        return None, f"{head}: {found} registered at that count, so the whole pool is solved ({took:.2f} s)"
    info = dict(got.info)
    if isinstance(info.get("presolve"), dict):  # said of what it presolved: the cover's stations and the new ones
        info["presolve"] = {
            **info["presolve"],
            "over": f"the plain cover's {plane_bound} stations and {len(new):,} aligned candidates",
        }
    result = replace(got, selected=tuple(rows[i] for i in got.selected), time_s=took, info=info)
    line = f"{head}: a registered plan of {plane_bound} among them ({took:.2f} s; the MILP over the whole pool not run)"
    return Aligned(result=result, problem=merged, line=line), line


def _rows(problem: CoverageProblem, rows: Sequence[int]) -> CoverageProblem:
    """``problem`` restricted to the candidates ``rows`` (in that order)."""
    r = np.asarray(rows, dtype=np.int64)
    by_c = problem.by_candidate[r].tocsr()
    where = {int(old): new for new, old in enumerate(r)}
    return CoverageProblem(
        candidates=tuple(problem.candidates[i] for i in r),
        targets=problem.targets,
        by_candidate=by_c,
        by_target=by_c.T.tocsr(),
        slant_m=problem.slant_m[r].tocsr(),
        incidence_deg=problem.incidence_deg[r].tocsr(),
        excluded={where[k]: v for k, v in problem.excluded.items() if k in where},
        limits=problem.limits,
    )
