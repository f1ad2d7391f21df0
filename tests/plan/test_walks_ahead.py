"""The connected plane bound's walks done ahead on a second core (:mod:`planner.bounds.ring_ahead`) change nothing in
the plan: polygon B planned with the walks forked ahead and with one core only gives the same plan.json apart from its
times (compared as ``scripts/check_determinism.py`` compares it), and the forked walks answered."""

from __future__ import annotations

import importlib.util

import pytest

import planner
import planner.bounds.ring_ahead as ahead_mod
from planner.plan.plan_dict import plan_to_dict
from tests.conftest import INSTANCES, ROOT

_spec = importlib.util.spec_from_file_location("check_determinism", ROOT / "scripts" / "check_determinism.py")
check = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(check)  # type: ignore[union-attr]


@pytest.mark.slow
def test_polygon_b_plans_the_same_with_walks_ahead(monkeypatch: pytest.MonkeyPatch) -> None:
    site = INSTANCES / "polygon_b.json"
    monkeypatch.setattr(ahead_mod, "thread_count", lambda: 1)
    alone = plan_to_dict(planner.plan_site(site))
    answers: list[object] = []
    walked = ahead_mod.WalksAhead.walked

    def recorded(self, *args):  # type: ignore[no-untyped-def]
        got = walked(self, *args)
        answers.append(got)
        return got

    monkeypatch.setattr(ahead_mod, "thread_count", lambda: 2)
    monkeypatch.setattr(ahead_mod.WalksAhead, "walked", recorded)
    ahead = plan_to_dict(planner.plan_site(site))
    assert len(answers) == 1 and answers[0] is not None  # the bound took the forked walks' answer
    assert alone["connected_plane_bound"] == 6
    assert check.plan_differences(alone, ahead) == []


@pytest.mark.parametrize(
    ("name", "zone_sides"),
    [("baalbek_site", True), ("building27", True), ("baalbek_site_doors", False), ("house_doors", False)],
)
def test_site_areas_guessed_as_zone_sides_before_the_pool(name: str, zone_sides: bool) -> None:
    # site registration: rooms without doors and one outside zone bundle by zone-side (the walks start early); doors
    # join rooms to the outside (not)
    from planner.engine import problem_of
    from planner.plan.methods import areas_are_zone_sides

    problem = problem_of(INSTANCES / f"{name}.json")
    assert problem.registration.mode == "site"
    assert areas_are_zone_sides(problem.site) is zone_sides
