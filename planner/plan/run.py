"""From a site to a verified plan: candidates -> coverage -> method -> verification."""

from __future__ import annotations

import math
import time
from collections import Counter
from dataclasses import dataclass, field, replace
from typing import Any

import networkx as nx
import numpy as np

from planner import progress
from planner.candidates.axis import axis_candidates
from planner.candidates.closed_form import Limits
from planner.candidates.complete import complete_candidates
from planner.candidates.from_regions import whole_side_candidates
from planner.candidates.pool import PoolOptions, candidate_pool, dedupe
from planner.checks import SAMPLING_M, argument, count, flag, real
from planner.coverage.links import default_registration, registration_groups
from planner.coverage.matrix import CoverageProblem, build_coverage
from planner.coverage.overlap import OverlapRule, overlap_graph, piece_lengths, rule_of
from planner.coverage.regions import FrameSpace, regions_apply
from planner.coverage.targets import Targets, make_targets
from planner.coverage.visibility import SightLimits, sight_limits
from planner.errors import InfeasibleError, UsageError
from planner.plan.verify import VerifyReport, verify_stations
from planner.site.candidate import Candidate
from planner.site.model import Site
from planner.site.validate import ValidationReport, validate_site
from planner.solve.closed_form import closed_form_plan
from planner.solve.greedy import connected_greedy_plan, greedy_cover
from planner.solve.instance import cover_instance
from planner.solve.milp import MilpOptions, solve
from planner.solve.plane import price_plane, with_plane_bound
from planner.solve.plane_ring import connected_plane_bound, plan_counts, with_connected_plane_bound
from planner.solve.result import SolveResult
from planner.solve.tripod import TripodDisc, tripod_discs, tripod_heights_line

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
    tripod: bool = False
    recentre: bool = False
    registration: str | None = None  # zone | site; None: site where zones are placed or openings given
    regions: bool = True
    pricing: bool = True
    pricing_time_limit_s: float = 120.0
    memory_limit_bytes: int | None = None  # None: a share of the available memory (planner.plan.memory_guard)

    def for_site(self, site: Site) -> PlanOptions:
        """These options with the MILP's ``overlap="site"`` resolved to ``site``'s overlap share."""
        milp = self.milp.for_site(site.parameters.overlap)
        return self if milp is self.milp else replace(self, milp=milp)

    def checked_rule(self, site: Site) -> OverlapRule:
        """The rule a plan's registration is checked on: the one it was planned under, else the site's
        (the closed form, or planning with no rule, is checked at the site's share)."""
        rule = self.milp.for_site(site.parameters.overlap).rule
        return rule if self.method != "closed-form" and rule else rule_of(site.parameters.overlap)

    @property
    def combined(self) -> bool:
        """Views add information (``--precision combined``), for every method."""
        return self.precision and self.milp.precision == "combined"

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise UsageError(f"unknown method (known: {', '.join(METHODS)})", field="method", value=self.method)
        argument(self.pool, PoolOptions, "pool")
        argument(self.milp, MilpOptions, "milp")
        real(self.target_spacing_m, "target_spacing_m", above=0)
        real(self.verify_spacing_m, "verify_spacing_m", at_least=SAMPLING_M[0])  # finer than 1 mm: no survey resolution
        real(self.pricing_time_limit_s, "pricing_time_limit_s", at_least=0)
        for name in ("incidence_3d", "precision", "tripod", "recentre", "regions", "pricing"):
            flag(getattr(self, name), name)
        if self.memory_limit_bytes is not None:
            count(self.memory_limit_bytes, "memory_limit_bytes", 1)
        if self.registration not in (None, "zone", "site"):
            raise UsageError("must be 'zone', 'site' or None", field="registration", value=self.registration)
        if self.milp.k != 1 and self.method != "milp":  # the greedy and the closed form cover each piece once
            raise UsageError(
                f"k > 1 needs method='milp' (method {self.method!r} covers each piece once)",
                field="k",
                value=self.milp.k,
            )
        if self.milp.precision == "combined" and not self.precision:
            raise UsageError(
                "combined precision needs the precision check (precision=True)", field="precision", value=self.precision
            )


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
    registration: dict[str, int] = field(default_factory=dict)
    tripods: tuple[TripodDisc, ...] = ()

    @property
    def connected(self) -> bool:
        """Every zone-side's stations form one registration bundle."""
        return all(n <= 1 for n in self.registration.values())

    def count_by_side(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for s in self.stations:
            out[s.side.value] = out.get(s.side.value, 0) + 1
        return out

    def _repr_html_(self) -> str:
        from planner.text import summary_html

        return summary_html(self, f"Plan: {len(self.stations)} stations")

    def summary(self) -> str:
        by_zone: dict[tuple[str, str], int] = {}
        for s in self.stations:
            by_zone[(s.zone, s.side.value)] = by_zone.get((s.zone, s.side.value), 0) + 1
        sides = self.count_by_side()
        w = max([10] + [len(z) + 1 for z, _ in by_zone])  # long room names (IFC) keep their column
        lines = [
            f"instance {self.site.name}, method {self.result.method}: {self.result.summary(self.time_label)}",
            f"presolve: {self.result.info['presolve']}" if "presolve" in self.result.info else "",
            f"stations: {len(self.stations)} (inside {sides.get('inside', 0)}, outside {sides.get('outside', 0)}); "
            f"candidates {self.problem_size['candidates']}, targets {self.problem_size['targets']}",
            f"{'zone':<{w}}{'side':<9}{'stations':>9}",
        ]
        lines += [f"{z:<{w}}{s:<9}{n:>9}" for (z, s), n in by_zone.items()]
        lines += list(self.log)
        lines.append(self._accuracy_line())
        lines.append(self._bound_line())
        broken = {g: n for g, n in self.registration.items() if n > 1}
        lines.append(
            "registration: every registration group connected under the overlap relation"
            if not broken
            else "registration: not connected: " + ", ".join(f"{g} in {n} parts" for g, n in broken.items())
        )
        if self.tripods:
            radii = [d.radius_m for d in self.tripods]
            lines.append(
                f"tripod discs: radius min {min(radii):.3f} m, median {float(np.median(radii)):.3f} m, max {max(radii):.3f} m"
                + (" (stations recentred)" if self.options.recentre else " (centred on the planned stations)")
            )
            lines.append(tripod_heights_line(self.tripods, self.site.parameters))
        lines.append(self.verification.summary())
        return "\n".join(line for line in lines if line)

    def _bound_line(self) -> str:
        """Both bounds, each with what it holds over: the pool's (the MILP's) and the plane's (pricing)."""
        r = self.result
        scope = r.scope
        if scope is None:
            return ""
        info = r.info
        pool = info.get("pool_bound", r.bound)
        plane = info.get("plane_bound")
        pool_s = f"{pool:g} over the candidate pool (MILP)" if pool is not None else "none over the pool"
        plane_s = (
            f"{plane:g} over every position in the plane (cover LP priced over the coverage regions; "
            f"{info.get('certificate', {}).get('assumes', 'pieces of the target spacing')})"
            if plane is not None
            else "no plane bound (pricing off)"
        )
        conn = info.get("connected_plane_bound")
        if conn is not None:
            plane_s += f"; connected plans: {conn:g} over every position in the plane (ring walk over patches)"
        head = (
            "bound scope: plane (no plan from any positions in the plane has fewer stations)"
            if scope == "plane"
            else "bound scope: pool (the plan is proven only over the candidate pool)"
            if r.status.value == "optimal"
            else "bound scope: pool"
        )
        return f"{head}; bounds: {pool_s}; {plane_s}"

    @property
    def time_label(self) -> str:
        """What the result's time covers: the solver alone (on how many threads), or the whole tiled run."""
        if self.result.method == "milp-tiles":
            return "whole tiled run: pool, coverage, tiles, bound, stitch and search"
        threads = self.options.milp.threads if self.result.method == "milp" else 1
        return f"solver alone, {threads} thread{'s' if threads > 1 else ''}"

    def _accuracy_line(self) -> str:
        """How views were judged: incidence model, precision mode, stand-off, and theta_max (derived: per range)."""
        p, o = self.site.parameters, self.options
        mode = "off" if not o.precision else "combined" if o.combined else "single"
        theta = self.validation.theta_limit
        th = theta.summary() if theta is not None else f"theta_max {p.theta_max_deg:g} deg"
        return f"accuracy: view error e(S, theta), incidence model {p.incidence_model}, precision {mode}, stand-off {p.min_standoff_m:g} m; {th}"


def closed_form_limits(validation: ValidationReport) -> Limits:
    p = validation.site.parameters
    return Limits(validation.range_limit.max_slant_range_m, p.theta_max_deg, p.overlap, p.instrument_height_m)


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


def plan_limits(validation: ValidationReport, options: PlanOptions) -> SightLimits:
    """The sight limits of a run: :func:`sight_limits` with the options' incidence and precision modes."""
    return sight_limits(validation, options.incidence_3d, options.precision, options.combined)


def build_problem(
    site: Site,
    options: PlanOptions,
    validation: ValidationReport | None = None,
    *,
    spaces: dict[str, FrameSpace] | None = None,
    region_cache: dict[int, Any] | None = None,
) -> CoverageProblem:
    """Candidates, targets and coverage of a site; refuses a problem with a target no position sees.

    ``spaces`` and ``region_cache``, when given, keep the frame spaces and coverage regions drawn for the
    region candidates (keyed by piece index of the problem's targets), for pricing to reuse.

    Raises
    ------
    InfeasibleError
        Listing (up to five) targets by id and position, each with why no position sees it, before any
        solver runs.
    InputError
        When the estimated memory of the work exceeds ``options.memory_limit_bytes`` (exit 3).
    """
    problem, unseen, reasons = coverage_problem(site, options, validation, spaces=spaces, region_cache=region_cache)
    if unseen.size:
        err = unseen_error(problem, unseen, reasons)
        raise err.located(site.source) if site.source else err
    return problem


def coverage_problem(
    site: Site,
    options: PlanOptions,
    validation: ValidationReport | None = None,
    *,
    spaces: dict[str, FrameSpace] | None = None,
    region_cache: dict[int, Any] | None = None,
) -> tuple[CoverageProblem, np.ndarray, dict[int, str]]:
    """:func:`build_problem` without the refusal: the problem, the pieces no candidate sees (after every
    unseen piece got a candidate from its own region) and, per such piece, why its region is empty."""
    argument(site, Site, "site")
    argument(options, PlanOptions, "options")
    validation = validation or validate_site(site)
    limits = plan_limits(validation, options)
    from planner.plan.memory_guard import check_memory  # issue 17: refuse what will not fit, before building

    check_memory(
        site,
        options.target_spacing_m,
        options.pool.grid_spacing_m,
        closed_form_limits(validation).max_slant_range_m,
        options.memory_limit_bytes,
    )
    targets = make_targets(site, options.target_spacing_m)
    spaces = {} if spaces is None else spaces
    region_cache = {} if region_cache is None else region_cache
    pool = site_candidates(site, options, validation, targets, limits, spaces, region_cache)
    problem = build_coverage(site, pool, targets, limits, step="coverage build")
    reasons: dict[int, str] = {}
    if options.regions and regions_apply(limits):
        # a candidate from its own region for every piece still unseen; refused only when that is empty
        problem, reasons = complete_candidates(site, problem, limits, spaces, region_cache)
    return problem, problem.uncoverable(), reasons


def site_candidates(
    site: Site,
    options: PlanOptions,
    validation: ValidationReport,
    targets: Targets,
    limits: SightLimits,
    spaces: dict[str, FrameSpace] | None = None,
    region_cache: dict[int, Any] | None = None,
) -> list[Candidate]:
    """The candidate pool of a site (the one home of it: the single model and the tiles both take it): the
    closed form, field samples and grid of :func:`planner.candidates.pool.candidate_pool`; with regions, one
    station per zone-side where one sees all of it; a candidate per maximal cell of the regions along every
    room's medial axis and the rings round outside zones; duplicates removed."""
    pool = candidate_pool(site, closed_form_limits(validation), options.pool)
    exact = options.regions and regions_apply(limits)
    if exact:  # one station for a whole zone-side, found exactly where one exists
        pool = pool + whole_side_candidates(site, targets, limits, spaces, region_cache)
    return dedupe(
        pool
        + axis_candidates(site, targets, limits, spaces, region_cache, cells=exact, step_m=options.target_spacing_m)
    )


def plan_site(site: Site, options: PlanOptions | None = None, validation: ValidationReport | None = None) -> Plan:
    """Plan the stations of a site with the chosen method, check registration, and verify the plan.

    ``validation``: the site's :func:`validate_site` report when the caller has it (the command line validates
    once per run and hands it on); else it is made here.

    Raises
    ------
    InfeasibleError
        When some wall piece is seen by no candidate of the pool (listed by id and position).
    """
    argument(site, Site, "site")
    argument(options, (PlanOptions, type(None)), "options")
    options = (options or PlanOptions()).for_site(site)
    argument(validation, (ValidationReport, type(None)), "validation")
    if validation is None:
        validation = validate_site(site)
    elif validation.site is not site:
        raise UsageError("validation is the report of another site", field="validation", value=validation.site.name)
    limits = plan_limits(validation, options)
    cf_limits = closed_form_limits(validation)
    start = time.perf_counter()
    spaces: dict[str, FrameSpace] = {}
    region_cache: dict[int, Any] = {}  # regions drawn once: for the whole-side candidates, then pricing
    problem = build_problem(site, options, validation, spaces=spaces, region_cache=region_cache)
    targets, pool = problem.targets, problem.candidates
    log: list[str] = [
        f"coverage built in {time.perf_counter() - start:.2f} s "
        f"({len(pool):,} candidates of the pool, {problem.by_candidate.nnz:,} candidate-target pairs"
        f"{', before pricing' if options.method == 'milp' and options.pricing else ''})"
    ]
    pool_pairs = int(problem.by_candidate.nnz)
    if options.method == "closed-form":
        result, problem, extra = closed_form_plan(site, cf_limits, targets, limits)
        log += extra
    elif options.method == "milp":
        p = site.parameters
        pricing_on = options.pricing and regions_apply(limits)
        if options.pricing and not pricing_on:
            log.append(
                "pricing off: coverage regions do not model the incidence-dependent view error with 3-D incidence"
            )
        if pricing_on:
            with progress.ticking("pricing (coverage regions)", options.pricing_time_limit_s):
                problem, pricing = price_plane(
                    site, problem, limits, time_limit_s=options.pricing_time_limit_s, cache=region_cache, spaces=spaces
                )
            log.append(pricing.summary())
            pool, pool_pairs = problem.candidates, int(problem.by_candidate.nnz)
        mode = options.registration or default_registration(site)
        reach = (options.milp.rule.max_link_m if options.milp.rule else None) or limits.effective_range_m
        groups, links = registration_groups(site, problem.candidates, mode, reach)
        inst = cover_instance(
            problem,
            scanner=validation.scanner,
            budget=p.budget,
            sigma_req_m=p.sigma_req_m,
            name=site.name,
            groups=groups,
            links=links,
            incidence_model=p.incidence_model,
        )
        with progress.ticking(f"solving ({options.milp.backend})", options.milp.time_limit_s):
            result = solve(inst, options.milp)
        if pricing_on:
            result = with_plane_bound(result, pricing)
            if result.scope != "plane" and mode == "zone" and links is None and result.selected:
                share = options.milp.rule.overlap if options.milp.rule else 0.0
                cb = connected_plane_bound(
                    site,
                    problem,
                    limits,
                    share,
                    np.asarray(pricing.duals),
                    plan_counts(problem, result.selected),
                    cache=region_cache,
                )
                result = with_connected_plane_bound(result, cb)
                log.append(cb.summary())
    elif options.combined and limits.precision is not None:
        from planner.solve.combined import combined_greedy

        result = combined_greedy(problem, limits.precision)
    elif (rule := options.milp.rule) is not None and rule.overlap > 0:  # greedy under the rule
        groups, links = registration_groups(
            site,
            problem.candidates,
            options.registration or default_registration(site),
            rule.max_link_m or limits.effective_range_m,
        )
        result = connected_greedy_plan(cover_instance(problem, name=site.name, groups=groups, links=links), rule)
        if not result.selected:
            log.append("greedy: no cover connected under the overlap rule found; plain greedy plan instead")
            result = greedy_cover(problem.by_candidate)
    else:
        result = greedy_cover(problem.by_candidate)
    rule = options.checked_rule(site)
    registration, partners = registration_check(
        problem, result.selected, rule, site, options.registration, rule.max_link_m or limits.effective_range_m
    )
    if rule.overlap == 0:
        registration, log = {}, log + ["registration: not required (overlap 0)"]
    stations, tripods = placed_stations(site, problem, result.selected, options, partners)
    verification = verify_stations(site, stations, limits, options.verify_spacing_m)
    # the pool's size (after pricing for the MILP); the closed form solves over its own stations, not counted here
    size = {"candidates": len(pool), "targets": len(targets), "pairs": pool_pairs}
    return Plan(
        site, options, validation, result, tuple(stations), verification, size, tuple(log), registration, tripods
    )


def placed_stations(
    site: Site,
    problem: CoverageProblem,
    selected: tuple[int, ...],
    options: PlanOptions,
    partners: dict[int, list[int]],
) -> tuple[list[Candidate], tuple[TripodDisc, ...]]:
    """The chosen stations and, with ``options.tripod`` or ``options.recentre``, their tripod discs (relied
    pieces only, checked on centre and rim); ``recentre`` moves each station to its disc's centre."""
    stations = [problem.candidates[i] for i in selected]
    if not (options.tripod or options.recentre):
        return stations, ()
    tripods = tuple(tripod_discs(site, problem, selected, problem.limits, partners, options.recentre))
    if options.recentre:
        stations = [replace(s, x=d.centre[0], y=d.centre[1]) for s, d in zip(stations, tripods)]
    return stations, tripods


def registration_check(
    problem: CoverageProblem,
    selected: tuple[int, ...],
    rule: OverlapRule,
    site: Site | None = None,
    mode: str | None = "zone",
    reach_m: float = math.inf,
) -> tuple[dict[str, int], dict[int, list[int]]]:
    """Components of each registration group's chosen stations under the overlap relation, computed afresh
    with networkx (independent of any solver), and each station's registration partners.

    Groups: each zone-side (``mode="zone"``), or each accessible area of ``site`` with links through
    openings (``"site"``; ``None``: :func:`default_registration`)."""
    lengths = piece_lengths(problem.targets.s0_m, problem.targets.s1_m)
    chosen = [problem.candidates[i] for i in selected]
    xy = np.array([c.xy for c in chosen], dtype=float).reshape(-1, 2)
    mode = mode or (default_registration(site) if site is not None else "zone")
    labels, links = (
        registration_groups(site, chosen, mode, reach_m)
        if site is not None
        else (tuple((c.zone, c.side.value) for c in chosen), None)
    )
    groups: dict[Any, list[int]] = {}  # labels: (zone, side) pairs or ("area", k)
    for k, label in enumerate(labels):
        groups.setdefault(label, []).append(k)
    out, partners = {}, {}
    sub = problem.by_candidate[list(selected)] if selected else problem.by_candidate[:0]
    for label, nodes in groups.items():
        g = overlap_graph(sub, lengths, nodes, rule, xy, links)
        names = sorted({f"{chosen[k].zone}/{chosen[k].side.value}" for k in nodes})
        key = (
            "/".join(label)
            if mode == "zone"
            else f"area {label[1]} ({', '.join(names[:4])}{', ...' if len(names) > 4 else ''})"
        )
        out[key] = nx.number_connected_components(g)
        partners.update({selected[n]: sorted(selected[m] for m in g.neighbors(n)) for n in nodes})
    return out, partners
