"""Chvatal's greedy set cover on the coverage matrix, and the greedy under the registration rule."""

from __future__ import annotations

import time
from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp

from planner.core.errors import ArgumentTypeError, InputError, UsageError
from planner.coverage.overlap import OverlapRule, overlap_adjacency
from planner.solve.connectivity import connected_greedy
from planner.solve.instance import CoverInstance
from planner.solve.result import SolveResult, Status


def greedy_cover(
    by_candidate: sp.csr_matrix,
    must_cover: np.ndarray | None = None,
    weights: Sequence[float] | np.ndarray | None = None,
) -> SolveResult:
    """Greedy set cover: repeatedly take the candidate with the lowest cost per newly covered target; ``feasible`` with
    the chosen candidates in the order taken, or ``infeasible`` when a target in ``must_cover`` (default: every target
    some candidate sees) is seen by no candidate. ``weights``: cost per candidate (default 1: fewest stations). Ties go
    to the lowest candidate index, so the pool order (closed form first) decides them. Invariant: after each step
    ``uncovered`` holds exactly the targets no chosen candidate sees. Each step costs one sparse product, O(nnz); at
    most min(C, T) steps. The cover is within H(max set size) <= 1 + ln T of the optimum (Chvatal, "A greedy heuristic
    for the set-covering problem", Math. Oper. Res. 4(3):233-235, 1979).
    """
    start = time.perf_counter()
    if not sp.issparse(by_candidate):
        raise ArgumentTypeError(
            "must be a scipy.sparse matrix, candidates x targets (e.g. problem.by_candidate)",
            field="by_candidate",
            value=type(by_candidate).__name__,
        )
    n_cand, n_targ = by_candidate.shape
    a = by_candidate.astype(np.int64)
    seen = np.asarray(a.sum(axis=0)).ravel() > 0
    if must_cover is not None and np.shape(must_cover) != (n_targ,):
        raise UsageError(f"needs one flag per target ({n_targ})", field="must_cover", value=np.shape(must_cover))
    uncovered = seen.copy() if must_cover is None else np.asarray(must_cover, dtype=bool).copy()
    if np.any(uncovered & ~seen):
        unseen = np.flatnonzero(uncovered & ~seen).tolist()
        return SolveResult.no_plan("greedy", Status.INFEASIBLE, start, info={"unseen_targets": unseen})
    w = np.ones(n_cand) if weights is None else np.asarray(weights, dtype=float)
    if w.shape != (n_cand,) or not (np.all(np.isfinite(w)) and np.all(w > 0)):  # 0 or -1 gave "0 stations"
        raise InputError(
            f"needs {n_cand} finite costs > 0",
            field="weights",
            value=w.shape if w.shape != (n_cand,) else float(w[~(np.isfinite(w) & (w > 0))][0]),
        )
    chosen: list[int] = []
    taken = np.zeros(n_cand, dtype=bool)
    while uncovered.any():
        gain = a @ uncovered.astype(np.int64)
        gain[taken] = 0
        score = np.where(gain > 0, gain / w, -np.inf)
        best = int(np.argmax(score))  # first index among ties
        chosen.append(best)
        taken[best] = True
        uncovered[a.indices[a.indptr[best] : a.indptr[best + 1]]] = False
    return SolveResult.timed("greedy", Status.FEASIBLE, chosen, float(w[chosen].sum()), start)


def connected_greedy_plan(instance: CoverInstance, rule: OverlapRule, starts: int = 50) -> SolveResult:
    """Greedy under the registration rule: a cover whose every registration group is one bundle connected under
    ``rule`` (the baseline the MILP is compared against; :func:`planner.solve.bundles.bundle_cover`). Without groups in
    ``instance``, the plain greedy. ``starts``: seeds tried per group when re-growing its bundle (0: the first pass,
    pruned, only). ``infeasible`` when the greedy finds no connected choice that covers every target."""
    start = time.perf_counter()
    a = instance.by_candidate.astype(bool).tocsr()
    if instance.groups is None:
        return greedy_cover(a, weights=instance.cost)
    adj, _ = overlap_adjacency(a, instance.lengths_m, rule, instance.groups, instance.xy, instance.links)
    need = np.asarray(a.sum(axis=0)).ravel() > 0
    chosen = connected_greedy(a, adj, instance.groups, instance.cost, need, starts)
    info = {"connected": True, "starts": starts}
    if chosen is None:
        return SolveResult.no_plan("greedy", Status.INFEASIBLE, start, info=info)
    return SolveResult.timed("greedy", Status.FEASIBLE, chosen, float(instance.cost[chosen].sum()), start, info=info)
