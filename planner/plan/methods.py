"""The planning methods by name: :data:`REGISTRY` (what :func:`planner.plan.run.plan_single` looks up; its keys are
:data:`METHODS`, the ``--method`` choices), among them the dissertation's own plan (closed-form candidates after the
final step).

Each method takes a :class:`MethodInput` (the site's coverage problem over its candidate pool, and what drew it) and
returns a :class:`MethodOutput`: the solver's result, the problem the result's indices refer to, the pool the plan's
size counts, and log lines. A new method is a function of that signature added here.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp

from planner.bounds.connected_result import ConnectedPlaneBound, plan_counts, with_connected_plane_bound
from planner.bounds.k_views import with_k_plane_bound
from planner.bounds.outer import OuterRegions
from planner.bounds.plane import price_plane, with_plane_bound
from planner.bounds.plane_ring import CONNECTED_WORK_PATCHES, connected_plane_bound
from planner.bounds.ring_ahead import WalksAhead
from planner.bounds.ring_walks import RingWalks
from planner.candidates.closed_form import Limits
from planner.candidates.final_step import drop_redundant, relocate
from planner.candidates.pool import closed_form_candidates
from planner.candidates.twins import twin_candidates
from planner.core import progress
from planner.core.errors import InfeasibleError, PlannerError
from planner.coverage.links import zone_side_groups
from planner.coverage.matrix import CoverageProblem, build_coverage
from planner.coverage.openings import accessible_areas
from planner.coverage.overlap import OverlapRule, piece_lengths
from planner.coverage.regions import FrameSpace, regions_apply
from planner.coverage.relation import Registration
from planner.coverage.sight import Sight
from planner.coverage.targets import Targets
from planner.coverage.visibility import SightLimits
from planner.plan.aligned import aligned_first
from planner.plan.surfaces import PLANE_OFF
from planner.site.model import Site
from planner.site.validate import ValidationReport
from planner.solve.greedy import connected_greedy_plan, greedy_cover
from planner.solve.instance import CoverInstance, cover_instance
from planner.solve.milp import solve
from planner.solve.result import SolveResult, Status

if TYPE_CHECKING:
    from planner.plan.options import PlanOptions


@dataclass(frozen=True)
class MethodInput:
    """What a method plans from: the site, the run's options, the sight limits, the registration and the coverage
    problem of the pool; ``spaces`` and ``region_cache`` hold the frame spaces and coverage regions already drawn
    (pricing reuses them). ``surfaces``: candidates x floor and ceiling patches (bool CSR, the patches some
    candidate sees), columns every method covers besides the wall pieces (None: walls only); the registration links
    and the precision rule stay the walls' (a patch adds no shared wall)."""

    site: Site
    options: PlanOptions
    validation: ValidationReport
    limits: SightLimits
    registration: Registration
    problem: CoverageProblem
    spaces: dict[str, FrameSpace]
    region_cache: dict[int, Any]
    surfaces: sp.csr_matrix | None = None
    #: the outer regions O_t drawn in this run (pricing's check of the heaviest weight, then the connected bound)
    outer: OuterRegions = field(default_factory=OuterRegions)
    #: the connected bound's ring walks started ahead by the caller (:func:`early_walks`), which also ends them
    walks_ahead: WalksAhead | None = None


def with_columns(inst: CoverInstance, extra: sp.csr_matrix | None) -> CoverInstance:
    """``inst`` with the columns ``extra`` (candidates x patches) appended as targets of no wall length, so that
    they count in no overlap; their precision weight is 1 (one view meets it)."""
    if extra is None:
        return inst
    if extra.shape[0] != inst.shape[0]:
        raise ValueError(f"{extra.shape[0]} rows of surface columns for {inst.shape[0]} candidates")
    by = _columns(inst.by_candidate, extra)
    lengths = None
    if inst.target_length_m is not None:
        lengths = np.concatenate([np.asarray(inst.target_length_m, dtype=float), np.zeros(extra.shape[1])])
    info = None if inst.info is None else sp.hstack([inst.info, extra.astype(float)], format="csr")
    return replace(inst, by_candidate=by, target_length_m=lengths, info=info)


@dataclass(frozen=True)
class MethodOutput:
    """A method's result; ``problem``: what its indices refer to; ``pool``: the pool the plan's size counts
    (the MILP's after pricing; the closed form solves over its own stations, not counted)."""

    result: SolveResult
    problem: CoverageProblem
    pool: CoverageProblem
    log: tuple[str, ...] = ()
    #: the connected plane bound still being finished by the walks ahead (:func:`finish_bound` adds it to the result);
    #: only where the caller started them (:attr:`MethodInput.walks_ahead`), so that it waits for them after its own
    #: checks of the plan rather than before
    pending: Future[ConnectedPlaneBound] | None = None


def closed_form_limits(validation: ValidationReport) -> Limits:
    """The closed form's limits (3.1): the slant range, theta_max, overlap and instrument height of the site."""
    p = validation.site.parameters
    return Limits(validation.range_limit.max_slant_range_m, p.theta_max_deg, p.overlap, p.instrument_height_m)


def closed_form_plan(
    site: Site, cf_limits: Limits, targets: Targets, limits: SightLimits, rule: OverlapRule
) -> tuple[SolveResult, CoverageProblem, list[str]]:
    """Closed-form candidates, moved where misplaced, redundant ones dropped (3.1.3) under the overlap ``rule``.

    Returns the result (indices into the returned problem's candidates), that problem, and a log of the moves and
    removals. The status is ``incomplete`` when the closed form leaves targets uncovered.
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


def closed_form_method(run: MethodInput) -> MethodOutput:
    """The dissertation's own plan: closed-form stations after the final step (3.1.3)."""
    cf_limits = closed_form_limits(run.validation)
    result, problem, log = closed_form_plan(
        run.site, cf_limits, run.problem.targets, run.limits, run.registration.checked_rule
    )
    return MethodOutput(result, problem, run.problem, tuple(log))


def milp_method(run: MethodInput) -> MethodOutput:
    """The set-cover MILP (connected under the overlap rule), after pricing over the plane where the coverage
    regions apply; the plane bound and, for zone registration, the connected plane bound beside it."""
    options, limits = run.options, run.limits
    log: list[str] = []
    pricing_on = options.pricing and regions_apply(limits)
    if run.surfaces is not None:
        log.append(f"bound over the pool ({PLANE_OFF})")
    elif options.pricing and not pricing_on:
        log.append("pricing off: coverage regions do not model the incidence-dependent view error with 3-D incidence")
    if run.walks_ahead is not None:
        return _milp(run, run.walks_ahead, log, pricing_on)
    ahead = _walks_ahead(run) if pricing_on and run.surfaces is None else None
    try:
        return _milp(run, ahead, log, pricing_on)
    finally:
        if ahead is not None:
            ahead.close()


def early_walks(
    site: Site, options: PlanOptions, registration: Registration, limits: SightLimits, targets: Targets
) -> WalksAhead | None:
    """The connected plane bound's ring walks started on a second core before the pool's coverage is built, where a
    plain MILP run of walls with ``zone`` registration will form that bound: they need only the targets (every piece
    counted as seen, as the coverage build refuses a piece nothing sees; the bound checks it) and their regions, the
    inner ones from the caller (:meth:`WalksAhead.share`, see :func:`planner.plan.run.plan_single`). None: not
    started."""
    rule = registration.rule
    plain = options.method == "milp" and not options.hours and options.pricing and regions_apply(limits)
    if not plain or rule is None or rule.overlap <= 0:
        return None
    if registration.mode != "zone" and not (registration.mode == "site" and areas_are_zone_sides(site)):
        return None
    walks = RingWalks(
        site,
        targets,
        limits,
        rule.overlap,
        np.ones(len(targets), dtype=bool),
        cache={},
        spaces={},
        outer_regions=OuterRegions(),
    )
    return WalksAhead.start(walks, CONNECTED_WORK_PATCHES, regions_later=True)


def areas_are_zone_sides(site: Site) -> bool:
    """True where ``site`` registration will likely bundle the stations by zone-side (each accessible area one
    zone-side's space: rooms without doors, one outside zone a frame, no stairs), so that the connected plane bound is
    formed: a guess made before the pool exists, to start its walks early; :func:`zone_side_groups` decides on the pool
    (where it says no, the walks started are ended unused)."""
    if getattr(site, "stairs", ()):
        return False
    sides = [(z.id, s) for z in site.zones for s in z.scan_side.sides]
    areas = accessible_areas(site)
    return len(sides) == len(areas) == len(set(areas.values()))


def _walks_ahead(run: MethodInput) -> WalksAhead | None:
    """The connected plane bound's ring walks started on a second core (:mod:`planner.bounds.ring_ahead`) where the run
    will likely form that bound: an overlap rule and registration groups that are the zone-sides."""
    rule = run.registration.rule
    share = rule.overlap if rule else 0.0
    groups, links = run.registration.groups(run.problem.candidates)
    if share <= 0 or not zone_side_groups(run.problem.candidates, groups, links):
        return None
    problem = run.problem
    walks = RingWalks(
        run.site,
        problem.targets,
        run.limits,
        share,
        problem.by_target.getnnz(axis=1) > 0,
        cache=run.region_cache,
        spaces=run.spaces,
        outer_regions=run.outer,
    )
    return WalksAhead.start(walks, CONNECTED_WORK_PATCHES)


def _milp(run: MethodInput, ahead: WalksAhead | None, log: list[str], pricing_on: bool) -> MethodOutput:
    """:func:`milp_method` after its checks, with the walks started ahead (or None)."""
    site, options, limits, problem = run.site, run.options, run.limits, run.problem
    pricing = None
    if pricing_on:
        limit_s, cache = options.pricing_time_limit_s, run.region_cache
        with progress.ticking("pricing (coverage regions)", limit_s):
            problem, pricing = price_plane(
                site, problem, limits, time_limit_s=limit_s, cache=cache, spaces=run.spaces, outer=run.outer
            )
        log.append(pricing.summary())
    k = options.milp.k
    if (
        k > 1 and regions_apply(limits) and options.regions and run.surfaces is None
    ):  # k distinct positions wherever a plan may need them
        problem, line = twin_candidates(
            Sight(site=site, limits=limits, scanner=run.validation.scanner), problem, k, run.spaces, run.region_cache
        )
        log.append(line)
    aligned, said = aligned_first(run, problem, pricing.plane_bound) if pricing is not None else (None, None)
    log += [said] if said else []
    if aligned is not None:
        problem = aligned.problem
    p = site.parameters
    groups, links = run.registration.groups(problem.candidates)
    # the precision weights (a float per pair) only where the model reads them: combined precision
    combined = options.milp.precision == "combined"
    inst = cover_instance(
        problem,
        scanner=run.validation.scanner if combined else None,
        budget=p.budget if combined else None,
        sigma_req_m=p.sigma_req_m if combined else None,
        name=site.name,
        groups=groups,
        links=links,
        incidence_model=p.incidence_model,
    )
    if aligned is not None:
        result = aligned.result
    else:
        with progress.ticking(f"solving ({options.milp.backend})", options.milp.time_limit_s):
            result = solve(with_columns(inst, run.surfaces), options.milp)
    if run.surfaces is not None:
        result = replace(result, info={**result.info, "plane_off": PLANE_OFF})
    if result.status is Status.INFEASIBLE and options.milp.rule is not None and "count" not in result.info:
        raise no_pool_plan(site, options)
    if pricing is not None:
        result = with_plane_bound(result, pricing) if k == 1 else with_k_plane_bound(result, pricing, k)
        if result.scope != "plane" and zone_side_groups(problem.candidates, groups, links) and result.selected:
            share = run.registration.rule.overlap if run.registration.rule else 0.0
            duals, counts = np.asarray(pricing.duals), plan_counts(problem, result.selected)
            refine, cache = options.plane_refine_steps, run.region_cache

            def bound() -> ConnectedPlaneBound:
                return connected_plane_bound(
                    site,
                    problem,
                    limits,
                    share,
                    duals,
                    counts,
                    cache=cache,
                    refine_steps=refine,
                    spaces=run.spaces,
                    outer_regions=run.outer,
                    ahead=ahead,
                )

            if ahead is not None and ahead is run.walks_ahead and not refine:
                return MethodOutput(result, problem, problem, tuple(log), pending=_in_thread(bound))
            cb = bound()
            result = with_connected_plane_bound(result, cb)
            log.append(cb.summary())
    return MethodOutput(result, problem, problem, tuple(log))


def _in_thread(work: Callable[[], ConnectedPlaneBound]) -> Future[ConnectedPlaneBound]:
    """``work`` run on a daemon thread of its own: the walks ahead answer on their own core while the caller checks the
    plan (the thread mostly waits on their pipe, so it takes little of the interpreter from the caller); a run that
    fails meanwhile does not wait for it to exit."""
    done: Future[ConnectedPlaneBound] = Future()

    def target() -> None:
        if not done.set_running_or_notify_cancel():
            return
        try:
            done.set_result(work())
        except BaseException as exc:  # handed to the caller, raised where it takes the result
            done.set_exception(exc)

    threading.Thread(target=target, name="connected-bound", daemon=True).start()
    return done


def finish_bound(result: SolveResult, pending: Future[ConnectedPlaneBound]) -> tuple[SolveResult, str]:
    """``result`` with the connected plane bound that ``pending`` finishes (:attr:`MethodOutput.pending`), and the
    bound's log line."""
    cb = pending.result()
    return with_connected_plane_bound(result, cb), cb.summary()


def no_pool_plan(site: Site, options: PlanOptions) -> PlannerError:
    """The refusal of a connected plan the solver proved impossible over the candidate pool only (no proof over
    the plane was found: :func:`planner.plan.run.unlinkable` found none), with what to try."""
    rules = ["every piece covered"] + ([f"k = {options.milp.k}"] if options.milp.k > 1 else [])
    err = InfeasibleError(
        f"milp found no plan over the candidate pool (scope: pool; no proof over the plane): no set of candidates "
        f"meets {', '.join(rules)}, registration overlap connected; try a finer pool (--grid-spacing 2), shorter "
        "pieces (--target-spacing 0.5), a smaller --overlap, or --no-overlap"
    )
    return err.located(site.source) if site.source else err


def greedy_method(run: MethodInput) -> MethodOutput:
    """Chvátal's greedy: with combined precision, the greedy that adds views' information; under an overlap
    rule, the connected greedy (the plain one where it finds no connected cover); else the plain greedy."""
    site, options, problem = run.site, run.options, run.problem
    log: tuple[str, ...] = ()
    if options.combined and run.limits.precision is not None:
        from planner.solve.combined import combined_greedy

        result = combined_greedy(problem, run.limits.precision)
    elif (rule := run.registration.rule) is not None and rule.overlap > 0:
        groups, links = run.registration.groups(problem.candidates)
        inst = with_columns(cover_instance(problem, name=site.name, groups=groups, links=links), run.surfaces)
        result = connected_greedy_plan(inst, rule)
        if not result.selected:
            log = ("greedy: no cover connected under the overlap rule found; plain greedy plan instead",)
            result = greedy_cover(_columns(problem.by_candidate, run.surfaces))
    else:
        result = greedy_cover(_columns(problem.by_candidate, run.surfaces))
    return MethodOutput(result, problem, problem, log)


def _columns(walls: sp.csr_matrix, extra: sp.csr_matrix | None) -> sp.csr_matrix:
    """The wall coverage with the surface columns appended (the wall coverage alone without them)."""
    if extra is None:
        return walls
    return sp.hstack([walls, extra], format="csr").astype(bool)


Method = Callable[[MethodInput], MethodOutput]

#: the methods by ``--method`` name
REGISTRY: dict[str, Method] = {"closed-form": closed_form_method, "greedy": greedy_method, "milp": milp_method}
#: their names, in the order ``--method`` lists them
METHODS: tuple[str, ...] = tuple(REGISTRY)
