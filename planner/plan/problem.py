"""The resolved problem of a run (:class:`Problem`, made by :func:`resolve`): the site validated once, the one
sight (limits), the one registration rule and scope, and the strategy. Every later stage takes it, or the
:class:`~planner.plan.result.Plan` that carries it, and none re-derives what it holds."""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property
from typing import Any

from planner.core.checks import argument
from planner.core.errors import UsageError
from planner.coverage.links import default_registration
from planner.coverage.overlap import OverlapRule, SiteShare, rule_of
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
    """What a run plans, resolved once.

    ``options``: as given, with the registration rule and scope filled in (``options.milp.overlap`` is
    ``rule``, ``options.registration`` is ``registration``). ``sight``: the site and its sight limits, which
    build every coverage matrix of the run. ``rule``: the registration rule the plan must meet (None: none, the
    one place that decides "off": overlap share 0 or no rule asked for); ``checked_rule``: the rule its
    registration is checked and reported on (the planning rule, else the site's share). ``registration``:
    ``zone`` (one bundle per zone-side) or ``site`` (across the accessible areas), ``registration_reason``
    why. ``strategy``: one model or tiles, with the reason. ``surfaces``: the floors and ceilings planned
    besides the walls, with their patches and sight limits (None: walls only); pricing is then off, since the
    plane bound covers walls only.
    """

    site: Site
    validation: ValidationReport
    options: PlanOptions
    sight: Sight
    rule: OverlapRule | None
    checked_rule: OverlapRule
    registration: str
    registration_reason: str
    strategy: Strategy
    surfaces: SurfaceSetup | None = None

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
        rule = self.rule
        rule_text = (
            f"overlap {rule.overlap:.0%}"
            + (f", at least {rule.min_shared_m:g} m shared" if rule.min_shared_m else "")
            + (f", links up to {rule.max_link_m:g} m" if rule.max_link_m else "")
            if rule
            else "none"
        )
        return f"registration rule: {rule_text}; scope {self.registration} ({self.registration_reason})"

    def summary(self) -> str:
        """The resolved choices, a line each: what every number of the run was computed under."""
        site = f"site {self.site.name}: {len(self.site.zones)} zone(s), instrument {self.validation.scanner.name}"
        lines = [site, self.limits_line(), self.registration_line(), self.strategy.line()]
        return "\n".join(lines + ([self.surfaces.line()] if self.surfaces is not None else []))

    def to_dict(self) -> dict[str, Any]:
        lim = self.limits
        return {
            "max_slant_range_m": lim.max_slant_range_m,
            "theta_max_deg": lim.theta_max_deg,
            "incidence_3d": lim.incidence_3d,
            "rule": None
            if self.rule is None
            else {
                "overlap": self.rule.overlap,
                "min_shared_m": self.rule.min_shared_m,
                "max_link_m": self.rule.max_link_m,
            },
            "registration": self.registration,
            "registration_reason": self.registration_reason,
            "strategy": self.strategy.to_dict(),
        }


def resolve(site: Site, options: PlanOptions | None = None, *, validation: ValidationReport | None = None) -> Problem:
    """Resolve a run once: validate ``site`` (unless its report is given), take its sight limits, its
    registration rule and scope, and the strategy (:func:`planner.plan.strategy.resolve_strategy`).

    Raises
    ------
    ClosureError, InputError
        From the validation of the site.
    UsageError
        When ``validation`` is another site's report, or the options ask for what the site cannot give.
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
    checked = rule if options.method != "closed-form" and rule else rule_of(share)
    if options.registration is not None:
        registration, reason = options.registration, "asked for"
    else:
        default = default_registration(site)
        registration, reason = default.mode, default.reason
    resolved = replace(options, milp=replace(options.milp, overlap=rule), registration=registration)
    modes = {"incidence_3d": resolved.incidence_3d, "precision": resolved.precision, "combined": resolved.combined}
    validation, sight = sight_of(site, validation=validation, **modes)
    surfaces = surface_setup(site, validation, resolved, sight.limits)
    if surfaces is not None:  # the patches are priced over no region: the bound holds over the pool
        resolved = replace(resolved, pricing=False)
    if resolved.hours:  # pricing's regions know no spacing, tripod discs keep no setting (issue 47)
        resolved = replace(resolved, pricing=False, tripod=False, recentre=False)
    strategy = resolve_strategy(site, resolved, validation)
    if resolved.pool.grid_spacing_m is None:  # the grid the strategy chose, else the pool's default, recorded
        grid = strategy.grid_spacing_m or resolved.pool.grid_m
        resolved = replace(resolved, pool=replace(resolved.pool, grid_spacing_m=grid))
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
        rule=rule,
        checked_rule=checked,
        registration=registration,
        registration_reason=reason,
        strategy=strategy,
        surfaces=surfaces,
    )
