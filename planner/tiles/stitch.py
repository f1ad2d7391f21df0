"""Stitching tile plans into one site plan, and the global lower bound.

Stitching: the union of the tiles' plans covers every piece (each tile's plan covers its core).
On the site's whole coverage matrix and overlap relation (shared wall over every piece a station
sees, not only a tile's), stations are then

1. pruned: in order of fewest pieces seen (ties by index), a station is dropped when every piece
   stays covered and its registration group does not fall into more parts;
2. joined: :func:`planner.solve.connectivity.repair` adds the cheapest chains of stations between
   the parts of each group (shortest paths in the overlap graph);
3. pruned again.

The same is done from the best whole-site cover the bound's MILP found (a plan without the
registration rule, joined the same way) and from the connected greedy on the whole site; the
smallest connected plan is kept (:func:`planner.tiles.search.best_plan`).

Bound: every connected plan is a cover, so any lower bound of the plain set cover over the whole
pool bounds the connected problem. Two are computed on the whole matrix: the LP relaxation
(HiGHS interior point; rounded up, an integer count) and the best bound of the cover MILP without
the registration rule (CP-SAT, time-limited); optionally a third, the Lagrangian decomposition over
the tiles (:mod:`planner.bounds.lagrange`); the largest is reported.
"""

from __future__ import annotations

import math
from collections.abc import Hashable, Sequence
from dataclasses import dataclass, replace
from functools import partial
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from planner.bounds.lagrange import LagrangeBound, lagrangian_bound
from planner.solve.connectivity import components, group_members, repair
from planner.solve.instance import CoverInstance
from planner.solve.milp import WALL_CAP, MilpOptions, solve
from planner.solve.presolve import implied_targets
from planner.solve.result import Status
from planner.tiles.engine import run_tasks


def _group_parts(adj: sp.csr_matrix, groups: Sequence[str], chosen: Sequence[int], g: str) -> int:
    return len(components(adj, [i for i in chosen if groups[i] == g]))


def prune(a: sp.csr_matrix, adj: sp.csr_matrix, groups: Sequence[str], chosen: Sequence[int]) -> list[int]:
    """Drop stations that no piece needs and whose removal splits no registration group further."""
    keep = sorted(int(i) for i in chosen)
    count = np.asarray(a[keep].astype(np.int64).sum(axis=0)).ravel()
    seen = {i: a.indices[a.indptr[i] : a.indptr[i + 1]] for i in keep}
    for i in sorted(keep, key=lambda i: (len(seen[i]), i)):
        if np.any(count[seen[i]] <= 1):
            continue
        before = _group_parts(adj, groups, keep, groups[i])
        rest = [j for j in keep if j != i]
        if _group_parts(adj, groups, rest, groups[i]) > before:
            continue
        keep = rest
        count[seen[i]] -= 1
    return keep


@dataclass(frozen=True, kw_only=True)
class Stitched:
    """The site plan made from the tiles': ``selected`` (global indices), how many stations the
    union, the pruning and the joining chains held, and the parts of each group at the end."""

    selected: tuple[int, ...]
    union: int
    pruned: int
    added: int
    parts: dict[Hashable, int]
    source: str = "tile plans"
    tried: dict[str, int] | None = None


def stitch(
    a: sp.csr_matrix, adj: sp.csr_matrix, groups: Sequence[str], tile_plans: Sequence[Sequence[int]]
) -> Stitched:
    """Union, prune, join, prune (module docstring)."""
    union = sorted({int(i) for plan in tile_plans for i in plan})
    first = prune(a, adj, groups, union)
    joined = repair(adj, np.ones(a.shape[0]), groups, first)
    joined = first if joined is None else joined
    final = prune(a, adj, groups, joined)
    parts = {g: len(components(adj, m)) for g, m in group_members(groups, final).items()}
    return Stitched(
        selected=tuple(final),
        union=len(union),
        pruned=len(union) - len(first),
        added=len(joined) - len(first),
        parts=parts,
    )


@dataclass(frozen=True, kw_only=True)
class Bound:
    """A lower bound on the stations of any cover from the pool: ``value`` = max of the two below;
    ``cover``: the best cover the MILP found (registration not required), a second start for stitching."""

    lp: float
    milp: float | None
    milp_status: Status | None
    cover: tuple[int, ...] = ()
    wall_cap_hit: bool = False
    lagrange: LagrangeBound | None = None

    @property
    def value(self) -> int:
        lp = math.ceil(self.lp - 1e-6)
        best = max(lp, math.ceil(self.milp - 1e-6)) if self.milp is not None else lp
        return max(best, math.ceil(self.lagrange.value - 1e-6)) if self.lagrange is not None else best

    @property
    def how(self) -> str:
        """How ``value`` was derived (plan.json ``bound_how``)."""
        terms = ["ceil(LP of the whole cover)"] + (["cover-MILP bound"] if self.milp is not None else [])
        if self.lagrange is not None:
            terms.append(f"Lagrangian bound over {len(self.lagrange.per_tile)} tile parts")
        return f"max({', '.join(terms)}), registration rule dropped"


def lp_bound(a: sp.csr_matrix) -> float:
    """Optimum of min sum x, A^T x >= 1, 0 <= x <= 1 over the whole matrix (HiGHS interior point with
    crossover). Rows implied by another row (a piece seen by every candidate that sees some other piece)
    are dropped first: covering the other covers it, so the optimum is unchanged."""
    used = np.flatnonzero(np.diff(a.indptr) > 0)
    at = a[used].T.astype(np.float64).tocsr()
    at = at[~implied_targets(at.astype(bool).tocsr())]
    res = linprog(np.ones(len(used)), A_ub=-at, b_ub=-np.ones(at.shape[0]), bounds=(0, 1), method="highs-ipm")
    if res.status != 0:
        raise RuntimeError(f"LP bound failed: {res.message}")
    return float(res.fun)


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
) -> Bound:
    """The LP bound and, with ``time_limit_s`` > 0, the cover MILP's bound (registration rule dropped).
    ``work_limited``: the limit is CP-SAT work (deterministic seconds), under a wall cap ``wall_cap`` times
    as long where one is given (None: none), so the bound and the cover it returns do not depend on the load. With ``parts`` (a partition
    of the pieces, e.g. the tiles' cores) also the Lagrangian bound over them
    (:func:`planner.bounds.lagrange.lagrangian_bound`, always on CP-SAT work limits; on ``client`` if given)."""
    milp: float | None = None
    status: Status | None = None
    cover: tuple[int, ...] = ()
    capped = False
    if time_limit_s > 0:
        inst = CoverInstance(by_candidate=a.astype(bool).tocsr(), cost=np.ones(a.shape[0]), name="site cover")
        opts = MilpOptions(overlap=None, seed=seed, threads=1)
        wall = replace(opts, time_limit_s=time_limit_s, work_limit=None)  # the user chose wall-clock limits
        res = solve(inst, opts.with_work_limit(time_limit_s, wall_cap) if work_limited else wall)
        milp = res.objective if res.status is Status.OPTIMAL else res.bound
        status, cover, capped = res.status, tuple(int(i) for i in res.selected), res.wall_cap_hit
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
    return Bound(
        lp=lag.lp if lag is not None else lp_bound(a),
        milp=milp,
        milp_status=status,
        cover=cover,
        wall_cap_hit=capped,
        lagrange=lag,
    )
