"""The pool's fingerprint (planner.coverage.fingerprint) the same for two builds of one problem, another for another
pool."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

import planner
from planner.candidates.pool import PoolOptions
from planner.coverage.fingerprint import DIGITS, pool_fingerprint, pool_of
from planner.plan.run import build_problem

INSTANCES = Path(__file__).resolve().parents[2] / "instances"


def _options(grid_m: float = 20.0) -> planner.PlanOptions:
    # coarse pieces and grid: polygon B (the smallest bundled site scanned from both sides) builds in a few tenths
    return planner.PlanOptions(target_spacing_m=5.0, pool=PoolOptions(grid_spacing_m=grid_m))


@pytest.fixture(scope="module")
def site():
    return planner.load_site(INSTANCES / "polygon_b.json")


@pytest.fixture(scope="module")
def problem(site):
    return build_problem(site, _options())


def test_two_builds_of_one_problem_have_one_fingerprint(site, problem):
    again = build_problem(planner.load_site(INSTANCES / "polygon_b.json"), _options())
    pool = pool_of(problem)
    assert pool == pool_of(again)
    assert len(pool.fingerprint) == DIGITS and int(pool.fingerprint, 16) >= 0
    assert (pool.candidates, pool.targets, pool.pairs) == (*problem.shape, problem.by_candidate.nnz)
    assert pool.to_dict() == {
        "candidates": pool.candidates,
        "targets": pool.targets,
        "pairs": pool.pairs,
        "fingerprint": pool.fingerprint,
    }


def test_another_pool_has_another_fingerprint(site, problem):
    print_ = pool_of(problem).fingerprint
    coarser = build_problem(site, _options(grid_m=25.0))  # another candidate spacing
    assert pool_of(coarser).fingerprint != print_
    cands, targets = problem.candidates, problem.targets
    assert pool_fingerprint(cands, targets) == print_
    assert pool_fingerprint(cands[1:], targets) != print_  # one candidate dropped
    assert pool_fingerprint(cands[::-1], targets) != print_  # the pool's order counts
    moved = replace(cands[0], x=cands[0].x + 0.01)  # 1 cm: another position
    assert pool_fingerprint((moved, *cands[1:]), targets) != print_
    shaken = replace(cands[0], x=cands[0].x + 1e-7, id="renamed")  # below 1 mm, and the id: the same pool
    assert pool_fingerprint((shaken, *cands[1:]), targets) == print_
    finer = build_problem(site, replace(_options(), target_spacing_m=4.0))  # other targets
    assert pool_fingerprint(finer.candidates, finer.targets) != pool_fingerprint(finer.candidates, targets)
