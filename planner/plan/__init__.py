"""From a site to a verified plan (the pipeline's driver): options, the methods, the run, re-verification and
outcomes.

- :mod:`planner.plan.options`: :class:`PlanOptions` and the sight limits they give;
- :mod:`planner.plan.methods`: the planning methods by name (closed form, greedy, MILP), one registry;
- :mod:`planner.plan.run`: :func:`plan_site` (candidates -> coverage -> method -> registration check ->
  verification);
- :mod:`planner.plan.result`: :class:`Plan`, a verified plan and its summary;
- :mod:`planner.plan.registration`: the registration check and the stations' tripod discs;
- :mod:`planner.plan.verify`: re-verification of any plan on a fine sampling of every wall;
- :mod:`planner.plan.outcome`: a plan with its coverage, network check and figures' inputs, from a run or a file.
"""

from planner.coverage.visibility import sight_limits
from planner.plan.closed_form import closed_form_limits
from planner.plan.methods import METHODS
from planner.plan.options import PlanOptions, plan_limits
from planner.plan.registration import placed_stations, registration_check
from planner.plan.result import Plan
from planner.plan.run import build_problem, coverage_problem, plan_site, site_candidates, unseen_error

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
