"""From a site to a verified plan: candidates -> coverage -> method -> registration check -> verification."""

from __future__ import annotations

import time
from collections import Counter
from dataclasses import replace
from typing import Any

import numpy as np

from planner.bounds.corners import link_refusal
from planner.bounds.outer import OuterRegions
from planner.bounds.ring_ahead import WalksAhead, one_station_sides
from planner.candidates.axis import axis_candidates
from planner.candidates.complete import complete_candidates
from planner.candidates.connect import connect_candidates, is_link, split_groups
from planner.candidates.from_regions import whole_side_candidates
from planner.candidates.pool import candidate_pool, dedupe
from planner.core.checks import argument
from planner.core.errors import InfeasibleError, InputError, UsageError
from planner.coverage.fingerprint import pool_of
from planner.coverage.matrix import CoverageProblem
from planner.coverage.regions import FrameSpace, coverage_regions, regions_apply
from planner.coverage.targets import Targets
from planner.instrument.field_table import DEFAULT_FIELD, FieldProperties
from planner.plan.hours import Hours
from planner.plan.hours.columns import spacing_coverage, spacing_refusal
from planner.plan.hours.field_time import field_properties, hours_method
from planner.plan.hours.verify import verify_spacing
from planner.plan.memory_guard import check_memory
from planner.plan.methods import (
    REGISTRY,
    MethodInput,
    MethodOutput,
    closed_form_limits,
    early_walks,
    finish_bound,
)
from planner.plan.options import PlanOptions
from planner.plan.problem import Problem, resolve
from planner.plan.result import Plan
from planner.plan.surfaces import SurfaceCover, floor_candidates, surface_cover, surface_discs
from planner.plan.surfaces_bound import surface_region_candidates, with_surfaces_plane
from planner.plan.tripod import placed_stations
from planner.plan.verify import verify_stations
from planner.plan.verify_surfaces import verify_surfaces
from planner.site.candidate import Candidate
from planner.site.model import Site
from planner.site.validate import ValidationReport
from planner.solve.result import SolveResult


def unseen_error(
    problem: CoverageProblem, unseen: np.ndarray, reasons: dict[int, str] | None = None
) -> InfeasibleError:
    """The refusal of pieces nothing sees: up to five by id and position, each with its reason when known
    (``reasons``: why its coverage region is empty), and how many share each reason."""
    t = problem.targets
    reasons = reasons or {}

    def why(i: int) -> str:
        return f" ({reasons[int(i)]})" if int(i) in reasons else ""

    shown = "; ".join(f"{t.label(i)} at ({t.midpoint(i)[0]:.2f}, {t.midpoint(i)[1]:.2f}){why(i)}" for i in unseen[:5])
    more = f" and {len(unseen) - 5} more" if len(unseen) > 5 else ""
    if reasons:
        counts = Counter(reasons.get(int(i), "not checked") for i in unseen)
        tally = "; ".join(f"{n} {r}" for r, n in counts.items())
        return InfeasibleError(
            f"{len(unseen)} target(s) seen from no position (coverage region empty): {shown}{more} [{tally}]"
        )
    return InfeasibleError(f"{len(unseen)} target(s) seen by no candidate: {shown}{more}")


def build_problem(
    site: Site | Problem,
    options: PlanOptions | None = None,
    validation: ValidationReport | None = None,
    *,
    spaces: dict[str, FrameSpace] | None = None,
    region_cache: dict[int, Any] | None = None,
) -> CoverageProblem:
    """Candidates, targets and coverage of a resolved problem (or of a site with ``options``, resolved here).

    ``spaces`` and ``region_cache``, when given, keep the frame spaces and coverage regions drawn for the region
    candidates (keyed by piece index of the problem's targets), for pricing to reuse. Raises InfeasibleError,
    before any solver runs, where a target is seen from no position (:func:`unseen_error`), and InputError (exit
    3) where the estimated memory of the work exceeds ``options.memory_limit_bytes``.
    """
    resolved = as_problem(site, options, validation)
    problem, unseen, reasons = coverage_problem(resolved, spaces=spaces, region_cache=region_cache)
    source = resolved.site.source
    if unseen.size:
        err = unseen_error(problem, unseen, reasons)
        raise err.located(source) if source else err
    refusal = unlinkable(resolved, problem)
    if refusal:
        err = InfeasibleError(refusal)
        raise err.located(source) if source else err
    return problem


def unlinkable(problem: Problem, coverage: CoverageProblem) -> str | None:
    """Why no connected plan exists over the plane (:func:`planner.bounds.corners.link_refusal`), asked only where
    the run has an overlap rule and its pool, connectivity candidates included, still splits a registration group's
    pieces (:func:`planner.candidates.connect.split_groups`); None otherwise."""
    if problem.rule is None or not (problem.options.regions and regions_apply(problem.limits)):
        return None
    if not split_groups(coverage, problem.registration.groups):
        return None
    theta = problem.site.parameters.theta_max_deg
    return link_refusal(problem.site, coverage, problem.limits, problem.registration.groups, OuterRegions(), theta)


def as_problem(
    site: Site | Problem, options: PlanOptions | None = None, validation: ValidationReport | None = None
) -> Problem:
    """``site`` itself when it is a resolved problem (then neither ``options`` nor ``validation`` may be
    given), else :func:`resolve` of it."""
    if isinstance(site, Problem):
        if options is not None or validation is not None:
            raise UsageError("a resolved problem carries its options and validation", field="options")
        return site
    return resolve(site, options, validation=validation)


def coverage_problem(
    problem: Problem,
    *,
    spaces: dict[str, FrameSpace] | None = None,
    region_cache: dict[int, Any] | None = None,
) -> tuple[CoverageProblem, np.ndarray, dict[int, str]]:
    """:func:`build_problem` without the refusal: the coverage problem, the pieces no candidate sees (after every
    unseen piece got a candidate from its own region) and, per such piece, why its region is empty."""
    argument(problem, Problem, "problem")
    site, options, limits = problem.site, problem.options, problem.limits
    s_max = problem.validation.range_limit.max_slant_range_m  # refuse what will not fit, before building
    check_memory(site, options.target_spacing_m, options.pool.grid_m, s_max, options.memory_limit_bytes)
    targets = problem.targets
    spaces = {} if spaces is None else spaces
    region_cache = {} if region_cache is None else region_cache
    pool = site_candidates(problem, targets, spaces, region_cache)
    coverage = problem.sight.coverage(pool, targets, step="coverage build")
    reasons: dict[int, str] = {}
    if options.regions and regions_apply(limits):
        # a candidate from its own region for every piece still unseen; refused only when that is empty
        coverage, reasons = complete_candidates(problem.sight, coverage, spaces, region_cache)
        if problem.rule is not None and not reasons:
            # where the pool cannot link a registration group's pieces (an outside corner), positions that see both
            coverage, _ = connect_candidates(problem.sight, coverage, problem.registration.groups, spaces, region_cache)
    return coverage, coverage.uncoverable(), reasons


def site_candidates(
    problem: Problem,
    targets: Targets,
    spaces: dict[str, FrameSpace] | None = None,
    region_cache: dict[int, Any] | None = None,
) -> list[Candidate]:
    """The candidate pool of a site (the one home of it: the single model and the tiles both take it): the closed
    form, field samples and grid of :func:`planner.candidates.pool.candidate_pool`; with regions, one station per
    zone-side where one sees all of it; a candidate per maximal cell of the regions along every room's medial axis
    and the rings round outside zones; duplicates removed."""
    site, options, limits = problem.site, problem.options, problem.limits
    pool = candidate_pool(site, closed_form_limits(problem.validation), options.pool)
    exact = options.regions and regions_apply(limits)
    if exact:  # one station for a whole zone-side, found exactly where one exists
        pool = pool + whole_side_candidates(site, targets, limits, spaces, region_cache)
    if problem.surfaces is not None:  # a grid over the floors, finer than the walls'
        pool = pool + floor_candidates(site, problem.surfaces, options.pool.min_standoff_m)
        pool = pool + surface_region_candidates(problem, targets, spaces, region_cache)
    return dedupe(
        pool
        + axis_candidates(site, targets, limits, spaces, region_cache, cells=exact, step_m=options.target_spacing_m)
    )


def plan_single(
    problem: Problem,
    props: FieldProperties | None = None,
    coverage: CoverageProblem | None = None,
    *,
    surface_cover: SurfaceCover | None = None,
) -> Plan:
    """Plan the stations of a resolved problem as one model, with its method (:data:`planner.plan.methods.REGISTRY`),
    check registration, and verify the plan. The public entry, which also chooses tiles for a large site, is
    :func:`planner.engine.plan_site`. ``props``: the scan settings a run with point spacing or the field-time objective
    chooses from (None: the instrument's table). ``coverage``: the problem's coverage where the caller built it already
    (:func:`build_problem` of this problem, or of one that differs in its objective or method only: the trade-off's
    plans and the report's method comparison share the plan's, :attr:`Plan.coverage`); None: built here
    (InfeasibleError where some wall piece is seen by no candidate). ``surface_cover``: the floor and ceiling columns
    of ``coverage``'s candidates where built already (:attr:`Plan.surface_cover`); None: built here where the run has
    surfaces. The plan keeps both (:attr:`Plan.coverage`, :attr:`Plan.surface_cover`)."""
    argument(problem, Problem, "problem")
    # the connected bound's walks need only the targets: started on a free core before the coverage is built
    walls = props is None and problem.surfaces is None
    ahead = (
        early_walks(problem.site, problem.options, problem.registration, problem.limits, problem.targets)
        if walls
        else None
    )
    try:
        run, cover, log = _method_input(problem, coverage, surface_cover, ahead)
        if ahead is not None:
            ahead.skip(one_station_sides(run.problem))
        props = _settings(problem, run.problem, props)
        out = hours_method(run, props) if props is not None else REGISTRY[problem.options.method](run)
        out = with_surfaces_plane(problem, run, out, cover)
        if cover is not None and out.problem.candidates != run.problem.candidates:  # pricing is off with surfaces
            raise RuntimeError("the method changed the candidate pool the surface columns were built for")
        log = [*log, *out.log]
        plan = _checked_plan(problem, out, cover, props, log)
        if out.pending is not None:  # the connected bound, finished by the walks ahead while the plan was checked
            result, line = finish_bound(plan.result, out.pending)
            plan = replace(plan, result=result, log=(*plan.log[: len(log)], line, *plan.log[len(log) :]))
    finally:
        if ahead is not None:
            ahead.close()
    return replace(plan, coverage=run.problem, surface_cover=cover)


def _method_input(
    problem: Problem,
    coverage: CoverageProblem | None,
    given_cover: SurfaceCover | None = None,
    ahead: WalksAhead | None = None,
) -> tuple[MethodInput, SurfaceCover | None, list[str]]:
    """What the method plans from (the pool's coverage, built here unless given, with the regions drawn for
    pricing), the floor and ceiling columns of the same candidates where the run has surfaces (``given_cover``
    where given with ``coverage``), and the log."""
    site, options = problem.site, problem.options
    start = time.perf_counter()
    spaces: dict[str, FrameSpace] = {}
    region_cache: dict[int, Any] = {}  # regions drawn once: for the candidates, pricing and the walks ahead
    if ahead is not None:  # every piece's region drawn here while the walks draw the outer ones, then sent to them
        region_cache.update(coverage_regions(site, problem.targets, problem.limits, None, spaces))
        ahead.share(region_cache)
    how = "coverage given (built once for the run)"
    if coverage is None:
        coverage, given_cover = build_problem(problem, spaces=spaces, region_cache=region_cache), None
        how = f"coverage built in {time.perf_counter() - start:.2f} s"
    pricing = ", before pricing" if options.method == "milp" and options.pricing else ""
    pairs = f"{len(coverage.candidates):,} candidates of the pool, {coverage.by_candidate.nnz:,} candidate-target pairs"
    log = [f"{how} ({pairs}{pricing})"]
    links = sum(1 for c in coverage.candidates if is_link(c))
    if links:
        log.append(
            f"connectivity candidates: {links} where the pool split a registration group's pieces (outside corners)"
        )
    cover = None
    if problem.surfaces is not None and given_cover is not None:
        if given_cover.matrix.shape[0] != len(coverage.candidates):
            raise ValueError(
                f"{given_cover.matrix.shape[0]} rows of surface columns for {len(coverage.candidates)} candidates"
            )
        cover = given_cover
        log.append(f"{cover.line(problem.surfaces)} (given with the coverage)")
    elif problem.surfaces is not None:  # the floor and ceiling columns, for the same candidates
        t0 = time.perf_counter()
        cover = surface_cover(site, problem.surfaces, coverage.candidates, coverage.excluded)
        log.append(f"{cover.line(problem.surfaces)} ({time.perf_counter() - t0:.2f} s)")
    extra = None if cover is None else cover.matrix
    run = MethodInput(
        site,
        options,
        problem.validation,
        problem.limits,
        problem.registration,
        coverage,
        spaces,
        region_cache,
        extra,
        walks_ahead=ahead,
    )
    return run, cover, log


def _settings(problem: Problem, coverage: CoverageProblem, props: FieldProperties | None) -> FieldProperties | None:
    """The scan settings a run with point spacing or the field-time objective chooses from (``props``: a table
    given for the run, else the instrument's), refused where the spacing cannot be met; None: a run of stations."""
    site, options = problem.site, problem.options
    if options.hours:
        props = props or field_properties(site)
        if props is DEFAULT_FIELD and options.max_point_spacing_m is not None:
            raise InputError(
                f"instrument {site.instrument!r} has no [field] table of scan settings named by their point "
                "spacing ('6.3 mm @ 10 m'): --max-point-spacing needs one (docs/field-time.md)",
                field="instrument",
                value=site.instrument,
            )
    if props is not None and options.max_point_spacing_m is not None:
        refuse_spacing(problem, coverage, props)
    return props


def _checked_plan(
    problem: Problem, out: MethodOutput, cover: SurfaceCover | None, props: FieldProperties | None, log: list[str]
) -> Plan:
    """The method's plan with its registration checked, its stations placed and verified."""
    site, options = problem.site, problem.options
    result, coverage = out.result, out.problem
    registration, partners = problem.registration.check(coverage, result.selected)
    if problem.checked_rule.overlap == 0:
        registration, log = {}, [*log, "registration: not required (overlap 0)"]
    stations, tripods = placed_stations(site, coverage, result.selected, options, partners)
    verification = verify_stations(problem.sight, stations, options.verify_spacing_m)
    surfaces = None
    if cover is not None and problem.surfaces is not None:
        if tripods:  # discs that keep the floors too
            tripods, shrunk = surface_discs(site, problem.surfaces, cover, result.selected, stations, tripods)
            log.append(f"tripod discs: {shrunk} of {len(tripods)} shrunk to keep their floor and ceiling patches")
        t0 = time.perf_counter()
        surfaces = verify_surfaces(site, problem.surfaces, cover, stations, options.verify_spacing_m)
        log.append(f"surfaces verified in {time.perf_counter() - t0:.2f} s")
    # the pool's size (after pricing for the MILP); the closed form solves over its own stations, not counted here
    pool = out.pool
    size = {"candidates": len(pool.candidates), "targets": len(coverage.targets), "pairs": int(pool.by_candidate.nnz)}
    return Plan(
        problem=problem,
        result=result,
        stations=tuple(stations),
        verification=verification,
        problem_size=size,
        log=tuple(log),
        registration=registration,
        tripods=tripods,
        # the pool the size counts: the best plans known (of walls) are matched on its fingerprint
        pool=pool_of(pool) if surfaces is None else None,
        surfaces=surfaces,
        hours=None if props is None else hours_of(problem, props, result, stations),
    )


def refuse_spacing(problem: Problem, coverage: CoverageProblem, props: FieldProperties) -> None:
    """Refuse, before any solver runs, a run with pieces that no candidate scans at the asked spacing even at
    the instrument's finest setting (each with the finest spacing it gets)."""
    spacing = problem.options.max_point_spacing_m
    assert spacing is not None
    name, step, _ = props.by_step()[-1]
    unseen = spacing_coverage(coverage, step, spacing).uncoverable()
    if unseen.size:
        err = spacing_refusal(coverage, unseen, name, step, spacing)
        source = problem.site.source
        raise err.located(source) if source else err


def hours_of(problem: Problem, props: FieldProperties, result: SolveResult, stations: list[Candidate]) -> Hours:
    """The settings, set-up + scan time and spacing check of a plan with scan settings."""
    o = problem.options
    settings = tuple(result.info.get("settings", ()))
    spacing = None
    if o.max_point_spacing_m is not None and len(settings) == len(stations):
        spacing = verify_spacing(problem.sight, stations, settings, props, o.max_point_spacing_m, o.verify_spacing_m)
    return Hours(
        objective=o.objective,
        max_spacing_m=o.max_point_spacing_m,
        settings=settings,
        setup_s=len(settings) * props.setup_time_s,
        scan_s=sum(props.scan_time_s(s) for s in settings),
        timing=dict(result.info.get("field_time", {})),
        spacing=spacing,
    )
