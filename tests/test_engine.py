"""The engine: ``planner.plan_site`` gives what ``planner plan`` gives, from one resolved problem.

- the command's options with no flags are the library's defaults (so the two cannot drift apart);
- the plan of a path through the library and the plan.json of the command name the same stations, bound and
  bound scope (slow: three full planning runs each way);
- the strategy of the 16-ha plant is tiles when resolved by the library, as the command chooses;
- a plan records its pool's fingerprint, and the best plan known is compared (a gap) only on the same problem and
  pool (issue 44).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import planner
import planner.plan.best_known as best_known_module
from planner.cli.commands import plan_options
from planner.cli.main import build_parser, main
from planner.cli.profile import apply_config
from planner.core.errors import UsageError
from planner.coverage.overlap import SiteShare
from planner.engine import with_strategy
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


def test_the_library_s_defaults_are_the_settings() -> None:
    # one home: planner/core/settings/table.py (import-light, so that --help imports no solver)
    from planner.core.settings import DEFAULTS
    from planner.plan import strategy

    assert (strategy.BUDGET_S, strategy.WORKER_MEMORY) == (DEFAULTS["strategy.budget_s"], 3 * 2**29)
    assert strategy.MOVES_PER_PIECE == DEFAULTS["tiling.moves_per_piece"]


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
@pytest.mark.parametrize("name", ["polygon_b", "building27", pytest.param("baalbek_site", marks=pytest.mark.heavy)])
def test_library_and_command_give_the_same_plan(name: str, tmp_path: Path) -> None:
    path = INSTANCES / f"{name}.json"
    assert main(["plan", str(path), "--out", str(tmp_path), "--quiet"]) == 0
    command = json.loads((tmp_path / "plan.json").read_text())
    library = plan_to_dict(planner.plan_site(str(path)))
    for key in ("stations", "bound", "bound_scope", "status", "objective", "pool"):
        assert library[key] == command[key], key
    assert library["solver"]["strategy"] == command["solver"]["strategy"]
    assert library["resolved"] == command["resolved"]  # the same limits, rule, scope and strategy, written out
    assert library["verification"]["percent"] == command["verification"]["percent"] == 100.0


def _small_plan(**options) -> planner.Plan:
    # polygon_b (one zone, both sides, registration by zone) with coarse pieces and grid, greedy: a third of a
    # second (polygon_a took a second for the same plumbing)
    pool = planner.PoolOptions(grid_spacing_m=20.0)
    o = planner.PlanOptions(method="greedy", target_spacing_m=5.0, pool=pool, **options)
    return planner.plan_site(INSTANCES / "polygon_b.json", o)


def _best_known(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, *rows: dict) -> None:
    path = tmp_path / "best_known.json"
    path.write_text(json.dumps({"plans": list(rows)}))
    monkeypatch.setattr(best_known_module, "BEST_KNOWN", path)


def _entry(problem: str, fingerprint: str | None, stations: int, **more) -> dict:
    pool = None if fingerprint is None else {"fingerprint": fingerprint, "candidates": 1, "targets": 1, "pairs": 1}
    return {"instance": "polygon_b", "problem": problem, "stations": stations, "pool": pool, "command": "c", **more}


def test_a_plan_records_its_pool_and_the_gap_only_on_the_same_pool(tmp_path, monkeypatch) -> None:
    plan = _small_plan()
    data = plan_to_dict(plan)
    assert plan.pool is not None and data["pool"] == plan.pool.to_dict()
    assert data["pool"]["candidates"] == data["problem"]["candidates"] and data["pool"]["pairs"] > 0
    assert "best_known" not in data["solver"]  # the real file lists no entry for polygon_b
    n, fp, rule = len(plan.stations), plan.pool.fingerprint, plan.problem.rule
    assert rule is not None and plan.problem.registration.mode == "zone"
    row = {"registration": "zone", "overlap": rule.overlap}
    _best_known(tmp_path, monkeypatch, _entry("connected", fp, n - 1, **row))
    same = with_strategy(plan)
    assert f"this plan {n}, gap to it {100 / n:.1f} %" in same.log[-1]
    assert same.result.info["best_known"]["same_pool"] is True
    _best_known(tmp_path, monkeypatch, _entry("connected", "0123456789ab", n - 1, **row))
    other = with_strategy(plan)
    assert "on another pool (fingerprint 0123456789ab" in other.log[-1] and "gap to it" not in other.log[-1]
    known = plan_to_dict(other)["solver"]["best_known"]
    assert known["same_pool"] is False and known["gap"] is None and known["pool"]["fingerprint"] == "0123456789ab"
    _best_known(tmp_path, monkeypatch, _entry("plain cover", fp, n - 1, registration=None, overlap=0.0))
    assert "best_known" not in with_strategy(plan).result.info  # a connected plan is not compared with a plain one


def test_a_run_with_no_rule_is_compared_with_the_plain_cover(tmp_path, monkeypatch) -> None:
    plan = _small_plan(milp=planner.MilpOptions(overlap=None))  # --no-overlap
    assert plan.problem.rule is None and plan.pool is not None
    n, fp = len(plan.stations), plan.pool.fingerprint
    connected = _entry("connected", fp, n - 2, registration="zone", overlap=0.3)
    _best_known(tmp_path, monkeypatch, connected, _entry("plain cover", fp, n, registration=None, overlap=0.0))
    out = with_strategy(plan)
    known = out.result.info["best_known"]
    assert known["problem"] == "plain cover" and known["same_pool"] and known["gap"] == 0.0
    assert "(plain cover, registration none, overlap 0" in out.log[-1] and "gap to it 0.0 %" in out.log[-1]
