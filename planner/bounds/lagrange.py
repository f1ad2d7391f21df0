"""A lower bound on the plain cover by Lagrangian decomposition over tiles.

The targets are partitioned into parts ``T_1 .. T_m`` (the tiles' cores, or groups of them). A candidate ``j`` that sees
pieces of several parts ``I(j)`` has its cost split, ``c_j = sum_{i in I(j)} lam_ij``. Any cover ``x`` then costs
``sum_i sum_j lam_ij x_j >= sum_i OPT_i(lam_i)``, where ``OPT_i`` is the cheapest cover of ``T_i`` alone with the costs
``lam_i``: each part's share of ``x`` covers that part. So ``L(lam) = sum_i OPT_i(lam_i)`` bounds every cover from
below, for any split, and so every connected plan too; it stays valid with each ``OPT_i`` replaced by a proven lower
bound of it.

What is computed:

- costs are scaled by ``scale`` and floored to integers ``w_ij <= scale * lam_ij`` for CP-SAT; then ``sum_i w_ij <=
  scale * c_j``, so ``sum_i LB_i(w_i) / scale`` is still a bound (flooring never overestimates);
- the first split comes from the whole-cover LP's duals ``y``: ``lam_ij`` = the duals of ``T_i``'s pieces that ``j``
  sees, plus an equal share of ``j``'s reduced cost. ``y`` restricted to ``T_i`` is dual feasible for part ``i``, so
  ``L`` of this split is at least the LP value (less the flooring);
- then projected subgradient steps: ``g_ij = x_ij - mean_{i' in I(j)} x_i'j`` (``x_i`` the part's best cover), which
  keeps ``sum_i lam_ij = c_j``; the step is Polyak's, towards the cheapest cover made so far as the union of the parts'
  covers, halved whenever ``L`` does not improve. The best ``L`` is kept.

Each part's bound is the larger of its LP floor (the part's LP by HiGHS, made a proven bound by weak duality) and
CP-SAT's (one worker, stopped on deterministic work, so the bound does not depend on the machine's load). CP-SAT gets a
quarter of the part's work first and the whole of it only where that leaves its best cover near the bound: on the 16-ha
plant the parts it does not close end at their LP exactly, so their work buys nothing the floor does not give. The parts
are independent and run as :func:`planner.tiles.engine.run_tasks` jobs (serially, or on a Dask client).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import linprog

from planner.core.errors import InfeasibleError, InternalError, UsageError
from planner.solve.greedy import greedy_cover
from planner.solve.milp import WALL_CAP
from planner.solve.presolve import dominated, implied_targets


@dataclass(frozen=True)
class PartJob:
    """One part's cover: ``a`` (its candidates x its kept pieces, bool), integer costs ``w``, a start."""

    a: sp.csr_matrix
    w: NDArray[np.int64]
    hint: NDArray[np.bool_] | None


@dataclass(frozen=True, kw_only=True)
class PartResult:
    """A part's answer in scaled units: ``lower`` (proven), ``objective`` of ``chosen`` (its best cover)."""

    lower: int
    objective: int
    chosen: NDArray[np.bool_]
    optimal: bool
    capped: bool = False


@dataclass(frozen=True, kw_only=True)
class LagrangeBound:
    """The best bound found: ``value`` (rounded up when the costs are integers), ``per_tile`` (each part's bound at the
    best split, original units), ``proven`` (the parts solved to optimality there), ``upper`` (cheapest union of the
    parts' covers, pruned: a cover of the whole), ``capped`` (part solves stopped by the wall-clock cap, not the work
    limit: then, and only then, the bound may depend on the load)."""

    value: float
    raw: float
    lp: float
    iterations: int
    per_tile: tuple[float, ...]
    proven: tuple[bool, ...]
    upper: float
    time_s: float
    capped: int = 0

    @property
    def optimal(self) -> bool:
        """Every part proven optimal at the best split (else some part gave CP-SAT's bound only)."""
        return all(self.proven)


#: how the parts of one step are solved: ``runner(solve_part, jobs, shared)`` -> ``solve_part(**shared, job=job)`` for
#: each job, in job order (the tiles pass their Dask task runner; None: one after the other in this process)
PartRunner = Callable[[Callable[..., PartResult], list[PartJob], dict[str, Any]], list[PartResult]]


#: share of a part's work spent before deciding whether the rest of it can close the part
FIRST_SHARE = 0.25
#: a part gets the rest of its work only where its best cover after the first share is within this fraction of its
#: proven lower bound (on the plants CP-SAT's bound of a part that it does not close stays at the part's LP: its work
#: there buys nothing the LP floor does not give)
CLOSE_GAP = 0.10


def solve_part(job: PartJob, work_s: float, seed: int = 0) -> PartResult:
    """The cheapest cover of one part: its LP floor (:func:`_lp_floor`), then CP-SAT (one worker) for
    ``FIRST_SHARE * work_s`` deterministic seconds, and, where that leaves the best cover within ``CLOSE_GAP`` of the
    proven bound, once more for ``work_s`` from the same start (the run CP-SAT alone would make: started from the
    first run's cover its search differs, and on the 16-ha plant it then lost a proof it makes from the same start);
    a wall cap ``WALL_CAP`` times each limit where one is set.
    ``lower`` is the larger of the LP floor and CP-SAT's best bound, the objective when proven optimal. When CP-SAT finds
    no cover, the part's cover is Chvatal's greedy (:func:`_greedy_part`). Every piece of work is a count, not a time,
    so the answer does not depend on the load. :class:`InfeasibleError` when a piece of the part is seen by none of its
    candidates."""
    free, keep, rows = _reduce(job.a, job.w)
    cols = np.flatnonzero(keep)
    at = job.a[cols][:, rows].T.tocsr()
    if np.any(np.diff(at.indptr) == 0):
        raise InfeasibleError("a piece of this part is seen by none of its candidates", field="lagrange part")
    w, paid = job.w[cols], int(job.w[free].sum())
    floor = paid + _lp_floor(at, w)
    hint = None if job.hint is None else job.hint[cols]
    first = _cp_sat(at, w, hint, FIRST_SHARE * work_s, seed, cols)
    runs = [first]
    if first.chosen is not None and not first.optimal:
        cost, lower = paid + int(w[first.chosen].sum()), max(floor, paid + first.lower)
        if cost - lower <= CLOSE_GAP * cost:  # near: the rest of the work may prove it
            runs.append(_cp_sat(at, w, hint, work_s, seed, cols))  # from the same start: see solve_part
    lower = max([floor] + [paid + r.lower for r in runs])
    covers = [r.chosen for r in runs if r.chosen is not None]
    chosen = free.copy()
    # no cover within the work: Chvatal's greedy
    chosen[cols] = min(covers, key=lambda c: int(w[c].sum())) if covers else _greedy_part(at.T.tocsr(), w)
    objective = int(job.w[chosen].sum())
    optimal = any(r.optimal for r in runs) or lower >= objective
    capped = any(r.capped for r in runs) and not optimal
    return PartResult(lower=min(lower, objective), objective=objective, chosen=chosen, optimal=optimal, capped=capped)


@dataclass(frozen=True, kw_only=True)
class _Run:
    """One CP-SAT run on a part: its best cover (None: none found), proven bound, whether optimal, whether the wall
    cap stopped it."""

    chosen: NDArray[np.bool_] | None
    lower: int
    optimal: bool
    capped: bool


def _cp_sat(
    at: sp.csr_matrix,
    w: NDArray[np.int64],
    hint: NDArray[np.bool_] | None,
    work_s: float,
    seed: int,
    names: NDArray[np.int64],
) -> _Run:
    """CP-SAT on the cover of the rows of ``at`` (pieces x candidates) at costs ``w`` >= 0, one worker, ``work_s``
    deterministic seconds; its proven bound is 0 where none is finite (the costs are >= 0). ``names``: the candidates'
    numbers in the part, the variables' names."""
    from ortools.sat.python import cp_model

    model = cp_model.CpModel()
    x = [model.NewBoolVar(f"x{j}") for j in names]
    for t in range(at.shape[0]):
        model.AddBoolOr([x[j] for j in at.indices[at.indptr[t] : at.indptr[t + 1]]])
    model.Minimize(sum(int(c) * v for c, v in zip(w, x)))
    if hint is not None:
        for v, h in zip(x, hint):
            model.AddHint(v, bool(h))
    solver = cp_model.CpSolver()
    solver.parameters.num_workers = 1
    solver.parameters.random_seed = seed
    solver.parameters.linearization_level = 2
    solver.parameters.max_deterministic_time = work_s
    if WALL_CAP is not None:
        solver.parameters.max_time_in_seconds = WALL_CAP * work_s
    status = solver.Solve(model)
    if status == cp_model.INFEASIBLE:
        raise InfeasibleError("a piece of this part is seen by none of its candidates", field="lagrange part")
    if status == cp_model.MODEL_INVALID:
        raise InternalError(f"CP-SAT rejected a part: {solver.StatusName(status)}", field="lagrange part")
    chosen = None
    if status in (cp_model.OPTIMAL, cp_model.FEASIBLE):
        chosen = np.array([bool(solver.Value(v)) for v in x], dtype=bool)
    optimal = status == cp_model.OPTIMAL
    bound = solver.BestObjectiveBound()
    lower = int(w[chosen].sum()) if optimal and chosen is not None else _up_int(bound)
    capped = WALL_CAP is not None and not optimal and solver.wall_time >= 0.99 * WALL_CAP * work_s
    return _Run(chosen=chosen, lower=lower, optimal=optimal, capped=capped)


def _up_int(bound: float) -> int:
    """A finite bound rounded up (the costs are integers), 0 where it is not finite (the costs are >= 0)."""
    return max(0, math.ceil(bound - 1e-9)) if math.isfinite(bound) else 0


def _lp_floor(at: sp.csr_matrix, w: NDArray[np.int64]) -> int:
    """A proven lower bound on the cheapest cover of the rows of ``at`` (pieces x candidates) at integer costs ``w`` >=
    0, from its LP's duals ``y >= 0`` (HiGHS): every 0/1 cover costs at least ``sum(y) - sum_j max(0, (A y)_j - w_j)``
    (weak duality with ``x <= 1``, so it holds for any ``y >= 0``, whatever the LP solver's tolerances), rounded up as
    the costs are integers. 0 where the LP fails (still a bound)."""
    if at.shape[0] == 0:
        return 0
    res = linprog(
        w.astype(np.float64),
        A_ub=-at.astype(np.float64),
        b_ub=-np.ones(at.shape[0]),
        bounds=(0, None),
        method="highs",
    )
    if res.status != 0:
        return 0
    y = np.maximum(-np.asarray(res.ineqlin.marginals, dtype=np.float64), 0.0)
    excess = np.maximum(at.T.astype(np.float64) @ y - w, 0.0)
    return max(0, math.ceil(float(y.sum()) - float(excess.sum()) - 1e-3))


def _reduce(a: sp.csr_matrix, w: NDArray[np.int64]) -> tuple[NDArray[np.bool_], NDArray[np.bool_], NDArray[np.int64]]:
    """Candidates of negative cost (in every optimal cover, so taken), the rest that no other of them can replace at no
    more cost (:func:`planner.solve.presolve.dominated`, sound for costs >= 0), and the pieces the taken ones leave
    uncovered. The part's optimum is unchanged."""
    free = w < 0
    rows = np.flatnonzero(np.asarray(a[free].sum(axis=0)).ravel() == 0)
    rest = np.flatnonzero(~free)
    keep = np.zeros(len(w), dtype=bool)
    keep[rest[~dominated(a[rest][:, rows].tocsr(), w[rest].astype(float))]] = True
    return free, keep, rows


def _greedy_part(a: sp.csr_matrix, w: NDArray[np.int64]) -> NDArray[np.bool_]:
    """A cover of every column of ``a`` (candidates x pieces) at costs ``w`` >= 0: the free candidates, then Chvatal's
    greedy (:func:`planner.solve.greedy.greedy_cover`) on the pieces they leave."""
    take = w == 0
    open_ = a[take].getnnz(axis=0) == 0
    paid = np.flatnonzero(~take)
    if open_.any():
        res = greedy_cover(a[paid].tocsr(), must_cover=open_, weights=w[paid].astype(float))
        if res.status.value == "infeasible":
            raise InfeasibleError("a piece of this part is seen by none of its candidates", field="lagrange part")
        take[paid[list(res.selected)]] = True
    return take


def lp_duals(a: sp.csr_matrix, cost: NDArray[np.float64]) -> tuple[float, NDArray[np.float64]]:
    """Value and target duals ``y >= 0`` of min c x, A^T x >= 1, x >= 0 (HiGHS interior point with crossover: far faster
    than the dual simplex on a large site's whole cover, docs/benchmarks/setcover.md)."""
    res = linprog(
        cost, A_ub=-a.T.astype(np.float64).tocsr(), b_ub=-np.ones(a.shape[1]), bounds=(0, None), method="highs-ipm"
    )
    if res.status != 0:
        raise InfeasibleError(f"cover LP failed: {res.message}", field="lagrange")
    return float(res.fun), np.maximum(-np.asarray(res.ineqlin.marginals, dtype=float), 0.0)


def _check_parts(n_targets: int, parts: Sequence[NDArray[np.int64]]) -> NDArray[np.int64]:
    part_of = np.full(n_targets, -1, dtype=np.int64)
    for i, p in enumerate(parts):
        if np.any(part_of[p] >= 0):
            raise UsageError("a piece is in two parts", field="parts", value=i)
        part_of[p] = i
    if np.any(part_of < 0):
        raise UsageError("every piece must be in one part", field="parts", value=int(np.sum(part_of < 0)))
    return part_of


def split_costs(
    a: sp.csr_matrix, parts: Sequence[NDArray[np.int64]], cost: NDArray[np.float64], y: NDArray[np.float64] | None
) -> tuple[list[NDArray[np.int64]], list[NDArray[np.float64]]]:
    """Per part, its candidates (those seeing one of its pieces) and their shares ``lam_i``: from the duals ``y`` plus
    an equal share of the reduced cost (module docstring); an equal split when ``y`` is None."""
    n = a.shape[1]
    member = sp.csr_matrix((np.ones(n), (np.arange(n), _check_parts(n, parts))), shape=(n, len(parts)))
    seen = (sp.csr_matrix((np.ones(a.nnz), a.indices, a.indptr), shape=a.shape) @ member > 0).tocsc()
    dual = (a.astype(np.float64) @ sp.diags(y if y is not None else np.zeros(n)) @ member).tocsc()
    count = np.asarray(seen.sum(axis=1)).ravel()
    reduced = cost - np.asarray(dual.sum(axis=1)).ravel()
    share = np.divide(reduced, count, out=np.zeros_like(reduced), where=count > 0)
    cands, lams = [], []
    for i in range(len(parts)):
        js = seen.indices[seen.indptr[i] : seen.indptr[i + 1]].astype(np.int64)
        cands.append(js)
        lams.append(np.asarray(dual[js, i].todense()).ravel() + share[js])
    return cands, lams


def lagrangian_bound(
    a: sp.csr_matrix,
    parts: Sequence[NDArray[np.int64]],
    cost: NDArray[np.float64] | None = None,
    iterations: int = 0,
    work_s: float = 10.0,
    scale: int = 100_000,
    start: str = "lp",
    seed: int = 0,
    upper: float | None = None,
    mu: float = 0.25,
    runner: PartRunner | None = None,
) -> LagrangeBound:
    """The Lagrangian bound of the cover ``a`` (candidates x pieces, each piece seen by some candidate) over the target
    partition ``parts`` (the piece indices of each part, each piece in exactly one); its ``value`` never exceeds the
    cheapest cover of ``a``. ``cost``: >= 0 (default 1 each). ``iterations``: subgradient steps after the first split.
    ``work_s``: CP-SAT deterministic seconds per part and step. ``start``: ``"lp"``, the LP-dual split, or ``"equal"``,
    ``c_j / |I(j)|``. ``upper``: the cost of a known cover, which the step aims at (default: the best union of the
    parts' covers). ``mu``: the first step factor, halved when a step does not raise the bound."""
    if start not in ("lp", "equal") or iterations < 0 or not work_s > 0 or scale < 1:
        raise UsageError(
            "start must be lp or equal, iterations >= 0, work_s > 0, scale >= 1", field="lagrange", value=start
        )
    t0 = time.perf_counter()
    a = a.astype(bool).tocsr()
    c = np.ones(a.shape[0]) if cost is None else np.asarray(cost, dtype=float)
    lp, y = lp_duals(a, c)
    cands, lams = split_costs(a, parts, c, y if start == "lp" else None)
    subs = [_part_matrix(a, js, p) for js, p in zip(cands, parts)]
    best, upper = -math.inf, math.inf if upper is None else upper
    best_opt: tuple[bool, ...] = ()
    best_parts: tuple[float, ...] = ()
    hints: list[NDArray[np.bool_] | None] = [None] * len(parts)
    done = capped = 0
    for k in range(iterations + 1):
        jobs = [PartJob(s, np.floor(lam * scale).astype(np.int64), h) for s, lam, h in zip(subs, lams, hints)]
        shared: dict[str, Any] = {"work_s": work_s, "seed": seed}
        res = runner(solve_part, jobs, shared) if runner else [solve_part(**shared, job=j) for j in jobs]
        done, capped = k, capped + sum(r.capped for r in res)
        value = sum(r.lower for r in res) / scale
        upper = min(upper, _union_cost(a, c, cands, res))
        if value > best + 1e-12:
            best, best_parts, best_opt = value, tuple(r.lower / scale for r in res), tuple(r.optimal for r in res)
        else:
            mu /= 2
        hints = [r.chosen for r in res]
        g = _subgradient(a.shape[0], cands, res)
        norm = sum(float(gi @ gi) for gi in g)
        if k == iterations or norm == 0 or upper - value <= 1e-9:
            break
        step = mu * (upper - value) / norm
        lams = [lam + step * gi for lam, gi in zip(lams, g)]
    integral = bool(np.all(c == np.round(c)))
    return LagrangeBound(
        value=math.ceil(best - 1e-6) if integral else best,
        raw=best,
        lp=lp,
        iterations=done,
        per_tile=best_parts,
        proven=best_opt,
        upper=upper,
        time_s=time.perf_counter() - t0,
        capped=capped,
    )


def _part_matrix(a: sp.csr_matrix, js: NDArray[np.int64], part: NDArray[np.int64]) -> sp.csr_matrix:
    """The part's candidates ``js`` by its pieces, less the pieces another of them implies."""
    sub = a[js][:, part].tocsc()
    return sub[:, ~implied_targets(sub.T.tocsr())].tocsr()


def _union_cost(
    a: sp.csr_matrix, c: NDArray[np.float64], cands: list[NDArray[np.int64]], res: list[PartResult]
) -> float:
    """The cost of the union of the parts' covers (a cover of the whole) less the stations no piece needs, dropped in
    order of fewest pieces seen."""
    x = np.zeros(a.shape[0], dtype=bool)
    for js, r in zip(cands, res):
        x[js[r.chosen]] = True
    count = np.asarray(a[x].astype(np.int64).sum(axis=0)).ravel()
    sizes = np.diff(a.indptr)
    for j in sorted(np.flatnonzero(x), key=lambda j: (sizes[j], j)):
        seen = a.indices[a.indptr[j] : a.indptr[j + 1]]
        if np.all(count[seen] >= 2):
            x[j] = False
            count[seen] -= 1
    return float(c[x].sum())


def group_parts(
    cells: Sequence[tuple[int, int]], parts: Sequence[NDArray[np.int64]], group: int
) -> list[NDArray[np.int64]]:
    """The tiles' pieces ``parts`` (tile ``k`` at row and column ``cells[k]``) joined ``group`` x ``group`` tiles at a
    time (fewer, larger parts: a stronger bound, harder parts), in order of the first tile."""
    if group < 1:
        raise UsageError("must be >= 1", field="lagrange_group", value=group)
    merged: dict[tuple[int, int], list[NDArray[np.int64]]] = {}
    for (r, c), p in zip(cells, parts):
        merged.setdefault((r // group, c // group), []).append(np.asarray(p, dtype=np.int64))
    return [np.sort(np.concatenate(ps)) for ps in merged.values()]


def _subgradient(n: int, cands: list[NDArray[np.int64]], res: list[PartResult]) -> list[NDArray[np.float64]]:
    """``x_ij - mean over I(j)`` per part: moves cost between parts and keeps every ``sum_i lam_ij``."""
    total, count = np.zeros(n), np.zeros(n)
    for js, r in zip(cands, res):
        total[js] += r.chosen
        count[js] += 1
    mean = np.divide(total, count, out=np.zeros(n), where=count > 0)
    return [r.chosen.astype(float) - mean[js] for js, r in zip(cands, res)]
