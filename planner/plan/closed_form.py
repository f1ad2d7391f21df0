"""The dissertation's own plan as a method: closed-form candidates after the final step."""

from __future__ import annotations

import time

from planner.candidates.closed_form import Limits
from planner.candidates.final_step import drop_redundant, relocate
from planner.candidates.pool import closed_form_candidates
from planner.coverage.matrix import CoverageProblem, build_coverage
from planner.coverage.overlap import OverlapRule, piece_lengths
from planner.coverage.targets import Targets
from planner.coverage.visibility import SightLimits
from planner.site.model import Site
from planner.site.validate import ValidationReport
from planner.solve.result import SolveResult, Status


def closed_form_limits(validation: ValidationReport) -> Limits:
    """The closed form's limits (3.1): the slant range, theta_max, overlap and instrument height of the site."""
    p = validation.site.parameters
    return Limits(validation.range_limit.max_slant_range_m, p.theta_max_deg, p.overlap, p.instrument_height_m)


def closed_form_plan(
    site: Site, cf_limits: Limits, targets: Targets, limits: SightLimits, rule: OverlapRule
) -> tuple[SolveResult, CoverageProblem, list[str]]:
    """Closed-form candidates, moved where misplaced, redundant ones dropped (3.1.3) under the overlap ``rule``.

    Returns the result (indices into the returned problem's candidates), that
    problem, and a log of the moves and removals. The status is ``incomplete``
    when the closed form leaves targets uncovered.
    """
    start = time.perf_counter()
    cands, log = relocate(site, closed_form_candidates(site, cf_limits))
    problem = build_coverage(site, cands, targets, limits)
    keep = drop_redundant(
        problem.by_candidate, [(c.zone, c.side) for c in cands], piece_lengths(targets.s0_m, targets.s1_m), rule
    )
    dropped = [cands[i].id for i in range(len(cands)) if i not in set(keep)]
    if dropped:
        log.append(f"redundant closed-form candidates removed: {', '.join(dropped)}")
    covered = problem.covered_by(keep) > 0
    status = Status.FEASIBLE if covered.all() else Status.INCOMPLETE
    info = {"uncovered_targets": int((~covered).sum()), "generated": len(cands)}
    result = SolveResult(
        method="closed-form",
        status=status,
        selected=tuple(keep),
        objective=float(len(keep)),
        time_s=time.perf_counter() - start,
        info=info,
    )
    return result, problem, log
