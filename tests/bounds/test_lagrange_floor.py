"""The parts of the Lagrangian bound: the LP floor of a part and the two-stage CP-SAT work are proven bounds."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import linprog

from planner.bounds import lagrange
from planner.bounds.lagrange import PartJob, solve_part


def brute_force(a: sp.csr_matrix, w: np.ndarray) -> int:
    """The cheapest cover of the columns of ``a`` (candidates x pieces), trying every subset of candidates."""
    masks = np.array(list(itertools.product([0, 1], repeat=a.shape[0])), dtype=np.int64)
    covers = (masks @ a.toarray().astype(np.int64) > 0).all(axis=1)
    return int((masks[covers] @ w).min())


def random_part(seed: int, n_t: int = 8, n_extra: int = 7) -> tuple[sp.csr_matrix, np.ndarray]:
    """Every piece seen by its own candidate (a cover exists) plus random candidates; integer costs, some 0 or < 0."""
    rng = np.random.default_rng(seed)
    sets = [[t] for t in range(n_t)] + [
        sorted(rng.choice(n_t, size=rng.integers(2, 5), replace=False).tolist()) for _ in range(n_extra)
    ]
    rows = [j for j, s in enumerate(sets) for _ in s]
    cols = [t for s in sets for t in s]
    a = sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(len(sets), n_t))
    return a, rng.integers(-3, 60_000, size=len(sets)).astype(np.int64)


@pytest.mark.parametrize("seed", range(8))
def test_lp_floor_is_at_most_the_optimum_and_at_least_the_lp_rounded(seed: int) -> None:
    a, w = random_part(seed)
    w = np.abs(w)  # the floor is for costs >= 0
    at = a.T.tocsr()
    lp = linprog(w.astype(float), A_ub=-at.astype(float), b_ub=-np.ones(at.shape[0]), bounds=(0, None)).fun
    floor = lagrange._lp_floor(at, w)
    assert floor <= brute_force(a, w)
    assert floor >= np.ceil(lp - 1e-3) - 1  # nothing lost but rounding


@pytest.mark.parametrize("work_s", [1e-9, 0.05, 1.0])
@pytest.mark.parametrize("seed", range(6))
def test_part_answer_is_a_cover_and_its_lower_a_bound_whatever_the_work(seed: int, work_s: float) -> None:
    # with almost no work the greedy covers and the LP floor bounds; with more the first share or the second run
    # proves the optimum: in every case the cover covers, its cost is its objective, and lower <= optimum <= objective
    a, w = random_part(seed)
    r = solve_part(PartJob(a, w, None), work_s)
    assert (a[r.chosen].getnnz(axis=0) > 0).all() and r.objective == int(w[r.chosen].sum())
    opt = brute_force(a, w)
    assert r.lower <= opt <= r.objective
    if r.optimal:
        assert r.lower == r.objective == opt


def test_a_near_part_gets_the_rest_of_its_work_and_a_far_one_does_not(monkeypatch: pytest.MonkeyPatch) -> None:
    # the second CP-SAT run starts only where the first share left its best cover within CLOSE_GAP of the bound
    a, w = random_part(3)
    w = np.abs(w)
    calls: list[float] = []
    run = lagrange._cp_sat

    def far(at, ww, hint, work_s, seed, names):  # type: ignore[no-untyped-def]
        calls.append(work_s)
        r = run(at, ww, hint, work_s, seed, names)
        return lagrange._Run(chosen=r.chosen, lower=0, optimal=False, capped=False)

    monkeypatch.setattr(lagrange, "_lp_floor", lambda at, ww: 0)
    monkeypatch.setattr(lagrange, "_cp_sat", far)
    solve_part(PartJob(a, w, None), 4.0)
    assert calls == [4.0 * lagrange.FIRST_SHARE]  # lower 0: far, stops after the first share
    calls.clear()
    monkeypatch.setattr(
        lagrange,
        "_lp_floor",
        lambda at, ww: int(ww[run(at, ww, None, 10.0, 0, np.arange(at.shape[1])).chosen].sum()) - 1,
    )
    solve_part(PartJob(a, w, None), 4.0)
    assert calls[-2:] == [4.0 * lagrange.FIRST_SHARE, 4.0]  # one short of the cover: near, the full work follows
