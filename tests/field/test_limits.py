"""The field sheet's limits count work (routing solutions, branch-and-bound nodes): no wall clock unless the user
sets a cap, and a cap that cuts the search is said."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from planner.core.errors import UsageError
from planner.field.order import solve_order
from planner.field.run import FieldOptions


def _points(n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    p = rng.random((n, 2)) * 10 * np.sqrt(n)
    return np.hypot(*(p[:, None] - p[None]).transpose(2, 0, 1))


def _burn(stop: threading.Event) -> None:
    x = 0
    while not stop.is_set():
        x = (x * 31 + 7) % 1_000_003


def test_the_default_sheet_has_no_wall_clock_cap() -> None:
    assert FieldOptions().time_cap_s is None
    with pytest.raises(UsageError, match="seconds"):
        FieldOptions(time_cap_s=0.0)


def _same_order_quiet_and_busy(n: int, solutions: int) -> None:
    """Route ``n`` random points under a solution limit, then again with three busy threads beside it: the same
    order and length, and no cap said (none is set)."""
    d = _points(n)
    quiet = solve_order(d, solution_limit=solutions)
    stop = threading.Event()
    burners = [threading.Thread(target=_burn, args=(stop,)) for _ in range(3)]
    for t in burners:
        t.start()
    try:
        busy = solve_order(d, solution_limit=solutions)
    finally:
        stop.set()
        for t in burners:
            t.join()
    assert not quiet.capped and not busy.capped
    assert busy.order == quiet.order and busy.length_m == quiet.length_m


def test_a_short_order_is_the_same_on_a_busy_machine() -> None:
    _same_order_quiet_and_busy(20, 100)


@pytest.mark.slow
def test_the_order_is_the_same_on_a_busy_machine() -> None:
    # 40 points and 300 solutions: 4-6 s on 2 cores with the busy threads taking the interpreter's lock
    _same_order_quiet_and_busy(40, 300)


def test_a_cap_that_cuts_the_routing_is_said() -> None:
    capped = solve_order(_points(120, seed=1), solution_limit=10**9, time_cap_s=0.2)
    assert capped.capped
