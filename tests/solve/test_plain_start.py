"""The plain start of a MILP block: CFT's cover shrunk by the plain local search (planner.solve.plain_start)."""

from __future__ import annotations

import importlib

import numpy as np
import pytest
import scipy.sparse as sp

from planner.core.errors import UsageError
from planner.coverage.overlap import OverlapRule
from planner.plan.strategy import MOVES_PER_PIECE
from planner.solve.cft import CftCover
from planner.solve.greedy import greedy_cover
from planner.solve.instance import CoverInstance
from planner.solve.milp import MilpOptions, block_solvers, solve
from planner.solve.plain_start import MIN_TARGETS, MOVES_PER_TARGET, plain_start

#: the module (``planner.solve`` as an attribute is the package's ``solve`` function), where tests replace CFT
PLAIN_MODULE = importlib.import_module("planner.solve.plain_start")


def _matrix(cover: list[set[int]], n_targets: int) -> sp.csr_matrix:
    rows = [i for i, c in enumerate(cover) for _ in c]
    cols = [t for c in cover for t in sorted(c)]
    return sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(len(cover), n_targets))


# Chvatal's trap, 30 targets: r0 sees 0..14, r1 sees 15..29 (15 each); c0 sees 8 of each half (16 targets), c1 the
# next 4 of each (8), c2 the next 2 (4), c3 the last one of each (2). The greedy takes the candidate that sees the
# most unseen targets: c0 (16 > 15), then c1 (8 > 7 left in each half), c2 (4 > 3), c3 (2 > 1): 4 stations. The
# optimum is 2 (r0 + r1; no candidate sees all 30: the largest sees 16), and the cover LP is at least 30 / 16 =
# 1.875, rounded up 2 < 4, so the greedy does not meet the bound and the plain start runs.
def _half(lo: int, n: int) -> set[int]:
    return set(range(lo, lo + n))


TRAP = [
    _half(0, 8) | _half(15, 8),
    _half(8, 4) | _half(23, 4),
    _half(12, 2) | _half(27, 2),
    {14, 29},
    _half(0, 15),
    _half(15, 15),
]
PLAIN = MilpOptions(overlap=None)


def _is_cover(a: sp.csr_matrix, chosen) -> bool:
    return bool((np.bincount(a[list(chosen)].indices, minlength=a.shape[1]) > 0).all())


def test_the_trap_greedy_takes_four_and_the_plain_start_two():
    a = _matrix(TRAP, 30)
    greedy = list(greedy_cover(a).selected)
    assert greedy == [0, 1, 2, 3]
    start = plain_start(a, np.ones(6), None, greedy, PLAIN)
    assert start is not None and start.greedy == 4 and start.cft is not None
    assert start.selected == (4, 5) and _is_cover(a, start.selected)
    assert 1.875 - 1e-9 <= start.bound <= 2 + 1e-9


def test_the_search_reaches_the_optimum_from_a_cover_as_bad_as_the_greedy(monkeypatch):
    # CFT made to return the greedy's 4 stations with no bound: the local search (10 moves per target, 300) drops
    # c3 (its two targets also seen by c2 and by r0, r1) and swaps down to r0 + r1, the optimum 2 (the LP's floor)
    a = _matrix(TRAP, 30)
    monkeypatch.setattr(
        PLAIN_MODULE, "cft_cover", lambda *_, **__: CftCover(selected=(0, 1, 2, 3), lower_bound=0, time_s=0)
    )
    start = plain_start(a, np.ones(6), None, [0, 1, 2, 3], PLAIN)
    assert start is not None and start.cft == 4 and start.searched == 2 and start.selected == (4, 5)
    assert 0 < start.moves <= 300
    # with the search off (no moves) the start stays the greedy's
    off = plain_start(a, np.ones(6), None, [0, 1, 2, 3], MilpOptions(overlap=None, plain_start_moves=0))
    assert off is not None and off.moves == 0 and off.selected == (0, 1, 2, 3)


def test_a_plain_block_starts_from_the_optimum_before_any_solve():
    # presolve off: it would merge the targets of equal seers, leaving fewer than MIN_TARGETS
    inst = CoverInstance(_matrix(TRAP, 30), np.ones(6))
    _, (block,) = block_solvers(inst, MilpOptions(overlap=None, presolve=False))
    assert block.plain is not None and block.plain.greedy == 4
    assert sorted(block.incumbent) == [4, 5] and block.rounds == 0 and block.bound >= 1.875 - 1e-9
    r = solve(inst, overlap=None, presolve=False)
    assert r.status.value == "optimal" and r.selected == (4, 5)
    assert r.info["plain_start"] == {"blocks": 1, "cft_blocks": 1, "greedy": 4, "start": 2, "moves": 0}


def _random(seed: int, n: int = 80, m: int = 120, density: float = 0.06) -> sp.csr_matrix:
    rng = np.random.default_rng(seed)
    a = rng.random((n, m)) < density
    for j in np.flatnonzero(~a.any(axis=0)):
        a[rng.integers(n), j] = True
    return sp.csr_matrix(a)


@pytest.mark.parametrize("seed", [0, 1])
def test_same_block_and_seed_give_the_same_start(seed):
    a = _random(seed)
    greedy = list(greedy_cover(a).selected)
    runs = [plain_start(a, np.ones(a.shape[0]), None, greedy, MilpOptions(overlap=None, seed=seed)) for _ in range(2)]
    assert runs[0] is not None and runs[0] == runs[1]
    assert _is_cover(a, runs[0].selected) and len(runs[0].selected) <= len(greedy)
    inst = CoverInstance(a, np.ones(a.shape[0]))
    first, second = (solve(inst, overlap=None, seed=seed) for _ in range(2))
    assert first.selected == second.selected and first.info["plain_start"] == second.info["plain_start"]


def test_a_connected_block_never_takes_the_plain_start(monkeypatch):
    def refuse(*_, **__):
        raise AssertionError("CFT called for a connected block")

    monkeypatch.setattr(PLAIN_MODULE, "cft_cover", refuse)
    a = _matrix(TRAP, 30)
    inst = CoverInstance(a, np.ones(6), groups=("g",) * 6, target_length_m=np.ones(30))
    o = MilpOptions(overlap=OverlapRule(), presolve=False, ring_bound=False)
    _, blocks = block_solvers(inst, o)
    assert blocks and all(b.plain is None for b in blocks)
    r = solve(inst, o)
    assert r.objective is not None and "plain_start" not in r.info


def test_small_or_solved_blocks_keep_their_greedy(monkeypatch):
    def refuse(*_, **__):
        raise AssertionError("CFT called")

    monkeypatch.setattr(PLAIN_MODULE, "cft_cover", refuse)
    # fewer than MIN_TARGETS targets: no start at all
    small = _matrix([{0, 1}, {1, 2}, {2, 3}], 4)
    assert MIN_TARGETS > 4 and plain_start(small, np.ones(3), None, [0, 2], PLAIN) is None
    # 40 targets in two halves seen by c0 and c1, c2 sees 10 of each: the greedy c0 + c1 meets the LP's 2
    halves = _matrix([_half(0, 20), _half(20, 20), _half(0, 10) | _half(20, 10)], 40)
    met = plain_start(halves, np.ones(3), None, [0, 1], PLAIN)
    assert met is not None and met.cft is None and met.selected == (0, 1) and met.bound == pytest.approx(2)
    # off, k = 2 and costs not all equal: none
    a = _matrix(TRAP, 30)
    for o, cost in ((MilpOptions(overlap=None, plain_start=False), np.ones(6)), (PLAIN, np.arange(1.0, 7.0))):
        assert plain_start(a, cost, None, [0, 1, 2, 3], o) is None
    assert plain_start(a, np.ones(6), None, [0, 1, 2, 3], MilpOptions(overlap=None, k=2)) is None


def test_the_moves_per_target_are_the_tiled_plans_per_piece():
    assert MilpOptions().plain_start_moves == MOVES_PER_TARGET == MOVES_PER_PIECE


@pytest.mark.parametrize(
    ("field", "value"), [("plain_start", "yes"), ("plain_start_moves", -1.0), ("plain_start_moves", None)]
)
def test_options_are_checked(field, value):
    with pytest.raises(UsageError):
        MilpOptions(**{field: value})
