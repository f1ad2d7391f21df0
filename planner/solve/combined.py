"""Combined precision (``--precision combined``): the views of a piece add information.

A piece t is accepted when sum_j (sigma_req / e_tj)^2 >= 1 over the chosen stations j that see it, e_tj = e(S, theta)
of :func:`planner.instrument.accuracy.view_error_m` at the worst slant range and incidence over the piece: the
combined error 1 / sqrt(sum 1 / e_tj^2) is then at most sigma_req. The MILP holds these as rows; here are the same
weights for the greedy and for verification, so that every method and every check judges a piece the same way.
"""

from __future__ import annotations

import heapq
import time

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.core.errors import InfeasibleError
from planner.coverage.matrix import CoverageProblem
from planner.coverage.visibility import PrecisionRule
from planner.instrument.accuracy import view_error_m
from planner.solve.result import SolveResult, Status

#: information short of 1 by less than this counts as met (floating-point sums)
INFO_TOL = 1e-9


def information(problem: CoverageProblem, rule: PrecisionRule) -> sp.csr_matrix:
    """C x T weights (sigma_req / e_tj)^2 on the pattern of ``problem.by_candidate``."""
    slant = problem.slant_m.tocsr()
    inc = problem.incidence_deg.tocsr()
    e = view_error_m(slant.data, inc.data, rule.scanner, rule.budget, rule.incidence_model)
    return sp.csr_matrix(((rule.sigma_req_m / e) ** 2, slant.indices, slant.indptr), shape=slant.shape)


def information_met(info: sp.csr_matrix, selected: list[int] | tuple[int, ...]) -> NDArray[np.bool_]:
    """Per target: the chosen rows' information sums to at least 1."""
    if len(selected) == 0:
        return np.zeros(info.shape[1], dtype=bool)
    total = np.asarray(info[list(selected)].sum(axis=0)).ravel()
    return total >= 1.0 - INFO_TOL


def combined_greedy(problem: CoverageProblem, rule: PrecisionRule) -> SolveResult:
    """Greedy for combined precision: repeatedly take the candidate adding the most capped information sum_t min(w_jt,
    need_t) until every piece's need (1 at the start) is met. Lazy evaluation: a candidate's gain only falls as needs
    are met, so a stale heap entry is re-scored, never trusted. Ties go to the lower index (the pool's order).
    :class:`InfeasibleError` when even all candidates together give some piece less than the needed information."""
    start = time.perf_counter()
    info = information(problem, rule)
    short = np.flatnonzero(np.asarray(info.sum(axis=0)).ravel() < 1.0 - INFO_TOL)
    if short.size:
        t = problem.targets
        shown = "; ".join(t.label(i) for i in short[:5])
        raise InfeasibleError(
            f"{short.size} target(s) where all candidates together miss sigma_req "
            f"{rule.sigma_req_m * 1000:g} mm in combined precision: {shown}"
        )
    need = np.ones(info.shape[1])

    def gain(j: int) -> float:
        lo, hi = info.indptr[j], info.indptr[j + 1]
        return float(np.minimum(info.data[lo:hi], need[info.indices[lo:hi]]).sum())

    heap = [(-gain(j), j) for j in range(info.shape[0])]
    heapq.heapify(heap)
    chosen: list[int] = []
    while need.max(initial=0.0) > INFO_TOL and heap:
        g, j = heapq.heappop(heap)
        fresh = gain(j)
        if fresh <= 0.0:
            continue
        if heap and fresh < -heap[0][0] - 1e-12:
            heapq.heappush(heap, (-fresh, j))
            continue
        chosen.append(j)
        lo, hi = info.indptr[j], info.indptr[j + 1]
        cols = info.indices[lo:hi]
        need[cols] = np.maximum(need[cols] - info.data[lo:hi], 0.0)
    status = Status.FEASIBLE if need.max(initial=0.0) <= INFO_TOL else Status.INCOMPLETE
    return SolveResult.timed("greedy", status, chosen, float(len(chosen)), start, info={"precision": "combined"})
