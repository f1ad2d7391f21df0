"""The start of a plain block of the MILP: CFT's cover, shrunk by the plain local search, where it beats the greedy.

A block with no registration groups (``--no-overlap``; unit costs, k = 1, single precision) is a plain set cover,
from whose greedy start CP-SAT's work limit may end far above the optimum on a large block. :func:`plain_start` gives
it the start the large-site path uses (:func:`planner.tiles.search.plain_plan`): CFT's cover
(:func:`planner.solve.cft.cft_cover`) searched by :func:`planner.solve.local_search.shrink` with no links, taken when
it is smaller than the greedy's. A block of fewer than :data:`MIN_TARGETS` targets, or whose greedy cover already
meets the cover LP's bound (rounded up), keeps its greedy start. Every step stops on counts (CFT's own iteration rules,
``MilpOptions.plain_start_moves`` moves per target) and the seed, never on the clock: the same block gives the same
start under any load.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from planner.solve.cft import cft_cover
from planner.solve.local_search import shrink, unlinked

if TYPE_CHECKING:
    from planner.solve.milp import MilpOptions

#: moves of the search per target of the block unless ``MilpOptions.plain_start_moves`` says otherwise: the tiled
#: plan's :data:`planner.plan.strategy.MOVES_PER_PIECE` (a test keeps them equal; the solvers may not import the plan)
MOVES_PER_TARGET = 10.0
#: blocks with fewer targets keep their greedy start (the greedy of a handful of targets is near its optimum, and the
#: MILP proves it at once)
MIN_TARGETS = 20


@dataclass(frozen=True, kw_only=True)
class PlainStart:
    """``selected``: the smallest cover met (the greedy's when nothing beat it); ``greedy``, ``cft``, ``searched``:
    stations of the greedy cover, CFT's (None: not run, the greedy met the bound) and the searched one; the bounds in
    cost units."""

    selected: tuple[int, ...]
    greedy: int
    lp_bound: float
    cft: int | None = None
    cft_bound: float = 0.0
    searched: int | None = None
    moves: int = 0

    @property
    def bound(self) -> float:
        """The better of the two lower bounds."""
        return max(self.lp_bound, self.cft_bound)


def plain_start(
    a: sp.csr_matrix,
    cost: np.ndarray,
    groups: list | None,
    incumbent: list[int] | None,
    o: MilpOptions,
    deadline: float = math.inf,
) -> PlainStart | None:
    """The start of a plain block (module docstring), or None where it does not apply: registration groups, the start
    off, k > 1, combined precision, costs not all equal, no greedy cover, a block of fewer than :data:`MIN_TARGETS`
    targets, or a greedy cover of one station. ``incumbent``: the block's greedy cover (rows of ``a``); ``deadline``:
    the user's wall-clock cap as a ``time.perf_counter()`` instant, where CFT and the search stop.
    """
    n_cand, n_targ = a.shape
    if (
        groups is not None
        or not o.plain_start
        or o.k != 1
        or o.precision != "single"
        or incumbent is None
        or len(incumbent) <= 1
        or n_targ < MIN_TARGETS
        or np.ptp(cost) > 0
    ):
        return None
    unit = float(cost[0])
    lp = linprog(np.ones(n_cand), A_ub=-a.T.astype(np.float64), b_ub=-np.ones(n_targ), method="highs")
    lp_bound = float(lp.fun) if lp.status == 0 else 0.0
    greedy = tuple(sorted(int(i) for i in incumbent))
    if len(greedy) <= math.ceil(lp_bound - 1e-6):  # the greedy cover is optimal already
        return PlainStart(selected=greedy, greedy=len(greedy), lp_bound=unit * lp_bound)
    left = deadline - time.perf_counter()
    if left <= 0:
        return None
    cft = cft_cover(a, seed=o.seed, time_cap_s=left if math.isfinite(left) else None)
    floor = math.ceil(max(lp_bound, cft.lower_bound) - 1e-6)
    moves = 0 if o.local_search_moves == 0 else round(o.plain_start_moves * n_targ)
    found, made = cft.selected, 0
    if moves > 0 and len(found) > floor:
        alone, groups_of = unlinked(n_cand)
        searched = shrink(a, alone, groups_of, found, moves, floor, seed=o.seed, deadline=deadline)
        found, made = searched.selected, searched.moves
    return PlainStart(
        selected=found if len(found) < len(greedy) else greedy,
        greedy=len(greedy),
        lp_bound=unit * lp_bound,
        cft=len(cft.selected),
        cft_bound=unit * max(0.0, cft.lower_bound),  # CFT reports -FLT_MAX where it proved nothing
        searched=len(found),
        moves=made,
    )


def plain_record(starts: list[PlainStart]) -> dict[str, int]:
    """What the plain starts of a solve did, summed over the blocks, for plan.json."""
    return {
        "blocks": len(starts),
        "cft_blocks": sum(s.cft is not None for s in starts),
        "greedy": sum(s.greedy for s in starts),
        "start": sum(len(s.selected) for s in starts),
        "moves": sum(s.moves for s in starts),
    }
