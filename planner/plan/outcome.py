"""A plan's outcome as figures, the report and the exports need it: the site, the stations, what they cover, their
tripod discs and (optionally) the network check.

Built either from a :class:`~planner.plan.Plan` just computed or from a ``plan.json`` (``planner report
PLAN.json``); both recompute the coverage of the chosen stations, so what is drawn and exported is checked afresh,
not copied from the solver.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from planner.core.checks import argument
from planner.coverage.relation import Registration
from planner.coverage.sight import Sight
from planner.coverage.stations import StationCoverage, station_coverage
from planner.coverage.visibility import SightLimits
from planner.network.check import NetworkReport
from planner.plan.plan_dict import plan_to_dict
from planner.plan.result import Plan
from planner.plan.surfaces import SurfaceSetup
from planner.plan.verify import VerifyReport
from planner.site.candidate import Candidate
from planner.site.model import Site
from planner.site.validate import ValidationReport


@dataclass(frozen=True, eq=False, kw_only=True)
class Outcome:
    """Everything shown about one plan. ``meta`` is the plan.json dictionary (method, status, bound ...; its
    ``surfaces``: the floors and ceilings' verification, where the plan has them); ``surfaces``: the floor and
    ceiling patches and the rules they were planned under (None: walls only, or not rebuilt); ``registration``:
    the plan's, whose pairs the map and the network check draw."""

    site: Site
    validation: ValidationReport
    limits: SightLimits
    stations: tuple[Candidate, ...]
    coverage: StationCoverage
    verification: VerifyReport
    tripod_radius_m: dict[str, float]
    meta: dict[str, Any]
    registration: Registration
    network: NetworkReport | None = None
    comparison: tuple[dict[str, Any], ...] = field(default=())
    surfaces: SurfaceSetup | None = None

    @property
    def sight(self) -> Sight:
        """The site seen under the plan's limits, by its scanner: what the network check of it takes."""
        return Sight(site=self.site, limits=self.limits, scanner=self.validation.scanner)

    def _repr_html_(self) -> str:
        from planner.core.text import summary_html

        return summary_html(self, "Outcome")

    def summary(self) -> str:
        return (
            f"{self.site.name}: {len(self.stations)} stations ({self.meta.get('method', '?')}), "
            f"{self.coverage.percent_length:.3f} % of wall length covered; "
            + self.verification.summary().splitlines()[0]
        )


def outcome_from_plan(
    plan: Plan, network: NetworkReport | None = None, comparison: Sequence[dict[str, Any]] = ()
) -> Outcome:
    """The outcome of a plan computed in this process."""
    argument(plan, Plan, "plan")
    argument(network, (NetworkReport, type(None)), "network")
    sight = plan.problem.sight
    return Outcome(
        site=plan.site,
        validation=plan.validation,
        limits=sight.limits,
        stations=plan.stations,
        coverage=station_coverage(sight, plan.stations, plan.options.target_spacing_m),
        verification=plan.verification,
        tripod_radius_m={s.id: d.radius_m for s, d in zip(plan.stations, plan.tripods)},
        meta=plan_to_dict(plan),
        registration=plan.problem.registration,
        network=network,
        comparison=tuple(comparison),
        surfaces=plan.problem.surfaces if plan.surfaces is not None else None,
    )
