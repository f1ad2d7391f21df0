"""The planning methods' registry (issue 33: one registry instead of an if/elif in plan_site)."""

from __future__ import annotations

import ast
from pathlib import Path

from planner.core import settings as choices
from planner.engine import plan_site
from planner.plan import METHODS, PlanOptions, build_problem
from planner.plan.methods import REGISTRY, MethodOutput
from planner.site import ScanSide, Site, Zone
from planner.site.candidate import CandidateKind

ROOT = Path(__file__).resolve().parents[2]


def test_the_registry_is_the_list_of_methods():
    # --method's choices (kept apart for a fast start) are the registry's keys, in order
    assert METHODS == tuple(REGISTRY) == choices.METHODS
    assert all(callable(f) for f in REGISTRY.values())


def test_plan_site_branches_on_no_method_name():
    # plan_site looks the method up; no `if options.method == ...` statement picks one
    tree = ast.parse((ROOT / "planner/plan/run.py").read_text())
    branches = [
        ast.unparse(node.test)
        for node in ast.walk(tree)
        if isinstance(node, ast.If) and "method" in ast.unparse(node.test)
    ]
    assert branches == []


def test_every_method_plans_a_square_room():
    # a 6 x 6 m room, walls 3 m: every method gives a plan whose stations verify at 100 %
    room = Zone("room", ScanSide.INSIDE, ((0, 0), (6, 0), (6, 6), (0, 6)), (3.0,) * 4)
    site = Site("square", (room,), instrument="dissertation-tables")
    for name in REGISTRY:
        plan = plan_site(site, PlanOptions(method=name))
        assert plan.result.method == name, name
        assert plan.verification.percent == 100.0, name
        assert plan.result.selected, name


def test_a_method_returns_what_its_indices_refer_to():
    # the closed form solves over its own stations: its result indexes its own problem, and the plan's size
    # counts the pool (MethodOutput.pool), which is not that problem
    room = Zone("room", ScanSide.INSIDE, ((0, 0), (6, 0), (6, 6), (0, 6)), (3.0,) * 4)
    site = Site("square", (room,), instrument="dissertation-tables")
    plan = plan_site(site, PlanOptions(method="closed-form"))
    closed_form_kinds = {CandidateKind.VERTEX, CandidateKind.WALL, CandidateKind.CIRCLE}
    assert {s.kind for s in plan.stations} <= closed_form_kinds
    pool = build_problem(site, PlanOptions(method="closed-form"))
    assert plan.problem_size == {
        "candidates": len(pool.candidates),
        "targets": len(pool.targets),
        "pairs": int(pool.by_candidate.nnz),
    }
    assert MethodOutput.__dataclass_params__.frozen  # type: ignore[attr-defined]
