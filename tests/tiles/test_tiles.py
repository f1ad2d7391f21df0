"""Planning by tiles: exact coverage, verified and registered plans, a valid bound, Dask = serial."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.core import progress
from planner.coverage.matrix import build_coverage
from planner.io.load import load_site
from planner.plan import PlanOptions
from planner.solve.milp import MilpOptions
from planner.tiles import TileOptions, dask_client, plan_by_tiles
from planner.tiles.bound import lp_bound
from planner.tiles.layout import make_tiles, tile_job, zone_anchors
from planner.tiles.prepare import prepare
from planner.tiles.tasks import tile_task
from tests.conftest import INSTANCES

OPTIONS = PlanOptions(method="milp", pricing=False, tripod=True, milp=MilpOptions(time_limit_s=20))
TILING = TileOptions(tile_m=50.0, tile_time_limit_s=20.0, bound_time_limit_s=20.0)


@pytest.fixture(scope="module")
def site():
    return load_site(INSTANCES / "plant_1ha.json")


class _Notes:
    """A progress sink that keeps the notes (the bar's share reports are dropped)."""

    def __init__(self) -> None:
        self.lines: list[str] = []

    def __call__(self, step: str, done: float, total: float) -> None:
        pass

    def note(self, text: str) -> None:
        self.lines.append(text)


@pytest.fixture(scope="module")
def serial_run(site):
    notes = _Notes()
    previous = progress.set_sink(notes)
    try:
        return plan_by_tiles(site, OPTIONS, TILING), notes.lines
    finally:
        progress.set_sink(previous)


@pytest.fixture(scope="module")
def serial(serial_run):
    return serial_run[0]


@pytest.mark.slow
def test_progress_says_each_tile_and_phase_with_incumbent_and_bound(serial_run) -> None:
    # issue 34: one line per tile (its stations, its MILP bound) and per phase (the incumbent, the bound, the gap);
    # the figures are the plan's own: the tiles' in plan.json, the last incumbent the plan, the bound its bound
    plan, lines = serial_run
    tiles = plan.result.info["tiles"]
    tile_lines = [line for line in lines if line.startswith("tile ")]
    assert len(tile_lines) == len(tiles) == 4
    for k, (line, tile) in enumerate(zip(tile_lines, tiles)):
        assert line.startswith(f"tile {k + 1}/4 ") and f": {tile['stations']} stations, " in line
    phases = [line.split(":")[0] for line in lines[len(tiles) :]]
    assert phases[0] == "stitched" and phases[-2:] == ["best plan and local search", "window re-solves"]
    assert lines[-1].startswith(f"window re-solves: incumbent {len(plan.stations)} stations (connected)")
    bound = int(plan.result.bound)
    assert f"bound {bound} over the pool" in lines[-1]
    assert f"gap {(len(plan.stations) - bound) / len(plan.stations):.1%}" in lines[-1]


@pytest.mark.slow
def test_tiles_columns_are_the_site_matrix(site) -> None:
    """Each piece is in one tile, and a tile's candidates (within S_max of its pieces) are all that can see
    them: the tiles' pairs, put together, are exactly the pairs of the whole-site build."""
    prep = prepare(site, OPTIONS)
    pool, targets, limits, xy, usable = list(prep.pool), prep.targets, prep.limits, prep.xy, prep.usable
    whole = build_coverage(site, pool, targets, limits)
    assert set(np.flatnonzero(~usable).tolist()) <= set(whole.excluded)  # standing nowhere: excluded there too
    anchor = zone_anchors(site, targets)
    tiles = make_tiles(anchor, 50.0, limits.max_slant_range_m)
    assert len(tiles) == 4  # anchors span about 66 m (cell centres 16.5..82.5 m): 2 x 2 tiles of 50 m
    jobs = [tile_job(t, anchor, targets, xy, usable) for t in tiles]
    assert sorted(np.concatenate([j.targets for j in jobs]).tolist()) == list(range(len(targets)))
    pairs = set()
    for job in jobs:
        r = tile_task(
            prep.problem.sight, pool, targets, ["g"] * len(pool), job, MilpOptions(overlap=None, time_limit_s=5)
        )
        pairs |= set(zip(r.rows.tolist(), r.cols.tolist()))
    coo = whole.by_candidate.tocoo()
    assert pairs == set(zip(coo.row.tolist(), coo.col.tolist()))
    # the matrix the gap studies use (Prepared.coverage, built in one piece) is the tiles' matrix
    study = prep.coverage().tocoo()
    assert pairs == set(zip(study.row.tolist(), study.col.tolist()))


@pytest.mark.slow
def test_tiled_plan_verifies_is_one_bundle_and_bounded(site, serial) -> None:
    info = serial.result.info
    assert all(t["covers_core"] for t in info["tiles"])  # every tile's plan covers its own pieces
    assert serial.verification.percent == 100.0  # the stitched plan, re-verified at 0.1 m
    assert list(serial.registration.values()) == [1]  # the roads are one accessible area: one bundle
    bound = serial.result.bound
    assert math.ceil(info["lp_bound"] - 1e-6) <= bound <= len(serial.stations)
    assert serial.result.gap == pytest.approx((len(serial.stations) - bound) / len(serial.stations))


@pytest.mark.slow
def test_tiled_plan_has_a_tripod_disc_per_station(serial) -> None:
    # as plan_site: one disc per station, centred on it (no --recentre), radius >= 0, and a station
    # whose relied pieces allow no disc of the stated resolution gets radius 0, never a negative one
    discs = serial.tripods
    assert [d.station for d in discs] == [s.id for s in serial.stations]
    for d, s in zip(discs, serial.stations):
        assert d.radius_m >= 0.0
        assert math.dist(d.centre, s.xy) <= d.radius_m + 1e-9  # the disc holds its station
    assert all(d.relied_targets > 0 for d in discs)  # every station is relied on for some piece


@pytest.mark.slow
def test_tile_milps_run_on_work_limits_by_default(serial) -> None:
    # CP-SAT work (deterministic seconds) limits the tile and bound MILPs, so the plan does not depend on
    # the load; plan.json names any part whose 4x wall-clock cap was reached instead (none on a quiet
    # machine; not asserted, since that is a matter of speed)
    info = serial.result.info
    assert info["limits"] == "CP-SAT work (deterministic s)"
    assert isinstance(info["wall_cap_hit"], list) and all(isinstance(name, str) for name in info["wall_cap_hit"])
    assert any("deterministic seconds" in line for line in serial.log)


def test_lp_bound_of_a_small_cover() -> None:
    """Three targets, candidates {0,1}, {1,2}, {0,2}: x = 1/2 each covers every target twice-halved, LP 1.5."""
    import scipy.sparse as sp

    a = sp.csr_matrix(np.array([[1, 1, 0], [0, 1, 1], [1, 0, 1]], dtype=bool))
    assert lp_bound(a) == pytest.approx(1.5)


@pytest.mark.slow
def test_dask_on_two_workers_gives_the_serial_plan(site, serial) -> None:
    with dask_client(workers=2) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        dist = plan_by_tiles(site, OPTIONS, TILING, client=client)
    assert dist.result.selected == serial.result.selected
    assert dist.result.bound == serial.result.bound
    assert [t["stations"] for t in dist.result.info["tiles"]] == [t["stations"] for t in serial.result.info["tiles"]]


@pytest.mark.slow
def test_translated_plant_gives_the_same_counts(site, serial) -> None:
    from dataclasses import replace

    from planner.site.model import NoGoArea, Obstacle, Zone

    dx, dy = 1000.0, -500.0

    def move(v):
        return tuple((x + dx, y + dy) for x, y in v)

    zones = tuple(Zone(z.id, z.scan_side, move(z.vertices), z.vertex_heights_m) for z in site.zones)
    moved = replace(
        site,
        zones=zones,
        boundary=move(site.boundary),
        obstacles=tuple(Obstacle(o.name, move(o.vertices), o.height_m) for o in site.obstacles),
        no_go_areas=tuple(NoGoArea(n.name, move(n.vertices)) for n in site.no_go_areas),
    )
    plan = plan_by_tiles(moved, OPTIONS, TILING)
    assert len(plan.stations) == len(serial.stations)
    assert plan.result.bound == serial.result.bound


@pytest.mark.slow
def test_prepare_groups_follow_the_registration_mode(site) -> None:
    """Tiles default to ``site`` registration: the 1-ha plant's open ground is one accessible area, so one
    group; ``zone`` gives one group per object (9 zones in plant_1ha.json); links reach the sight range
    (P30 at the plant's limits: 60 m) and the rule is the site's 30 % overlap."""
    plain = prepare(site, OPTIONS)
    assert plain.registration.mode == "site" and len(set(plain.groups)) == 1
    zoned = prepare(site, PlanOptions(method="milp", pricing=False, registration="zone"))
    assert zoned.registration.mode == "zone" and len(set(zoned.groups)) == len(site.zones) == 9
    reg = plain.registration
    assert reg.reach_m == pytest.approx(60.0) and reg.checked_rule.overlap == pytest.approx(0.3)
    assert len(plain.pool) == len(plain.groups) == plain.xy.shape[0] == plain.usable.size


def _corridor():
    from planner.site.model import ScanSide, Site, Zone
    from planner.site.params import Parameters

    zone = Zone("K", ScanSide.INSIDE, ((0.0, 0.0), (200.0, 0.0), (200.0, 8.0), (0.0, 8.0)), (3.0,) * 4)
    return Site("corridor", (zone,), parameters=Parameters(theta_max_deg=68.0, overlap=0.0))


def test_tiles_plan_a_corridor_from_the_single_models_pool() -> None:
    # a 200 x 8 m corridor, which the 10-m grid's rows miss: the tiles take the single model's pool (its medial
    # axis), so they plan it within the centre-line construction (h tan 68 = 7.4 m of wall either side, 200 / 14.85)
    plan = plan_by_tiles(_corridor(), OPTIONS, TILING)
    assert plan.verification.complete and len(plan.stations) <= 14


def test_tiles_complete_a_pool_that_misses_pieces(monkeypatch) -> None:
    # a pool that keeps only the candidates of the corridor's western half: the pieces of the east are seen by
    # none, their regions are not empty, so each gets a candidate from its region and the tiles run again
    import planner.tiles.prepare as prep_mod

    whole = prep_mod.site_candidates

    def west(*args, **kwargs):
        return [c for c in whole(*args, **kwargs) if c.x < 100.0]

    monkeypatch.setattr(prep_mod, "site_candidates", west)
    plan = plan_by_tiles(_corridor(), OPTIONS, TILING)
    assert plan.verification.complete
    assert any(s.x > 100.0 for s in plan.stations)  # the east is planned, from the completed candidates


@pytest.mark.slow
def test_no_overlap_is_honoured_by_tiles(site, serial) -> None:
    # --no-overlap (MilpOptions(overlap=None)): the tiled run plans the plain cover (CFT's, then the local search
    # with no links), never the connected plan; every piece is still seen, and it needs no more stations than
    # the connected plan of the same pool (that plan is a cover too)
    options = PlanOptions(method="milp", pricing=False, tripod=True, milp=MilpOptions(overlap=None, time_limit_s=20))
    plain = plan_by_tiles(site, options, TILING)
    assert plain.problem.rule is None
    assert plain.verification.percent == 100.0
    assert len(plain.stations) <= len(serial.stations)
    info = plain.result.info
    assert info["cover"]["engine"].startswith("CFT") and info["windows"] == {}  # no connected window re-solves
    assert any("kept the whole-site cover" in line and "connected plans" not in line for line in plain.log)
    assert info["bound_terms"][0]["bound"] == "cover LP" and plain.result.bound <= len(plain.stations)


@pytest.mark.slow
def test_tiles_without_tile_milps_still_plan_a_verified_connected_site(site) -> None:
    # tile_plans=False (the automatic strategy's choice where CFT runs): the tiles give the coverage only; the
    # plan is grown from CFT's cover and the connected greedy, and is checked like any other
    tiling = TileOptions(tile_m=50.0, tile_time_limit_s=20.0, tile_plans=False)
    plan = plan_by_tiles(site, OPTIONS, tiling)
    info = plan.result.info
    assert {t["status"] for t in info["tiles"]} == {"no_solution"} and all(t["stations"] == 0 for t in info["tiles"])
    assert "tile plans" not in info["stitch"]["source"]
    assert plan.verification.percent == 100.0 and list(plan.registration.values()) == [1]
    assert any("no tile MILPs" in line for line in plan.log)
