"""The comparison of methods shown in a report: the closed form, the greedy and the plan's own method."""

from __future__ import annotations

import logging
from dataclasses import replace
from typing import Any

from planner.core.checks import argument
from planner.core.errors import PlannerError
from planner.plan import Plan, Problem, StrategyOptions, plan_single, resolve
from planner.plan.plan_dict import plan_to_dict

log = logging.getLogger(__name__)


def meta_row(meta: dict[str, Any], verified_percent: float) -> dict[str, Any]:
    """A comparison row from a plan.json dictionary (:func:`planner.io.plan_json.plan_to_dict`)."""
    counts = meta.get("counts") or {}
    return {
        "method": meta.get("method", "?"),
        "backend": meta.get("backend") or "",
        "stations": counts.get("total"),
        "inside": counts.get("inside"),
        "outside": counts.get("outside"),
        "bound": meta.get("bound"),
        "gap": meta.get("gap"),
        "status": meta.get("status", ""),
        "time_s": meta.get("time_s"),
        "bound_scope": meta.get("bound_scope"),
        "plane_bound": meta.get("plane_bound"),
        "verified_percent": verified_percent,
        "connected": (meta.get("registration") or {}).get("connected"),
    }


def method_row(plan: Plan) -> dict[str, Any]:
    return meta_row(plan_to_dict(plan), plan.verification.percent)


def compare_methods(done: Plan | Problem) -> list[dict[str, Any]]:
    """Closed form and greedy (cheap: one coverage build each) beside ``done``, the plan already made (or, given a
    resolved problem alone, beside nothing), each on the same site, validation and limits."""
    argument(done, (Plan, Problem), "done")
    problem = done.problem if isinstance(done, Plan) else done
    plain = StrategyOptions(single=True)  # the greedy and the closed form run as one model
    rows = []
    for method in ("closed-form", "greedy"):
        if isinstance(done, Plan) and done.result.method == method:
            continue
        # they plan stations alone: no point spacing, no field time (the MILP's; its trade-off table has them)
        options = replace(
            problem.options,
            method=method,
            tripod=False,
            recentre=False,
            strategy=plain,
            max_point_spacing_m=None,
            objective="stations",
        )
        try:
            rows.append(method_row(plan_single(resolve(problem.site, options, validation=problem.validation))))
        except PlannerError as exc:  # e.g. a piece the closed form cannot see: shown, not fatal
            log.info("method %s failed: %s", method, exc)
            rows.append({"method": method, "status": f"failed: {exc.one_line()}"})
    if isinstance(done, Plan):
        rows.append(method_row(done))
    return rows
