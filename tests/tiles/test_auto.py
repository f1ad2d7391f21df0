"""The plain command's strategy: one model or tiles, the tile size and the time split (planner.plan.strategy)."""

from __future__ import annotations

import json

import pytest

from planner.cli import main
from planner.io.load import load_site
from planner.plan import PlanOptions, closed_form_limits
from planner.plan.memory_guard import estimate_work
from planner.plan.strategy import MIN_PIECES, choose, strategy_for, tile_count
from planner.site.validate import validate_site
from planner.solve.cft import HEUR_ITERS
from planner.solve.milp import MilpOptions
from tests.conftest import INSTANCES


def _strategy(name: str, cores: int = 2, budget_s: float = 420.0, method: str = "milp"):
    site = load_site(INSTANCES / f"{name}.json")
    s_max = closed_form_limits(validate_site(site)).max_slant_range_m
    pieces = estimate_work(site, 1.0, 10.0, s_max).targets
    return choose(site, PlanOptions(method=method), s_max, pieces, budget_s, cores=cores)


@pytest.mark.parametrize("name", ["polygon_a", "polygon_c", "baalbek_site", "building27", "plant_1ha", "plant_4ha"])
def test_buildings_monuments_and_small_plants_stay_one_model(name):
    # at most 3,082 wall pieces (polygon C: 1,541 m of wall, both sides, 1-m pieces) < 5,000
    assert _strategy(name).tiling is None


def test_16ha_plant_goes_to_tiles_split_by_the_budget():
    # 7,688 pieces >= 5,000; S_max 60 m -> tile side max(100, 1.5 x 60 = 90) = 100 m; the zones span
    # 386.4 x 390.0 m -> 4 x 4 = 16 tiles
    st = _strategy("plant_16ha", cores=2)
    assert st.tiling is not None and st.tiling.tile_m == 100.0 and st.workers == 0
    site = load_site(INSTANCES / "plant_16ha.json")
    assert tile_count(site, 100.0) == 16
    # 2 cores: no worker (in this process); each tile 0.30 x 420 / 16 = 7.875 s of work, no bound MILP, the
    # Lagrangian 0.15 x 420 / 16 = 3.9375 s per part; a connected plan (the site's registration rule): no CFT
    # cover, the local search 15 moves per piece, 15 x 7,688 = 115,320
    assert st.tiling.tile_time_limit_s == pytest.approx(7.875)
    assert st.tiling.bound_time_limit_s == 0.0 and not st.tiling.cft
    assert st.tiling.moves_for(7_688) == 115_320
    assert st.to_dict()["cover"] is None and st.to_dict()["search_moves"] == "15 per piece"
    assert st.tiling.lagrange_work_s == pytest.approx(3.9375)
    assert "tiles of 100 m in this process (no Dask worker)" in st.line()  # not 'on no worker(s)'
    # windows: 0.30 x 420 s over 6 stations per tile x 16 tiles = 96 windows -> 1.3125 s each, but no pass by
    # default (WINDOW_PASSES)
    assert st.tiling.windows.work_s == pytest.approx(1.3125) and st.tiling.windows.passes == 0
    # 16 cores: half, 8 workers (docs/studies/workers.md: 8 beat 16), 8 tiles side by side:
    # 0.30 x 420 x 8 / 16 = 63 s, capped at 30 s per tile; Lagrangian 0.15 x 420 x 8 / 16 = 31.5, capped at 10
    big = _strategy("plant_16ha", cores=16)
    assert big.workers == 8 and big.tiling.tile_time_limit_s == 30.0 and big.tiling.lagrange_work_s == 10.0
    assert "16 tiles of 100 m" in big.line() and big.to_dict()["kind"] == "tiles"
    # 4 cores: 2 workers; 3 cores: 1 (a worker process, the client waiting); 2 cores: none
    assert [_strategy("plant_16ha", cores=c).workers for c in (4, 3, 2)] == [2, 1, 0]


def test_a_plain_cover_keeps_cft_and_ten_moves_per_piece():
    # --no-overlap (no registration rule): CFT's cover is the plan's start, 10 moves per piece, 76,880 on 16 ha
    site = load_site(INSTANCES / "plant_16ha.json")
    s_max = closed_form_limits(validate_site(site)).max_slant_range_m
    plain = PlanOptions(method="milp", milp=MilpOptions(overlap=None))
    st = choose(site, plain, s_max, estimate_work(site, 1.0, 10.0, s_max).targets, 420.0, cores=2)
    assert st.tiling is not None and st.tiling.cft and st.tiling.moves_for(7_688) == 76_880
    assert st.to_dict()["cover"] == f"CFT, {HEUR_ITERS} iterations"


def test_workers_asked_for_are_the_strategys_and_set_its_split():
    # `--workers N` (strategy_for(..., workers=N)): the strategy runs on N workers whatever the cores, says so in
    # its line (stop 39's 64-ha run printed "on no worker(s)" under --workers 1), and counts N side by side
    site = load_site(INSTANCES / "plant_16ha.json")
    options = PlanOptions(method="milp")
    one = strategy_for(site, options, validate_site(site), budget_s=420.0, workers=1)
    # 1 side by side, as with none: 0.30 x 420 / 16 = 7.875 s per tile
    assert one.workers == 1 and "on 1 worker(s)" in one.line()
    assert one.tiling is not None and one.tiling.tile_time_limit_s == pytest.approx(7.875)
    # 2 workers: 0.30 x 420 x 2 / 16 = 15.75 s per tile; Lagrangian 0.15 x 420 x 2 / 16 = 7.875 s per part
    two = strategy_for(site, options, validate_site(site), budget_s=420.0, workers=2)
    assert two.workers == 2 and two.tiling is not None
    assert two.tiling.tile_time_limit_s == pytest.approx(15.75) and two.tiling.lagrange_work_s == pytest.approx(7.875)
    # none asked for: the machine's choice, as choose() makes it (the same pieces estimate: 1-m pieces, 10-m grid)
    assert strategy_for(site, options, validate_site(site), budget_s=420.0) == choose(
        site, options, validate_site(site).range_limit.max_slant_range_m, _pieces(site), 420.0
    )


def _pieces(site) -> int:
    return estimate_work(site, 1.0, 10.0, closed_form_limits(validate_site(site)).max_slant_range_m).targets


def test_greedy_is_never_tiled():
    assert _strategy("plant_16ha", method="greedy").reason == "method greedy"
    assert MIN_PIECES == 5_000


@pytest.mark.slow
def test_plain_command_records_its_strategy(tmp_path, capsys):
    out = tmp_path / "p"
    assert main(["plan", str(INSTANCES / "house_doors.json"), "--out", str(out), "--quiet"]) == 0
    text = capsys.readouterr().out
    assert "strategy: single model (about 184 wall pieces, fewer than 5,000)" in text
    plan = json.loads((out / "plan.json").read_text())
    assert plan["solver"]["strategy"]["kind"] == "single model"
    assert main(["plan", str(INSTANCES / "house_doors.json"), "--tiles", "off", "--quiet"]) == 0
    assert "strategy: single model (one model asked for)" in capsys.readouterr().out


def test_a_tiled_site_of_few_pieces_gets_the_fine_grid_where_none_is_given():
    # 16 ha: 7,688 pieces <= 10,000 -> the strategy's grid 4 m, and resolve builds the pool with it; a grid given is
    # kept; one model keeps the 10-m default (polygon A); 64 ha: 30,358 pieces > 10,000 -> the 10-m default
    from planner.candidates.pool import PoolOptions
    from planner.plan.problem import resolve
    from planner.plan.strategy import FINE_GRID_M, FINE_GRID_PIECES

    assert _strategy("plant_16ha").grid_spacing_m == FINE_GRID_M == 4.0 and 7_688 <= FINE_GRID_PIECES
    assert "candidate grid 4 m where none is given" in _strategy("plant_16ha").line()
    assert _strategy("plant_64ha").grid_spacing_m is None and _strategy("polygon_a").grid_spacing_m is None
    plant = load_site(INSTANCES / "plant_16ha.json")
    assert resolve(plant, PlanOptions()).options.pool.grid_spacing_m == 4.0
    given = resolve(plant, PlanOptions(pool=PoolOptions(grid_spacing_m=10.0)))
    assert given.options.pool.grid_spacing_m == 10.0 and given.strategy.grid_spacing_m is None  # no 4 m recorded
    assert "candidate grid" not in given.strategy.line()
    # the fine grid's estimate (0.87 GiB on 16 ha) over a 600-MiB limit: the 10-m grid, which fits (0.38 GiB)
    small = resolve(plant, PlanOptions(memory_limit_bytes=600 * 2**20))
    assert small.options.pool.grid_spacing_m == 10.0 and small.strategy.grid_spacing_m is None
    # tiles asked for (`--tiles 100`, or plan_by_tiles with its TileOptions): the automatic strategy's grid is its own
    from planner.plan.strategy import StrategyOptions, TileOptions
    from planner.tiles.prepare import tiles_problem

    asked = PlanOptions(strategy=StrategyOptions(tiling=TileOptions(tile_m=100.0)))
    assert resolve(plant, asked).options.pool.grid_spacing_m == 10.0
    assert tiles_problem(plant, None, TileOptions(tile_m=100.0)).options.pool.grid_spacing_m == 10.0
    assert resolve(load_site(INSTANCES / "polygon_a.json"), PlanOptions()).options.pool.grid_spacing_m == 10.0
