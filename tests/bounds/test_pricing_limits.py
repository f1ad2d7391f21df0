"""Pricing stops on counted work (rounds, (point, region) pairs weighed) by default; a wall-clock cap only where the
user sets one, and a cap that cuts it is said."""

from __future__ import annotations

import pytest

from planner import load_site
from planner.bounds.plane import PRICING_WORK, price_plane
from planner.plan import PlanOptions, coverage_problem, resolve
from planner.solve.milp import MilpOptions
from tests.conftest import INSTANCES

OPTIONS = PlanOptions(method="milp", milp=MilpOptions(overlap=None))


@pytest.fixture(scope="module")
def polygon_b() -> tuple:
    """Polygon B and its coverage problem, built once for the module: each test prices it under other limits."""
    site = load_site(INSTANCES / "polygon_b.json")
    return site, coverage_problem(resolve(site, OPTIONS))[0]


def _priced(polygon_b, **limits):  # type: ignore[no-untyped-def]
    site, problem = polygon_b
    return price_plane(site, problem, problem.limits, **limits)[1]


def test_the_default_pricing_counts_its_work_and_converges_within_it(polygon_b: tuple) -> None:
    assert PlanOptions().pricing_time_limit_s is None
    report = _priced(polygon_b)
    assert report.converged and not report.wall_cap_hit
    assert 0 < report.work < PRICING_WORK
    assert report.to_dict()["work"] == report.work


def test_the_work_limit_stops_pricing_after_the_round_that_reached_it(polygon_b: tuple) -> None:
    report = _priced(polygon_b, max_work=1)
    assert (report.rounds, report.converged, report.wall_cap_hit) == (1, False, False)
    assert "work limit of 1 weighed pairs" in report.note


def test_a_wall_clock_cap_that_cuts_pricing_is_said(polygon_b: tuple) -> None:
    report = _priced(polygon_b, time_limit_s=0.0)
    assert report.wall_cap_hit and report.rounds == 0
    assert "wall-clock cap of 0 s; may depend on the load" in report.note
