"""The resolved problem of a run (:class:`Problem`, made by :func:`resolve`): the site validated once, the one
sight (limits), the one registration rule and scope, and the strategy. Every later stage takes it, or the
:class:`~planner.plan.result.Plan` that carries it, and none re-derives what it holds."""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace
from functools import cached_property
from typing import Any

from planner.core.checks import argument
from planner.core.errors import UsageError
from planner.coverage.overlap import OverlapRule, SiteShare, rule_of
from planner.coverage.relation import Registration
from planner.coverage.sight import Sight, sight_of
from planner.coverage.targets import Targets, make_targets
from planner.coverage.visibility import SightLimits
from planner.plan.options import PlanOptions
from planner.plan.strategy import Strategy, resolve_strategy
from planner.plan.surfaces import SurfaceSetup, surface_setup
from planner.site.model import Site
from planner.site.validate import ValidationReport


@dataclass(frozen=True, kw_only=True)
class Problem:
    """What a run plans, resolved once. ``options``: as given, with the registration rule and scope filled in
    (``options.milp.overlap`` is ``rule``, ``options.registration`` the scope) and the adjustments made. ``sight``: the
    site and its sight limits, which build every coverage matrix of the run. ``registration``: the scope, the rule the
    plan must meet and the rule it is checked on, and the link reach, which every stage that groups, relates or checks
    stations takes. ``strategy``: one model or tiles, with the reason. ``surfaces``: the floors and ceilings planned
    besides the walls (None: walls only). ``adjustments``: a line per option ``resolve`` changed."""

    site: Site
    validation: ValidationReport
    options: PlanOptions
    sight: Sight
    registration: Registration
    strategy: Strategy
    surfaces: SurfaceSetup | None = None
    adjustments: tuple[str, ...] = ()

    @property
    def rule(self) -> OverlapRule | None:
        """The registration rule the plan must meet (None: none, overlap share 0 or no rule asked for)."""
        return self.registration.rule

    @property
    def checked_rule(self) -> OverlapRule:
        """The rule the plan's registration is checked and reported on."""
        return self.registration.checked_rule

    @property
    def registration_reason(self) -> str:
        return self.registration.reason

    @property
    def limits(self) -> SightLimits:
        """The sight limits (S_max, theta_max, incidence, the accuracy rule) every coverage is built under."""
        return self.sight.limits

    @cached_property
    def targets(self) -> Targets:
        """The wall pieces of the run: every wall face cut into pieces of at most the target spacing."""
        return make_targets(self.site, self.options.target_spacing_m)

    def limits_line(self) -> str:
        """The sight limits in one line."""
        lim = self.limits
        precision = "off" if lim.precision is None else ("combined" if lim.precision.combined else "single view")
        return (
            f"limits: S_max {lim.max_slant_range_m:g} m, theta_max {lim.theta_max_deg:g} deg, incidence "
            f"{'3-D' if lim.incidence_3d else 'horizontal'}, precision {precision}"
        )

    def registration_line(self) -> str:
        """The registration rule and scope, with why, in one line."""
        return self.registration.line()

    def summary(self) -> str:
        """The resolved choices, a line each: what every number of the run was computed under, and the adjustments."""
        site = f"site {self.site.name}: {len(self.site.zones)} zone(s), instrument {self.validation.scanner.name}"
        lines = [site, self.limits_line(), self.registration_line(), self.strategy.line()]
        lines += [self.surfaces.line()] if self.surfaces is not None else []
        return "\n".join(lines + [f"adjusted: {a}" for a in self.adjustments])

    def to_dict(self) -> dict[str, Any]:
        lim = self.limits
        return {
            "max_slant_range_m": lim.max_slant_range_m,
            "theta_max_deg": lim.theta_max_deg,
            "incidence_3d": lim.incidence_3d,
            "rule": None if self.rule is None else asdict(self.rule),
            "registration": self.registration.mode,
            "registration_reason": self.registration.reason,
            "strategy": self.strategy.to_dict(),
            "adjustments": list(self.adjustments),
        }


def resolve(site: Site, options: PlanOptions | None = None, *, validation: ValidationReport | None = None) -> Problem:
    """Resolve a run once: validate ``site`` (unless its report is given), take its sight limits, its registration
    (:meth:`planner.coverage.relation.Registration.of`: the one place a run's scope and rules are decided) and the
    strategy (:func:`planner.plan.strategy.resolve_strategy`). Some options are adjusted, each listed in
    :attr:`Problem.adjustments` (printed by the summary, written to plan.json's ``resolved.adjustments``): pricing off
    with floors and ceilings (the patches are priced over no region) and with point spacing or the field-time objective
    (the regions know no spacing), tripod discs and recentring off with the latter (a disc keeps no setting), and the
    grid spacing the strategy chose filled in. Raises ClosureError or InputError from the validation of the site,
    UsageError where ``validation`` is another site's report or the options ask for what the site cannot give.
    """
    argument(site, Site, "site")
    argument(options, (PlanOptions, type(None)), "options")
    argument(validation, (ValidationReport, type(None)), "validation")
    options = options or PlanOptions()
    if validation is not None and validation.site is not site:
        raise UsageError("validation is the report of another site", field="validation", value=validation.site.name)
    share = site.parameters.overlap
    asked = options.milp.overlap
    rule = asked.rule(share) if isinstance(asked, SiteShare) else asked
    modes = {"incidence_3d": options.incidence_3d, "precision": options.precision, "combined": options.combined}
    validation, sight = sight_of(site, validation=validation, **modes)
    checked = rule if options.method != "closed-form" and rule else rule_of(share)
    registration = Registration.of(sight, options.registration, rule, checked)
    resolved = replace(options, milp=replace(options.milp, overlap=rule), registration=registration.mode)
    surfaces = surface_setup(site, validation, resolved, sight.limits)
    resolved, adjustments = _adjusted(resolved, surfaces is not None)
    strategy = resolve_strategy(site, resolved, validation)
    if resolved.pool.grid_spacing_m is None:  # the grid the strategy chose, else the pool's default, recorded
        grid = strategy.grid_spacing_m or resolved.pool.grid_m
        resolved = replace(resolved, pool=replace(resolved.pool, grid_spacing_m=grid))
        if strategy.grid_spacing_m:
            adjustments.append(f"grid spacing {grid:g} m: the strategy's")
    if strategy.tiles and (resolved.hours or surfaces is not None):  # neither is planned by tiles yet
        what = "point spacing and the field-time objective are" if resolved.hours else "floors and ceilings are"
        raise UsageError(
            f"{what} planned in one model for now, and this site is planned by tiles "
            f"({strategy.reason}); give --tiles off",
            field="tiles",
        )
    return Problem(
        site=site,
        validation=validation,
        options=resolved,
        sight=sight,
        registration=registration,
        strategy=strategy,
        surfaces=surfaces,
        adjustments=tuple(adjustments),
    )


def _adjusted(options: PlanOptions, surfaces: bool) -> tuple[PlanOptions, list[str]]:
    """The options with what the run cannot honour turned off, and a line for each change."""
    lines = []
    if surfaces and options.pricing:  # the patches are priced over no region: the bound holds over the pool
        options, lines = (
            replace(options, pricing=False),
            [
                "pricing off: the pool is not priced with floors and ceilings; the bound over walls and surfaces follows the solve"
            ],
        )
    if options.hours:  # pricing's regions know no spacing, tripod discs keep no setting
        off = [k for k in ("pricing", "tripod", "recentre") if getattr(options, k)]
        options = replace(options, pricing=False, tripod=False, recentre=False)
        lines += [f"{k} off: scan settings per station" for k in off]
    return options, lines


def recorded_problem(site: Site, meta: dict[str, Any]) -> Problem:
    """The problem a plan.json was made under, resolved again to check its stations: ``site`` (read with the
    parameters the plan recorded) under the plan's sight modes and registration (:func:`with_recorded_registration`)."""
    p = meta.get("parameters") or {}
    combined = (p.get("milp") or {}).get("precision") == "combined" or p.get("precision_mode") == "combined"
    options = PlanOptions.checking(
        incidence_3d=p.get("incidence") == "3d", precision=bool(p.get("precision", True)), combined=combined
    )
    return with_recorded_registration(resolve(site, options), meta)


def with_recorded_registration(problem: Problem, meta: dict[str, Any]) -> Problem:
    """``problem`` with the registration a plan.json records (its ``resolved`` scope, reason and rule, and the
    share its registration was checked at), so that a command starting from the plan file finds the plan's own
    pairs; a plan.json that records none leaves ``problem`` as it is."""
    resolved = meta.get("resolved")
    if not isinstance(resolved, dict) or resolved.get("registration") not in ("zone", "site"):
        return problem
    r = resolved.get("rule")
    rule = rule_of(float(r["overlap"]), float(r["min_shared_m"]), r["max_link_m"]) if isinstance(r, dict) else None
    share = (meta.get("registration") or {}).get("overlap")
    closed_form = meta.get("method") == "closed-form"
    checked = rule if rule and not closed_form else rule_of(float(share)) if share is not None else None
    reason = str(resolved.get("registration_reason") or "as planned")
    registration = Registration.of(problem.sight, resolved["registration"], rule, checked, reason)
    options = replace(problem.options, milp=replace(problem.options.milp, overlap=rule), registration=registration.mode)
    return replace(problem, options=options, registration=registration)
