"""The Lagrangian bound over tiles: hand-checked covers where it closes the LP gap, and validity on random covers."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import scipy.sparse as sp

from planner.bounds.lagrange import group_parts, lagrangian_bound, split_costs
from planner.core.errors import UsageError
from planner.tiles.bound import lp_bound


def cover(sets: list[list[int]], n_targets: int) -> sp.csr_matrix:
    """Candidates (rows) seeing the listed targets."""
    rows = [j for j, s in enumerate(sets) for _ in s]
    cols = [t for s in sets for t in s]
    return sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(len(sets), n_targets))


def brute_force(a: sp.csr_matrix, cost: np.ndarray) -> float:
    """The cheapest cover, trying every subset of candidates at once."""
    masks = np.array(list(itertools.product([0, 1], repeat=a.shape[0])), dtype=np.int64)
    covers = (masks @ a.toarray().astype(np.int64) > 0).all(axis=1)
    return float((masks[covers] @ cost).min())


def test_triangle_and_a_lone_piece_in_two_tiles() -> None:
    # tile 0: triangle t0 t1 t2 seen by A{t0,t1}, B{t1,t2}, C{t2,t0}; tile 1: t3 seen by D only. LP: A = B = C = 1/2 and
    # D = 1, 2.5. The triangle alone needs two stations, so every cover costs 3, and the tile bound is OPT_0 + OPT_1 = 2
    # + 1 = 3 (no station is shared, so no split matters).
    a = cover([[0, 1], [1, 2], [2, 0], [3]], 4)
    parts = [np.array([0, 1, 2]), np.array([3])]
    b = lagrangian_bound(a, parts, iterations=0, work_s=1.0)
    assert lp_bound(a) == pytest.approx(2.5)
    assert b.lp == pytest.approx(2.5)
    assert b.raw == pytest.approx(3.0)
    assert b.value == 3 and b.per_tile == pytest.approx((2.0, 1.0)) and b.optimal


@pytest.mark.parametrize("start", ["lp", "equal"])
def test_two_triangles_joined_by_a_dear_station(start: str) -> None:
    # tile 0: triangle t0 t1 t2 (A, B, C as above, cost 1); tile 1: triangle t3 t4 t5 (D{t3,t4}, E{t4,t5}, F{t5,t3},
    # cost 1); S{t0,t3} costs 2 and is shared. LP: y = 1/2 on every piece is dual feasible (each station's pieces sum to
    # 1 <= its cost) and x = 1/2 on A..F is primal, so LP = 3. Every cover costs 4: two of a triangle's own stations
    # each (2 + 2), or S + B + E (2 + 1 + 1). Split of S: the LP duals give 1/2 + 1/2, the reduced cost 2 - 1 = 1 is
    # halved, so 1 per tile, as the equal split 2 / 2. Tile 0 then: two of A, B, C (2) or S + B (1 + 1) -> OPT_0 = 2;
    # likewise OPT_1 = 2: bound 4 = the integer optimum, where the LP says 3.
    a = cover([[0, 1], [1, 2], [2, 0], [3, 4], [4, 5], [5, 3], [0, 3]], 6)
    cost = np.array([1, 1, 1, 1, 1, 1, 2], dtype=float)
    parts = [np.array([0, 1, 2]), np.array([3, 4, 5])]
    cands, lams = split_costs(a, parts, cost, None if start == "equal" else np.full(6, 0.5))
    assert lams[0][cands[0] == 6] == pytest.approx([1.0]) and lams[1][cands[1] == 6] == pytest.approx([1.0])
    b = lagrangian_bound(a, parts, cost=cost, iterations=0, work_s=1.0, start=start)
    assert b.lp == pytest.approx(3.0)
    assert b.value == 4 == brute_force(a, cost)


@pytest.mark.parametrize("seed", [*range(4), *(pytest.param(s, marks=pytest.mark.slow) for s in range(4, 12))])
def test_bound_is_valid_and_at_least_the_lp_on_random_covers(seed: int) -> None:
    # every piece seen by its own station (so a cover exists) plus random stations; parts at random
    rng = np.random.default_rng(seed)
    n_t, n_extra = 9, 8
    sets = [[t] for t in range(n_t)] + [
        sorted(rng.choice(n_t, size=rng.integers(2, 5), replace=False).tolist()) for _ in range(n_extra)
    ]
    a = cover(sets, n_t)
    cost = rng.integers(1, 4, size=len(sets)).astype(float)
    label = rng.integers(0, 3, size=n_t)
    parts = [np.flatnonzero(label == k) for k in range(3) if np.any(label == k)]
    opt = brute_force(a, cost)
    for iterations in (0, 3):
        b = lagrangian_bound(a, parts, cost=cost, iterations=iterations, work_s=1.0, scale=1000)
        assert b.value <= opt + 1e-9  # a lower bound on every cover
        assert b.upper >= opt - 1e-9  # the pruned union of the parts' covers is a cover
        # the LP-dual split gives each part at least its pieces' duals; flooring the costs to 1/1000 loses at most
        # 1/1000 per candidate of each part
        assert b.raw >= b.lp - sum(len(p) for p in split_costs(a, parts, cost, None)[0]) / 1000 - 1e-9


def test_group_parts_joins_two_by_two() -> None:
    cells = [(0, 0), (0, 1), (0, 2), (1, 0), (1, 1), (2, 2)]
    parts = [np.array([k]) for k in range(6)]
    grouped = group_parts(cells, parts, 2)
    assert [g.tolist() for g in grouped] == [[0, 1, 3, 4], [2], [5]]
    assert [g.tolist() for g in group_parts(cells, parts, 1)] == [[k] for k in range(6)]


def test_parts_must_partition_the_pieces() -> None:
    a = cover([[0, 1], [1, 2]], 3)
    with pytest.raises(UsageError):
        lagrangian_bound(a, [np.array([0, 1]), np.array([1, 2])])
    with pytest.raises(UsageError):
        lagrangian_bound(a, [np.array([0, 1])])


@pytest.mark.slow
def test_tiled_plan_reports_the_lagrangian_bound() -> None:
    from planner.io.load import load_site
    from planner.plan import PlanOptions
    from planner.solve.milp import MilpOptions
    from planner.tiles import TileOptions, plan_by_tiles
    from tests.conftest import INSTANCES

    site = load_site(INSTANCES / "plant_1ha.json")
    tiling = TileOptions(tile_m=50.0, tile_time_limit_s=5.0, bound_time_limit_s=5.0, lagrange=True, lagrange_work_s=5.0)
    plan = plan_by_tiles(site, PlanOptions(method="milp", pricing=False, milp=MilpOptions(time_limit_s=5)), tiling)
    info = plan.result.info
    lag = info["lagrange"]
    assert len(lag["per_tile"]) == len(info["tiles"]) == 4  # 2 x 2 tiles of 50 m, one part each
    assert lag["raw"] == pytest.approx(sum(lag["per_tile"]))
    assert "Lagrangian over 4 tile parts" in info["bound_how"]
    # the reported bound is the largest of those computed (LP, cover MILP, Lagrangian, CFT's), and bounds the plan
    milp = info["cover_milp_bound"]
    cft = math.ceil(info["cover"]["lower_bound"] - 1e-6)
    lp = math.ceil(info["lp_bound"] - 1e-6)
    expected = max(lp, math.ceil(milp - 1e-6) if milp is not None else 0, lag["value"], cft)
    assert plan.result.bound == expected <= len(plan.stations)
    assert [t["stations"] for t in info["bound_terms"]] == [lp, lag["value"], cft] + (
        [math.ceil(milp - 1e-6)] if milp is not None else []
    )
    assert info["bound_decided_by"] in info["bound_how"]
    assert lag["raw"] >= info["lp_bound"] - 0.01  # LP-dual split: at least the LP, less the flooring


def test_tile_options_reject_a_group_below_one() -> None:
    from planner.tiles import TileOptions

    with pytest.raises(UsageError):
        TileOptions(lagrange_group=0)


@pytest.mark.slow
def test_a_part_with_no_cover_within_its_work_gets_the_greedy_and_a_valid_bound(monkeypatch):
    # a part with no cover found within its work gets the greedy's cover and CP-SAT's lower bound (0 when none): 700
    # candidates (the identity keeps every piece coverable) x 300 pieces, costs 1-4; with 1e-12 deterministic s the
    # greedy runs, its cover covers every piece at the cost it reports, and its bound is below the part's optimum
    import importlib

    import scipy.sparse as sp

    lagrange = importlib.import_module("planner.bounds.lagrange")
    calls = []
    greedy = lagrange._greedy_part
    monkeypatch.setattr(lagrange, "_greedy_part", lambda a, w: calls.append(a.shape) or greedy(a, w))
    a = sp.random(400, 300, density=0.03, random_state=1, format="csr").astype(bool)
    a = sp.vstack([a, sp.identity(300, format="csr", dtype=bool)]).tocsr()
    w = np.random.default_rng(0).integers(1, 5, size=a.shape[0]).astype(np.int64)
    quick = lagrange.solve_part(lagrange.PartJob(a, w, None), 1e-12)
    assert calls and not quick.optimal
    assert (a[quick.chosen].getnnz(axis=0) > 0).all() and quick.objective == int(w[quick.chosen].sum())
    full = lagrange.solve_part(lagrange.PartJob(a, w, None), 20.0)
    assert full.optimal and quick.lower <= full.objective <= quick.objective
