"""A work limit (CP-SAT deterministic seconds) makes a time-limited MILP's answer independent of the load."""

from __future__ import annotations

import threading

import numpy as np
import pytest
import scipy.sparse as sp

from planner.errors import UsageError
from planner.solve.instance import CoverInstance
from planner.solve.milp import MilpOptions, solve
from planner.solve.result import Status


def random_cover(seed: int, n_cand: int = 400, n_targ: int = 600, density: float = 0.012) -> CoverInstance:
    """A seeded random set cover, each target seen by at least one candidate, no registration groups."""
    rng = np.random.default_rng(seed)
    a = rng.random((n_cand, n_targ)) < density
    a[rng.integers(0, n_cand, n_targ), np.arange(n_targ)] = True
    return CoverInstance(by_candidate=sp.csr_matrix(a), cost=np.ones(n_cand), name=f"random-{seed}")


def _burn(stop: threading.Event) -> None:
    x = 0
    while not stop.is_set():
        x = (x * 31 + 7) % 1_000_003


def test_work_limited_answer_is_the_same_on_a_busy_machine() -> None:
    inst = random_cover(3)
    opts = MilpOptions(overlap=None, time_limit_s=120.0, work_limit=0.05, presolve=False)
    quiet = solve(inst, opts)
    stop = threading.Event()
    burners = [threading.Thread(target=_burn, args=(stop,)) for _ in range(3)]
    for t in burners:
        t.start()
    try:
        busy = solve(inst, opts)
    finally:
        stop.set()
        for t in burners:
            t.join()
    # the work limit ended the search (no proof at 0.05 deterministic s), not the 120 s wall cap
    assert quiet.status is Status.FEASIBLE
    assert quiet.info["work"]["wall_cap_hit"] is False
    assert quiet.info["work"]["used"] == pytest.approx(0.05, rel=0.1)
    assert quiet.bound < quiet.objective  # FEASIBLE: the gap is still open
    # same plan, objective and bound with three busy threads beside it
    assert busy.selected == quiet.selected
    assert (busy.objective, busy.bound) == (quiet.objective, quiet.bound)
    assert np.all(inst.by_candidate[list(busy.selected)].sum(axis=0) >= 1)  # still a cover


def test_enough_work_proves_the_optimum_the_wall_clock_solve_proves() -> None:
    inst = random_cover(5, n_cand=60, n_targ=80, density=0.06)
    plain = solve(inst, MilpOptions(overlap=None, time_limit_s=60.0))
    worked = solve(inst, MilpOptions(overlap=None, time_limit_s=60.0, work_limit=60.0))
    assert plain.status is worked.status is Status.OPTIMAL
    assert worked.objective == plain.objective


@pytest.mark.parametrize("kw", [{"backend": "scip"}, {"threads": 2}, {"work_limit": 0.0}])
def test_work_limit_needs_cpsat_one_thread_and_a_positive_value(kw: dict) -> None:
    with pytest.raises(UsageError, match=r"work.limit"):  # the combination, or the value (work_limit = 0)
        MilpOptions(**{"work_limit": 1.0, **kw})
