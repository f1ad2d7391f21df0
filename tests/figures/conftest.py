"""Outcomes the figure tests draw: bundled sites planned by the greedy method (the quickest), made once."""

from __future__ import annotations

import pytest

import planner
from planner.plan.outcome import Outcome
from tests.conftest import INSTANCES


def greedy_outcome(name: str, network: bool) -> Outcome:
    """``instances/NAME.json`` planned greedily, with its network checked when ``network``."""
    site = planner.load_site(INSTANCES / f"{name}.json")
    plan = planner.plan_site(site, planner.PlanOptions(method="greedy"))
    report = planner.run_network(site, list(plan.stations)) if network else None
    return planner.outcome_from_plan(plan, report)


@pytest.fixture(scope="session")
def house_network() -> Outcome:
    """house_doors (4 rooms, 4 openings, 7 stations) with its network: proposed control points and ties."""
    return greedy_outcome("house_doors", network=True)


@pytest.fixture(scope="session")
def house_plain() -> Outcome:
    """house_doors without a network: the site figure computes the registration links itself."""
    return greedy_outcome("house_doors", network=False)


@pytest.fixture(scope="session")
def polygon_b() -> Outcome:
    """Polygon B (one zone, both sides, its own frame) without a network."""
    return greedy_outcome("polygon_b", network=False)
