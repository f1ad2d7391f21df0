"""The comparison of methods shown in a report: the closed form, the greedy and the plan's own method.

Beside a plan made in this process, the greedy and the closed form plan on the candidate pool's coverage the plan
was chosen from (:attr:`planner.plan.Plan.coverage`, with its floor and ceiling columns): the pool is not built
again, and the greedy's count is over the very pool the plan's is (before pricing, which adds positions to the
MILP's). The closed form needs no pool (its stations are the dissertation's construction per zone; only their own
coverage is computed). Each row says in ``over`` what its count is over, and the greedy's whether it is the
connected greedy or the plain one.
"""

from __future__ import annotations

import logging
from dataclasses import replace
from typing import Any

from planner.core.checks import argument
from planner.core.errors import PlannerError
from planner.plan import Plan, Problem, StrategyOptions, build_problem, plan_single, resolve
from planner.plan.plan_dict import plan_to_dict

log = logging.getLogger(__name__)

#: the greedy's log line where no connected cover was found (:func:`planner.plan.methods.greedy_method`)
PLAIN_INSTEAD = "plain greedy plan instead"


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
    """The comparison row of ``plan``, with what its count is over (``over``)."""
    return {**meta_row(plan_to_dict(plan), plan.verification.percent), "over": over_words(plan)}


def over_words(plan: Plan) -> str:
    """What ``plan``'s station count is over, in words: the closed form's own stations, the greedy (connected or
    plain) over the pool, or the pool the plan's method chose from (its size)."""
    size = plan.problem_size
    pool = f"{size.get('candidates', 0):,} candidates"
    method = plan.result.method
    if method == "closed-form":
        generated = plan.result.info.get("generated")
        made = f"{generated} generated" if generated is not None else "its own"
        return f"closed-form stations per zone ({made}, redundant ones dropped); no candidate pool"
    if method == "greedy":
        rule = plan.problem.rule
        if plan.options.combined and plan.problem.limits.precision is not None:
            kind = "greedy adding views' information (combined precision)"
        elif rule is None or rule.overlap <= 0:
            kind = "plain greedy (no overlap rule)"
        elif any(PLAIN_INSTEAD in line for line in plan.log):
            kind = "plain greedy (no cover connected under the overlap rule found)"
        else:
            kind = "connected greedy (under the overlap rule)"
        return f"{kind} over the candidate pool ({pool})"
    built = len(plan.coverage.candidates) if plan.coverage is not None else size.get("candidates", 0)
    added = size.get("candidates", 0) - built
    if added > 0:  # pricing adds positions of the plane to the pool the plan chose from
        return f"{method} over the candidate pool ({built:,} candidates, {added:,} more added by pricing)"
    return f"{method} over the candidate pool ({pool})"


def compare_methods(done: Plan | Problem) -> list[dict[str, Any]]:
    """Closed form and greedy beside ``done``, the plan already made (or, given a resolved problem alone, beside
    nothing), each on the same site, validation and limits. Beside a plan that keeps its pool's coverage
    (:attr:`Plan.coverage`), both plan on it (module docstring); else, or given a problem, the pool is built once
    and both plan on it."""
    argument(done, (Plan, Problem), "done")
    problem = done.problem if isinstance(done, Plan) else done
    coverage = done.coverage if isinstance(done, Plan) else None
    columns = done.surface_cover if isinstance(done, Plan) else None
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
            resolved = resolve(problem.site, options, validation=problem.validation)
            if columns is not None and resolved.surfaces is not None:  # the patches the plan's columns are over
                resolved = replace(resolved, surfaces=problem.surfaces)
            if coverage is None:  # no plan's pool: built once, for both methods (the same options but the method)
                coverage = build_problem(resolved)
            rows.append(method_row(plan_single(resolved, coverage=coverage, surface_cover=columns)))
        except PlannerError as exc:  # e.g. a piece the closed form cannot see: shown, not fatal
            log.info("method %s failed: %s", method, exc)
            rows.append({"method": method, "status": f"failed: {exc.one_line()}"})
    if isinstance(done, Plan):
        rows.append(method_row(done))
    return rows
