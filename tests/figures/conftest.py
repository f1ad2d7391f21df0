"""Outcomes the figure tests draw: bundled sites planned by the greedy method (the quickest), made once per session
(tests/conftest.py)."""

from __future__ import annotations

import pytest

import planner
from planner.plan.outcome import Outcome


def greedy_outcome(site: planner.Site, plan: planner.Plan, network: bool) -> Outcome:
    """The outcome of a greedy ``plan`` of ``site``, with its network checked when ``network``."""
    report = planner.run_network(site, list(plan.stations)) if network else None
    return planner.outcome_from_plan(plan, report)


@pytest.fixture(scope="session")
def house_network(house_doors_greedy) -> Outcome:
    """house_doors (4 rooms, 4 openings, 7 stations) with its network: proposed control points and ties."""
    return greedy_outcome(*house_doors_greedy, network=True)


@pytest.fixture(scope="session")
def house_plain(house_doors_greedy) -> Outcome:
    """house_doors without a network: the site figure computes the registration links itself."""
    return greedy_outcome(*house_doors_greedy, network=False)


@pytest.fixture(scope="session")
def polygon_b(polygon_b_greedy) -> Outcome:
    """Polygon B (one zone, both sides, its own frame) without a network."""
    return greedy_outcome(*polygon_b_greedy, network=False)
