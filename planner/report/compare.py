"""The comparison of methods shown in a report: the closed form, the greedy and the plan's own method."""

from __future__ import annotations

import logging
from dataclasses import replace
from typing import Any

from planner.errors import PlannerError
from planner.plan import Plan, PlanOptions, plan_site
from planner.site.model import Site

log = logging.getLogger(__name__)


def method_row(plan: Plan) -> dict[str, Any]:
    r = plan.result
    sides = plan.count_by_side()
    return {"method": r.method, "backend": r.backend or "", "stations": len(plan.stations),
            "inside": sides.get("inside", 0), "outside": sides.get("outside", 0), "bound": r.bound, "gap": r.gap,
            "status": r.status.value, "time_s": r.time_s, "verified_percent": plan.verification.percent,
            "connected": plan.connected}


def compare_methods(site: Site, options: PlanOptions, done: Plan | None = None) -> list[dict[str, Any]]:
    """Closed form and greedy (cheap: one coverage build each) beside ``done``, the plan already made."""
    rows = []
    for method in ("closed-form", "greedy"):
        if done is not None and done.result.method == method:
            continue
        try:
            rows.append(method_row(plan_site(site, replace(options, method=method, tripod=False, recentre=False))))
        except PlannerError as exc:  # e.g. a piece the closed form cannot see: shown, not fatal
            log.info("method %s failed: %s", method, exc)
            rows.append({"method": method, "status": f"failed: {exc.one_line()}"})
    if done is not None:
        rows.append(method_row(done))
    return rows
