"""From a site to a verified plan: candidates -> coverage -> method -> verification."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from planner.accuracy import max_slant_range_m
from planner.candidates.closed_form import Limits
from planner.candidates.final_step import drop_redundant, relocate
from planner.candidates.model import Candidate
from planner.candidates.pool import PoolOptions, candidate_pool, closed_form_candidates
from planner.coverage.matrix import CoverageProblem, build_coverage
from planner.coverage.overlap import OverlapRule, piece_lengths
from planner.coverage.targets import make_targets
from planner.coverage.visibility import SightLimits
from planner.errors import InfeasibleError, UsageError
from planner.site.model import Site
from planner.solve.greedy import greedy_cover
from planner.solve.instance import cover_instance
from planner.solve.milp import MilpOptions, solve
from planner.solve.result import SolveResult, Status
from planner.validate import ValidationReport, validate_site
from planner.verify import VerifyReport, verify_stations

METHODS = ("closed-form", "greedy", "milp")


@dataclass(frozen=True)
class PlanOptions:
    """Everything about a planning run that is not the site itself.

    ``target_spacing_m`` = 1 m: walls are cut into pieces of at most 1 m, and a
    piece counts as covered only when one station sees all of it, so a coarse
    piece costs coverage at its ends; 1 m keeps that loss below the verify
    sampling's resolution on the bundled sites while A (1,500 m of wall, both
    sides) stays at 3,000 targets and the coverage build under a few seconds.
    """

    method: str = "greedy"
    target_spacing_m: float = 1.0
    pool: PoolOptions = field(default_factory=PoolOptions)
    incidence_3d: bool = False
    precision: bool = True
    verify_spacing_m: float = 0.1
    milp: MilpOptions = field(default_factory=MilpOptions)

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise UsageError(f"unknown method (known: {', '.join(METHODS)})", field="method", value=self.method)
        for name, v in (("target_spacing_m", self.target_spacing_m), ("grid_spacing_m", self.pool.grid_spacing_m),
                        ("verify_spacing_m", self.verify_spacing_m)):
            if not v > 0:
                raise UsageError("must be > 0", field=name, value=v)


@dataclass(frozen=True)
class Plan:
    """A verified plan: the chosen stations, how they were found, and their verification."""

    site: Site
    options: PlanOptions
    validation: ValidationReport
    result: SolveResult
    stations: tuple[Candidate, ...]
    verification: VerifyReport
    problem_size: dict[str, int]
    log: tuple[str, ...] = ()

    def count_by_side(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for s in self.stations:
            out[s.side.value] = out.get(s.side.value, 0) + 1
        return out

    def summary(self) -> str:
        by_zone: dict[tuple[str, str], int] = {}
        for s in self.stations:
            by_zone[(s.zone, s.side.value)] = by_zone.get((s.zone, s.side.value), 0) + 1
        sides = self.count_by_side()
        lines = [
            f"instance {self.site.name}, method {self.result.method}: {self.result.summary()}",
            f"stations: {len(self.stations)} (inside {sides.get('inside', 0)}, outside {sides.get('outside', 0)}); "
            f"candidates {self.problem_size['candidates']}, targets {self.problem_size['targets']}",
            f"{'zone':<10}{'side':<9}{'stations':>9}",
        ]
        lines += [f"{z:<10}{s:<9}{n:>9}" for (z, s), n in by_zone.items()]
        lines += list(self.log)
        lines.append(self.verification.summary())
        return "\n".join(lines)


def sight_limits(validation: ValidationReport, incidence_3d: bool, precision: bool) -> SightLimits:
    """The pair limits for a validated site; the precision range is (3.1) for the scanner and sigma_req."""
    p = validation.site.parameters
    precision_range = max_slant_range_m(validation.scanner, validation.range_limit.sigma_instr_m) if precision else None
    return SightLimits(validation.range_limit.max_slant_range_m, p.theta_max_deg, p.instrument_height_m,
                       incidence_3d, precision_range)


def closed_form_limits(validation: ValidationReport) -> Limits:
    p = validation.site.parameters
    return Limits(validation.range_limit.max_slant_range_m, p.theta_max_deg, p.overlap, p.instrument_height_m)


def unseen_error(problem: CoverageProblem, unseen: np.ndarray) -> InfeasibleError:
    t = problem.targets
    shown = "; ".join(f"{t.label(i)} at ({t.midpoint(i)[0]:.2f}, {t.midpoint(i)[1]:.2f})" for i in unseen[:5])
    more = f" and {len(unseen) - 5} more" if len(unseen) > 5 else ""
    return InfeasibleError(f"{len(unseen)} target(s) seen by no candidate: {shown}{more}")


def plan_site(site: Site, options: PlanOptions | None = None) -> Plan:
    """Plan the stations of a site with the chosen method and verify the plan.

    Raises
    ------
    InfeasibleError
        When some wall piece is seen by no candidate of the pool (listed by id and position).
    """
    options = options or PlanOptions()
    validation = validate_site(site)
    combined = options.method == "milp" and options.milp.precision == "combined"
    limits = sight_limits(validation, options.incidence_3d, options.precision and not combined)
    cf_limits = closed_form_limits(validation)
    targets = make_targets(site, options.target_spacing_m)
    start = time.perf_counter()
    pool = candidate_pool(site, cf_limits, options.pool)
    problem = build_coverage(site, pool, targets, limits)
    build_s = time.perf_counter() - start
    unseen = problem.uncoverable()
    if unseen.size:
        err = unseen_error(problem, unseen)
        raise err.located(site.source) if site.source else err
    log: list[str] = [f"coverage built in {build_s:.2f} s ({problem.by_candidate.nnz:,} candidate-target pairs)"]
    if options.method == "closed-form":
        result, stations, extra = _closed_form(site, cf_limits, targets, limits)
        log += extra
    elif options.method == "milp":
        p = site.parameters
        inst = cover_instance(problem, scanner=validation.scanner, budget=p.budget, sigma_req_m=p.sigma_req_m,
                              name=site.name)
        result = solve(inst, options.milp)
        stations = [problem.candidates[i] for i in result.selected]
    else:
        result = greedy_cover(problem.by_candidate)
        stations = [problem.candidates[i] for i in result.selected]
    verification = verify_stations(site, stations, limits, options.verify_spacing_m)
    size = {"candidates": len(problem.candidates), "targets": len(targets), "pairs": int(problem.by_candidate.nnz)}
    return Plan(site, options, validation, result, tuple(stations), verification, size, tuple(log))


def _closed_form(site: Site, cf_limits: Limits, targets: Any, limits: SightLimits) -> tuple[SolveResult, list[Candidate], list[str]]:
    """The dissertation's plan: closed-form candidates, moved where misplaced, redundant ones dropped."""
    start = time.perf_counter()
    cands, log = relocate(site, closed_form_candidates(site, cf_limits))
    problem = build_coverage(site, cands, targets, limits)
    lengths = piece_lengths(targets.s0_m, targets.s1_m)
    rule = OverlapRule(site.parameters.overlap)
    keep = drop_redundant(problem.by_candidate, [(c.zone, c.side) for c in cands], lengths, rule)
    dropped = [cands[i].id for i in range(len(cands)) if i not in set(keep)]
    if dropped:
        log.append(f"redundant closed-form candidates removed: {', '.join(dropped)}")
    stations = [cands[i] for i in keep]
    covered = problem.covered_by(keep) > 0
    status = Status.FEASIBLE if covered.all() else Status.INCOMPLETE
    info = {"uncovered_targets": int((~covered).sum()), "generated": len(cands)}
    return SolveResult("closed-form", status, tuple(keep), float(len(keep)), time_s=time.perf_counter() - start,
                       info=info), stations, log
