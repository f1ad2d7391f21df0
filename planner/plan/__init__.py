"""From a site to a verified plan (the pipeline's driver): options, the methods, the run, re-verification and outcomes.

- :mod:`planner.plan.options`: :class:`PlanOptions` and the sight limits they give;
- :mod:`planner.plan.methods`: the planning methods by name (closed form, greedy, MILP), one registry;
- :mod:`planner.plan.strategy`: one model or tiles, and why (:class:`StrategyOptions`, :class:`Strategy`);
- :mod:`planner.plan.problem`: :func:`resolve` -> :class:`Problem`, the run resolved once;
- :mod:`planner.plan.run`: :func:`plan_single` (candidates -> coverage -> method -> registration check ->
  verification, as one model);
- :mod:`planner.plan.result`: :class:`Plan`, a verified plan and its summary;
- :mod:`planner.plan.tripod`: where the stations stand, their tripod discs;
- :mod:`planner.plan.verify`: re-verification of any plan on a fine sampling of every wall;
- :mod:`planner.plan.outcome`: a plan with its coverage, network check and figures' inputs, from a run or a file.
"""

from planner.plan.methods import METHODS, closed_form_limits
from planner.plan.options import PlanOptions, plan_limits
from planner.plan.problem import Problem, resolve
from planner.plan.result import Plan
from planner.plan.run import build_problem, coverage_problem, plan_single, site_candidates, unseen_error
from planner.plan.strategy import Strategy, StrategyOptions
from planner.plan.tripod import placed_stations

__all__ = [
    "METHODS",
    "Plan",
    "PlanOptions",
    "Problem",
    "Strategy",
    "StrategyOptions",
    "build_problem",
    "closed_form_limits",
    "coverage_problem",
    "placed_stations",
    "plan_limits",
    "plan_single",
    "resolve",
    "site_candidates",
    "unseen_error",
]
