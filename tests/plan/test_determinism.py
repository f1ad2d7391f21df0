"""The same plan under load: polygon A planned twice through the library, the second time beside one busy process
per core; plan.json compared apart from its times as ``scripts/check_determinism.py`` compares it."""

from __future__ import annotations

import importlib.util
import os

import pytest

import planner
from planner.plan.plan_dict import plan_to_dict
from tests.conftest import INSTANCES, ROOT

_spec = importlib.util.spec_from_file_location("check_determinism", ROOT / "scripts" / "check_determinism.py")
check = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(check)  # type: ignore[union-attr]


@pytest.mark.slow
@pytest.mark.heavy
def test_polygon_a_plans_the_same_with_every_core_busy() -> None:
    site = INSTANCES / "polygon_a.json"
    first = plan_to_dict(planner.plan_site(site))
    with check.busy(os.cpu_count() or 2):
        second = plan_to_dict(planner.plan_site(site))
    assert first["wall_cap_hit"] == second["wall_cap_hit"] == []  # only counted work stopped either run
    assert first["parameters"]["milp"]["time_limit_s"] is None
    assert check.plan_differences(first, second) == []


def test_times_are_left_out_of_the_comparison() -> None:
    a = {"time_s": 1.0, "log": ["coverage built in 13.60 s (2 candidates)"], "solver": {"presolve": {"time_s": 2}}}
    b = {"time_s": 9.0, "log": ["coverage built in 1.2 s (2 candidates)"], "solver": {"presolve": {"time_s": 3}}}
    assert check.plan_differences(a, b) == []
    assert check.plan_differences({**a, "stations": [1]}, {**b, "stations": [2]}) == ["/stations[0]: 1, then 2"]
    assert check.field_differences({"order": [1, 2], "solve_s": 1}, {"order": [2, 1], "solve_s": 1}) != []
