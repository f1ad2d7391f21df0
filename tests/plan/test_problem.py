"""The resolved problem's registration scope and its reason, as the summary's registration line prints them
(issue 44: site-wide by default wherever the zones share one frame; ``--registration`` still wins)."""

from __future__ import annotations

import pytest

from planner.io.load import load_site
from planner.plan import PlanOptions
from planner.plan.problem import resolve
from tests.conftest import INSTANCES


@pytest.mark.parametrize(
    ("name", "scope", "reason"),
    [
        ("plant_1ha.json", "site", "the 9 zones share one frame (site coordinates): one bundle per accessible area"),
        (
            "baalbek.json",
            "zone",
            "each of the 12 zones in its own frame: one bundle per zone-side, as the dissertation",
        ),
        ("polygon_b.json", "zone", "one zone"),
    ],
)
def test_registration_line_says_the_scope_and_why(name, scope, reason):
    problem = resolve(load_site(INSTANCES / name))
    assert problem.registration.mode == scope and problem.options.registration == scope
    assert reason in problem.registration_reason
    assert f"; scope {scope} ({reason}" in problem.registration_line()
    assert problem.to_dict()["registration"] == scope


@pytest.mark.parametrize(("name", "asked"), [("plant_1ha.json", "zone"), ("baalbek.json", "site")])
def test_registration_asked_for_wins_over_the_default(name, asked):
    problem = resolve(load_site(INSTANCES / name), PlanOptions(registration=asked))
    assert problem.registration.mode == asked and problem.registration_reason == "asked for"


def test_resolve_lists_what_it_adjusts():
    site = load_site(INSTANCES / "polygon_b.json")
    assert resolve(site).adjustments == ()
    hours = resolve(site, PlanOptions(objective="field-time"))
    assert {"pricing off: scan settings per station", "tripod off: scan settings per station"} <= set(hours.adjustments)
    assert not hours.options.pricing and not hours.options.tripod
    assert all(f"adjusted: {a}" in hours.summary() for a in hours.adjustments)
    assert hours.to_dict()["adjustments"] == list(hours.adjustments)
