"""The rest solved (:func:`solve_rest`) with the planner's own MILP (:func:`planner.solve.milp.solve`): the done
stations are forced into the plan by a column of no wall length that only each of them covers (the presolve fixes
them), at the cost of one station each, which the count and the bound of the rest then leave out; the overlap
relation is the rest's (:class:`planner.replanning.rest.RestProblem`), formed once over its rows. Warm from the
previous plan: its stations that survive the edits, with the done ones, are a plan of the rest wherever they still
cover every piece and register as one network (their redundant stations dropped); the re-plan is never larger."""

from __future__ import annotations

import math
from collections.abc import Hashable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components, dijkstra

from planner.coverage.matrix import CoverageProblem
from planner.plan.methods import with_columns
from planner.plan.problem import Problem
from planner.replanning.narrow import lp_bound, restricted, shortlist
from planner.replanning.rest import RestProblem
from planner.solve.instance import CoverInstance, cover_instance
from planner.solve.milp import MilpOptions, solve
from planner.solve.result import SolveResult, Status

#: CP-SAT work (deterministic seconds) of a re-plan's solve by default: seconds, not the plan's minutes
REPLAN_WORK_S = 0.5
#: the re-plan's connected greedy seeds and rounds of the cut loop: a start and a few rounds, not the plan's search
GREEDY_STARTS = 5
MAX_ROUNDS = 20
#: moves of the solver's local search in a re-plan (the plan's: 500): on the shortlist the repaired plan is its start
LOCAL_SEARCH_MOVES = 100


@dataclass(frozen=True, kw_only=True)
class RestSolution:
    """The rows chosen (the done stations' among them), the solver's result over the whole (done included), the
    rest's count and bound (done left out; the bound over the pool left after the edits, scope ``pool``), and
    what the previous plan gave as a start."""

    selected: tuple[int, ...]
    result: SolveResult
    rest_count: int
    rest_bound: int | None
    warm: str


def rest_instance(
    rest: RestProblem, problem: Problem, every_row: bool = False
) -> tuple[CoverInstance, np.ndarray, np.ndarray]:
    """The MILP's instance of the rest and what its rows and columns are (indices into the rest's rows and the
    targets): the pieces left to cover (neither lost nor seen by a done station), the candidates that see one of
    them and the done stations, each of these forced by a column of its own (``every_row``: every candidate left,
    those that may only join others in one network too)."""
    cov = rest.coverage
    combined = problem.options.milp.precision == "combined"
    k = problem.options.milp.k
    done = np.asarray(rest.done_rows, dtype=np.int64)
    need = np.ones(cov.shape[1], dtype=bool)
    need[list(rest.lost.pieces)] = False
    if not combined:  # a piece the done stations see k times needs nothing more
        need &= np.asarray(cov.by_candidate[done].astype(np.int64).sum(axis=0)).ravel() < k
    cols = np.flatnonzero(need)
    useful = np.diff(cov.by_candidate[:, cols].tocsr().indptr) > 0
    useful[done] = True
    useful |= every_row
    rows = np.flatnonzero(useful)
    p = problem.site.parameters
    sub = _rows_of(cov, rows)
    inst = cover_instance(
        sub,
        scanner=problem.validation.scanner if combined else None,
        budget=p.budget if combined else None,
        sigma_req_m=p.sigma_req_m if combined else None,
        name=problem.site.name,
        groups=[rest.groups[r] for r in rows],
        links=None if rest.links is None else rest.links[rows][:, rows],
        incidence_model=p.incidence_model,
    )
    inst = replace(
        inst,
        by_candidate=inst.by_candidate[:, cols].tocsr(),
        target_length_m=np.asarray(inst.lengths_m)[cols],
        info=None if inst.info is None else inst.info[:, cols].tocsr(),
        relation=None if rest.relation is None else rest.relation[rows][:, rows].tocsr(),
    )
    at = np.searchsorted(rows, done)
    d = len(done)
    force = sp.csr_matrix((np.ones(d, dtype=bool), (at, np.arange(d))), shape=(len(rows), d))
    return with_columns(inst, force), rows, cols


def _rows_of(cov: CoverageProblem, rows: np.ndarray) -> CoverageProblem:
    by = cov.by_candidate[rows]
    return replace(
        cov,
        candidates=tuple(cov.candidates[r] for r in rows),
        by_candidate=by,
        by_target=by.T.tocsr(),
        slant_m=cov.slant_m[rows],
        incidence_deg=cov.incidence_deg[rows],
        excluded={},
    )


def solve_rest(
    rest: RestProblem, problem: Problem, milp: dict[str, Any], work_limit_s: float = REPLAN_WORK_S
) -> RestSolution:
    """Solve the rest under the plan's MILP settings (``milp``: plan.json's ``parameters.milp``) within
    ``work_limit_s`` of CP-SAT work, and take the previous plan's survivors where they are as good."""
    solution = _solve(rest, problem, milp, work_limit_s, False)
    if not solution.selected:  # a network may need candidates that cover nothing left: all of them, then
        solution = _solve(rest, problem, milp, work_limit_s, True)
    return solution


def _solve(
    rest: RestProblem, problem: Problem, milp: dict[str, Any], work_limit_s: float, every_row: bool
) -> RestSolution:
    """:func:`solve_rest` over the candidates that cover something left (``every_row``: over all of them)."""
    inst, rows, cols = rest_instance(rest, problem, every_row)
    options = MilpOptions(
        backend=str(milp.get("backend", "cpsat")),
        seed=int(milp.get("seed", 0)),
        k=int(milp.get("k", 1)),
        precision=str(milp.get("precision", "single")),
        overlap=problem.rule,
        work_limit=work_limit_s,
        time_limit_s=None,
        greedy_starts=GREEDY_STARTS,
        floor_probe=False,
        max_rounds=MAX_ROUNDS,
        local_search_moves=LOCAL_SEARCH_MOVES,
    )
    d = len(rest.done_rows)
    pos = {int(r): i for i, r in enumerate(rows)}
    done = [pos[r] for r in rest.done_rows]
    survivors = [pos[r] for r in rest.plan_rows.values() if r in pos and pos[r] not in set(done)]
    warm_rows = _repair(inst, done, survivors, options.k)
    short = shortlist(inst, [*done, *(warm_rows or survivors)], len(cols))
    result = solve(restricted(inst, short), options)
    chosen = tuple(int(short[i]) for i in result.selected) if result.selected else None
    lp = lp_bound(inst, done, len(cols), options.k)
    whole = len(short) == inst.shape[0]  # the solver's bound holds over the whole pool left
    mip = None if result.bound is None or not whole else max(0, math.ceil(result.bound - 1e-6) - d)
    warm = "the previous plan could not be repaired into a plan of the rest"
    if warm_rows is not None:
        kept = len(set(warm_rows) & set(survivors))
        warm = (
            f"the previous plan repaired: {kept} of its {len(survivors)} surviving stations kept, "
            f"{len(warm_rows) - kept - d} added: {len(warm_rows) - d} for the rest"
        )
        if chosen is None or len(warm_rows) < len(chosen):
            chosen = warm_rows
            warm += " (taken: fewer than the solver's)"
    warm += f"; the solver chose among {len(short):,} of the {inst.shape[0]:,} candidates left"
    if chosen is None:
        return RestSolution(selected=(), result=result, rest_count=0, rest_bound=None, warm=warm)
    count = len(chosen) - d
    bounds = [b for b in (lp, mip) if b is not None]
    bound = min(count, max(bounds)) if bounds else None
    # optimal only where the bound over the whole pool left meets the count (the solver's own proof may be of the
    # shortlist only)
    status = Status.OPTIMAL if bound == count else Status.FEASIBLE
    picked = tuple(sorted(int(rows[i]) for i in chosen))
    result = replace(
        result,
        selected=picked,
        objective=float(len(chosen)),
        bound=None if bound is None else float(bound + d),
        status=status,
    )
    return RestSolution(selected=picked, result=result, rest_count=count, rest_bound=bound, warm=warm)


def _repair(inst: CoverInstance, done: list[int], survivors: list[int], k: int) -> tuple[int, ...] | None:
    """The previous plan repaired: its ``survivors`` with the ``done`` rows, grown by the candidate that covers most
    of what is left among those related to the plan (any candidate where none is) until every column is covered
    ``k`` times, then its redundant stations dropped (last first) while it stays a registered cover; None where
    nothing covers the rest or the result does not register as one network per group."""
    a = inst.by_candidate.astype(np.float64).tocsr()
    sel = sorted(set(done) | set(survivors))
    for _ in range(a.shape[0]):
        count = inst.coverage_count(sel)
        short = count < k
        if not short.any():
            break
        gain = np.asarray(a[:, short].sum(axis=1)).ravel()
        gain[sel] = 0
        if inst.relation is not None and sel:
            near = np.asarray(inst.relation[sel].sum(axis=0)).ravel() > 0
            if (gain * near).max() > 0:
                gain = gain * near
        if gain.max() <= 0:
            return None
        sel.append(int(np.argmax(gain)))
    if inst.relation is not None and inst.groups is not None:
        sel = _connected(inst.relation, inst.groups, sel)
    keep = set(done)
    for r in sorted(set(sel) - keep, reverse=True):
        trial = [s for s in sel if s != r]
        if _feasible(inst, trial, k):
            sel = trial
    return tuple(sorted(sel)) if _feasible(inst, sel, k) else None


def _connected(relation: sp.csr_matrix, groups: Sequence[Hashable], sel: list[int]) -> list[int]:
    """``sel`` with the stations of the shortest relation paths that join each group's parts to its first part
    (through candidates of the same group)."""
    sel = list(sel)
    for _ in range(len(sel)):
        parts = _parts(relation, groups, sel)
        if parts is None:
            return sel
        first, rest = parts
        same = np.array([g == groups[first[0]] for g in groups], dtype=bool)
        keep = sp.diags(same.astype(float))
        graph = (keep @ relation.astype(float) @ keep).tocsr()
        dist, pred, _ = dijkstra(
            graph, directed=False, indices=first, unweighted=True, min_only=True, return_predecessors=True
        )
        target = min(rest, key=lambda r: dist[r])
        if not np.isfinite(dist[target]):
            return sel
        node = int(pred[target])
        while node >= 0 and node not in sel:
            sel.append(node)
            node = int(pred[node])
    return sel


def _parts(relation: sp.csr_matrix, groups: Sequence[Hashable], sel: list[int]) -> tuple[list[int], list[int]] | None:
    """The first disconnected group's first component and its other stations (None: every group is connected)."""
    by: dict[Hashable, list[int]] = {}
    for r in sel:
        by.setdefault(groups[r], []).append(r)
    for rows in by.values():
        n, label = connected_components(relation[rows][:, rows], directed=False)
        if n > 1:
            return [r for r, lab in zip(rows, label) if lab == label[0]], [
                r for r, lab in zip(rows, label) if lab != label[0]
            ]
    return None


def _feasible(inst: CoverInstance, sel: Sequence[int], k: int) -> bool:
    """``sel`` covers every column ``k`` times and registers as one network per group (where a relation is given)."""
    if not sel or np.any(inst.coverage_count(list(sel)) < k):
        return False
    if inst.relation is None or inst.groups is None:
        return True
    return connected_groups(inst.relation, inst.groups, sel)


def connected_groups(relation: sp.csr_matrix, groups: Sequence[Hashable], sel: Sequence[int]) -> bool:
    """Whether the rows ``sel`` of each registration group form one component of ``relation``."""
    by: dict[Hashable, list[int]] = {}
    for r in sel:
        by.setdefault(groups[r], []).append(r)
    for rows in by.values():
        if len(rows) > 1 and connected_components(relation[rows][:, rows], directed=False)[0] > 1:
            return False
    return True
