"""The engine: ``planner.plan_site`` gives what ``planner plan`` gives, from one resolved problem.

- the command's options with no flags are the library's defaults (so the two cannot drift apart);
- the plan of a path through the library and the plan.json of the command name the same stations, bound and
  bound scope (slow: three full planning runs each way);
- the strategy of the 16-ha plant is tiles when resolved by the library, as the command chooses.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import planner
from planner.cli.commands import plan_options
from planner.cli.main import build_parser, main
from planner.cli.profile import apply_config
from planner.core.errors import UsageError
from planner.coverage.overlap import SiteShare
from planner.plan.plan_dict import plan_to_dict

INSTANCES = Path(__file__).resolve().parents[1] / "instances"


def _args(argv: list[str]):
    parser = build_parser()
    apply_config(parser, argv)
    return parser.parse_args(argv)


def test_the_command_without_flags_plans_with_the_library_defaults() -> None:
    # every PlanOptions field (and the MILP's, the pool's, the strategy's) the plain command sets equals the
    # default a design script gets from planner.PlanOptions()
    assert plan_options(_args(["plan", str(INSTANCES / "polygon_b.json")])) == planner.PlanOptions()


def test_the_defaults_are_the_command_s_method() -> None:
    o = planner.PlanOptions()
    assert o.method == "milp" and o.tripod is True  # the MILP places tripod discs
    assert planner.PlanOptions(method="greedy").tripod is False
    assert isinstance(o.milp.overlap, SiteShare)  # the site's share, resolved with the site


def test_resolve_names_tiles_for_the_16_ha_plant_and_one_model_for_a_building() -> None:
    plant = planner.resolve(planner.load_site(INSTANCES / "plant_16ha.json"))
    assert plant.strategy.tiles and "tiles" in plant.strategy.line()
    b = planner.resolve(planner.load_site(INSTANCES / "polygon_b.json"))
    assert not b.strategy.tiles and "fewer than" in b.strategy.reason


def test_the_resolved_rule_is_the_one_place_that_says_off() -> None:
    site = planner.load_site(INSTANCES / "polygon_b.json")
    on = planner.resolve(site)
    assert on.rule is not None and on.rule.overlap == site.parameters.overlap
    assert on.options.milp.overlap == on.rule  # the stages read the resolved rule
    off = planner.resolve(site.with_parameters(overlap=0.0))
    assert off.rule is None and off.checked_rule.overlap == 0.0  # share 0: no registration asked for
    plain = planner.resolve(site, planner.PlanOptions(milp=planner.MilpOptions(overlap=None)))
    assert plain.rule is None and plain.checked_rule.overlap == site.parameters.overlap


def test_a_problem_carries_its_options() -> None:
    problem = planner.resolve(planner.load_site(INSTANCES / "polygon_b.json"))
    with pytest.raises(UsageError, match="carries its options"):
        planner.plan_site(problem, planner.PlanOptions())


def test_workers_for_one_model_are_refused() -> None:
    site = planner.load_site(INSTANCES / "polygon_b.json")
    options = planner.PlanOptions(strategy=planner.StrategyOptions(workers=4))
    with pytest.raises(UsageError, match="one model") as err:
        planner.resolve(site, options)
    assert err.value.field == "workers"


@pytest.mark.slow
@pytest.mark.parametrize("name", ["polygon_b", "building27", "baalbek_site"])
def test_library_and_command_give_the_same_plan(name: str, tmp_path: Path) -> None:
    path = INSTANCES / f"{name}.json"
    assert main(["plan", str(path), "--out", str(tmp_path), "--quiet"]) == 0
    command = json.loads((tmp_path / "plan.json").read_text())
    library = plan_to_dict(planner.plan_site(str(path)))
    for key in ("stations", "bound", "bound_scope", "status", "objective"):
        assert library[key] == command[key], key
    assert library["solver"]["strategy"] == command["solver"]["strategy"]
    assert library["resolved"] == command["resolved"]  # the same limits, rule, scope and strategy, written out
    assert library["verification"]["percent"] == command["verification"]["percent"] == 100.0
