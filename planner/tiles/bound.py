"""The lower bound of a tiled plan: several bounds of the plain cover over the pool, the largest kept, and which one
decided. Every connected plan is a cover, so any lower bound of the plain set cover over the whole pool bounds the
connected problem too (registration rule dropped). Computed on the whole matrix:

- the LP relaxation (HiGHS interior point; rounded up, an integer count);
- by disjoint sub-areas: where the pieces fall into groups no candidate sees two of (components of the
  candidate-piece graph), the optima add up, and so do the rounded-up LPs of the groups, each at least its share
  of the LP: a bound at least ceil(LP), larger where several groups round up;
- the Lagrangian decomposition over the tiles (:mod:`planner.bounds.lagrange`), optional;
- CFT's Lagrangian bound (:mod:`planner.solve.cft`), where CFT made the whole-site cover;
- the best bound of a time-limited cover MILP (CP-SAT), where one is asked for.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import partial
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog
from scipy.sparse.csgraph import connected_components

from planner.bounds.lagrange import LagrangeBound, lagrangian_bound
from planner.solve.instance import CoverInstance
from planner.solve.milp import WALL_CAP, MilpOptions, solve
from planner.solve.presolve import implied_targets
from planner.solve.result import Status
from planner.tiles.engine import run_tasks


@dataclass(frozen=True, kw_only=True)
class Bound:
    """Lower bounds on the stations of any cover from the pool; ``value`` is the largest, rounded up. ``lp``: the
    cover LP; ``areas``: the sum of the rounded-up LPs of the disjoint sub-areas and their count; ``milp``: the
    cover MILP's bound (None: not run); ``cover``: the best cover the MILP found, a start for stitching."""

    lp: float
    milp: float | None
    areas: tuple[int, int] | None = None
    cover: tuple[int, ...] = ()
    wall_cap_hit: bool = False
    lagrange: LagrangeBound | None = None
    cft: float | None = None

    def terms(self) -> list[tuple[str, float, int]]:
        """Each bound computed: its name, its value and that value rounded up (an integer count)."""
        out = [("cover LP", self.lp, _up(self.lp))]
        if self.areas is not None:
            out.append((f"{self.areas[1]} disjoint sub-areas' LPs rounded up", float(self.areas[0]), self.areas[0]))
        if self.lagrange is not None:
            name = f"Lagrangian over {len(self.lagrange.per_tile)} tile parts"
            out.append((name, self.lagrange.raw, _up(self.lagrange.value)))
        if self.cft is not None:
            out.append(("CFT's Lagrangian", self.cft, _up(self.cft)))
        if self.milp is not None:
            out.append(("cover MILP's bound", self.milp, _up(self.milp)))
        return out

    @property
    def value(self) -> int:
        return max(up for _, _, up in self.terms())

    @property
    def decides(self) -> str:
        """The bound that gives ``value`` (the first listed on ties)."""
        return next(name for name, _, up in self.terms() if up == self.value)

    @property
    def how(self) -> str:
        """How ``value`` was derived (plan.json ``bound_how``, and the summary's bound line)."""
        terms = ", ".join(f"{name} {raw:.2f} -> {up}" for name, raw, up in self.terms())
        return f"max({terms}) = {self.value}, decided by the {self.decides}; registration rule dropped, over the pool"


def _up(x: float) -> int:
    return math.ceil(x - 1e-6)


def lp_bound(a: sp.csr_matrix) -> float:
    """Optimum of min sum x, A^T x >= 1, 0 <= x <= 1 over the whole matrix (HiGHS interior point with crossover).
    Rows implied by another row (a piece seen by every candidate that sees some other piece) are dropped first:
    covering the other covers it, so the optimum is unchanged."""
    used = np.flatnonzero(np.diff(a.indptr) > 0)
    at = a[used].T.astype(np.float64).tocsr()
    at = at[~implied_targets(at.astype(bool).tocsr())]
    res = linprog(np.ones(len(used)), A_ub=-at, b_ub=-np.ones(at.shape[0]), bounds=(0, 1), method="highs-ipm")
    if res.status != 0:
        raise RuntimeError(f"LP bound failed: {res.message}")
    return float(res.fun)


def sub_areas(a: sp.csr_matrix) -> list[np.ndarray]:
    """The pieces in groups that no candidate sees two of (the components of the candidate-piece graph, over the
    pieces some candidate sees), each group's piece indices sorted, groups in order of their first piece."""
    a = sp.csr_matrix(a, dtype=bool)
    n_cand, n_targ = a.shape
    both = sp.bmat([[None, a], [a.T, None]]).tocsr()
    _, label = connected_components(both, directed=False)
    piece = label[n_cand:]
    _, first, inverse = np.unique(piece, return_index=True, return_inverse=True)
    return [np.flatnonzero(inverse == k) for k in np.argsort(first)]


def areas_bound(a: sp.csr_matrix, areas: Sequence[np.ndarray]) -> tuple[int, int]:
    """The sum over ``areas`` (:func:`sub_areas`) of each area's cover LP rounded up, and their number."""
    a = sp.csr_matrix(a, dtype=bool)
    return sum(_up(lp_bound(a[:, cols].tocsr())) for cols in areas), len(areas)


def global_bound(
    a: sp.csr_matrix,
    time_limit_s: float,
    seed: int = 0,
    work_limited: bool = False,
    wall_cap: float | None = WALL_CAP,
    parts: Sequence[np.ndarray] | None = None,
    lagrange_iterations: int = 0,
    lagrange_work_s: float = 10.0,
    client: Any = None,
    cft: float | None = None,
) -> Bound:
    """The bounds of the module docstring over ``a``: the LP, the sub-areas, with ``time_limit_s`` > 0 the cover
    MILP's bound, with ``parts`` (a partition of the pieces, e.g. the tiles' cores) the Lagrangian bound over them
    (:func:`planner.bounds.lagrange.lagrangian_bound`, on CP-SAT work limits; on ``client`` if given), and ``cft``
    (CFT's bound, computed by the caller with its cover). ``work_limited``: the MILP's limit is CP-SAT work
    (deterministic seconds) under a wall cap ``wall_cap`` times as long (None: none), so the bound and the cover it
    returns do not depend on the load."""
    milp: float | None = None
    cover: tuple[int, ...] = ()
    capped = False
    if time_limit_s > 0:
        inst = CoverInstance(by_candidate=a.astype(bool).tocsr(), cost=np.ones(a.shape[0]), name="site cover")
        opts = MilpOptions(overlap=None, seed=seed, threads=1, plain_start=False)  # a bound; CFT runs once elsewhere
        wall = replace(opts, time_limit_s=time_limit_s, work_limit=None)  # the user chose wall-clock limits
        res = solve(inst, opts.with_work_limit(time_limit_s, wall_cap) if work_limited else wall)
        milp = res.objective if res.status is Status.OPTIMAL else res.bound
        cover, capped = tuple(int(i) for i in res.selected), res.wall_cap_hit
    lag = None
    if parts is not None:
        lag = lagrangian_bound(
            a,
            parts,
            iterations=lagrange_iterations,
            work_s=lagrange_work_s,
            seed=seed,
            upper=float(len(cover)) if cover else None,
            runner=partial(run_tasks, client=client, step="lagrange"),
        )
    # the Lagrangian bound solves the same cover LP for its duals: its value is not solved for twice
    areas = sub_areas(a)
    lp = lag.lp if lag is not None else lp_bound(a)
    return Bound(
        lp=lp,
        areas=areas_bound(a, areas) if len(areas) > 1 else None,  # one area: the LP itself
        milp=milp,
        cover=cover,
        wall_cap_hit=capped,
        lagrange=lag,
        cft=cft,
    )
