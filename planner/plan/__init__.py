"""From a site to a verified plan (the pipeline's driver): options, the run, re-verification and outcomes.

- :mod:`planner.plan.run`: :class:`PlanOptions`, :func:`plan_site` (candidates -> coverage -> method ->
  registration check -> verification) and :class:`Plan`;
- :mod:`planner.plan.verify`: re-verification of any plan on a fine sampling of every wall;
- :mod:`planner.plan.outcome`: a plan with its coverage, network check and figures' inputs, from a run or a file.
"""

from planner.plan.run import (
    METHODS,
    Plan,
    PlanOptions,
    build_problem,
    closed_form_limits,
    coverage_problem,
    placed_stations,
    plan_limits,
    plan_site,
    registration_check,
    sight_limits,
    site_candidates,
    unseen_error,
)

__all__ = [
    "METHODS",
    "Plan",
    "PlanOptions",
    "build_problem",
    "closed_form_limits",
    "coverage_problem",
    "placed_stations",
    "plan_limits",
    "plan_site",
    "registration_check",
    "sight_limits",
    "site_candidates",
    "unseen_error",
]
