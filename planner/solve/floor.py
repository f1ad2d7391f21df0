"""The floor probe: is there a connected plan of exactly the block's bound, among the few candidates such a plan can use?

A block's cover LP is often the plain optimum, and the cut loop then spends most of its work finding and cutting off
disconnected plans of that size in the whole pool. A plan of cost ``L`` can only use candidates that belong to some
plain cover of cost ``L``; for a site whose areas are seen apart (no candidate sees two of them) that is a small part
of the pool: a room one station covers keeps only the stations that see all of it. The probe solves the block on those
candidates with the cap ``sum c x <= L`` (the same cut loop); an infeasible model proves the bound ``L + 1``, a
connected answer is an optimal plan, and the repairs and local search on the way often find the incumbent as well.

Which candidates stay (unit costs, counts of stations): the block's targets fall into components (targets linked by a
common seer); the cover LP decomposes over them, and each component ``c`` needs at least ``lb_c``, the ceiling of its
LP value. A candidate ``j`` of component ``c`` is in a plan of ``L`` stations only if ``c`` can be covered with ``j``
in ``L - sum_{c' != c} lb_c'`` stations: its LP value plus ``j``'s reduced cost (at the LP's duals) must fit, and where
one or no station is left after ``j`` that is checked exactly (what ``j`` misses of ``c`` is seen whole by one other
candidate, or there is nothing it misses). A candidate that sees no target stays only if one station is spare.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog
from scipy.sparse.csgraph import connected_components

from planner.solve.backends import CAPABILITIES
from planner.solve.block import BlockSolver
from planner.solve.instance import CoverInstance

if TYPE_CHECKING:
    from planner.solve.milp import MilpOptions

__all__ = ["CoverLP", "Floor", "ProbeRecord", "cover_lp", "floor_candidates", "probe"]

#: LP values and reduced costs within this of an integer are that integer
_TOL = 1e-6


@dataclass(frozen=True, kw_only=True)
class Floor:
    """The plan size a probe tests (``level`` stations), the block's candidates (local indices) that a plan of that
    size can use (``keep``), and ``lower``: the sum of the components' LP ceilings (a lower bound in stations)."""

    level: int
    keep: np.ndarray
    lower: int


@dataclass(frozen=True, kw_only=True)
class CoverLP:
    """What :func:`floor_candidates` reads of a unit-cost block whatever the level: the coverage as 0/1 floats, the
    cover LP's reduced costs, the components of targets and candidates (targets linked by a common seer), each
    component's LP value and ceiling, and the sum of the ceilings (``lower``)."""

    a: sp.csr_matrix
    reduced: np.ndarray
    target_comp: np.ndarray
    cand_comp: np.ndarray
    lp_value: dict[int, float]
    need: dict[int, int]
    lower: int


def cover_lp(sub: sp.csr_matrix) -> CoverLP | None:
    """The cover LP of a unit-cost block (``sub``: candidates x targets) and its components; None where it has no
    target or the LP does not solve."""
    a = sub.astype(bool).astype(np.float64).tocsr()
    n, m = a.shape
    if m == 0:
        return None
    lp = linprog(np.ones(n), A_ub=-a.T, b_ub=-np.ones(m), bounds=(0, None), method="highs")
    if lp.status != 0:
        return None
    duals = np.maximum(-np.asarray(lp.ineqlin.marginals), 0.0)
    both = sp.bmat([[None, a], [a.T, None]]).tocsr()
    _, label = connected_components(both, directed=False)
    target_comp = label[n:]
    lp_value = {int(c): float(duals[target_comp == c].sum()) for c in np.unique(target_comp)}
    need = {c: math.ceil(v - _TOL) for c, v in lp_value.items()}
    return CoverLP(
        a=a,
        reduced=1.0 - a @ duals,
        target_comp=target_comp,
        cand_comp=label[:n],
        lp_value=lp_value,
        need=need,
        lower=sum(need.values()),
    )


def floor_candidates(sub: sp.csr_matrix, bound: float, lp: CoverLP | None = None) -> Floor | None:
    """The candidates of a unit-cost block (``sub``: candidates x targets) that a plan of ``L`` stations can use, L the
    larger of ``ceil(bound)`` and the components' LP ceilings; None where the cover LP does not solve. ``lp``: the
    block's :func:`cover_lp`, when already solved (it does not depend on the bound)."""
    lp = lp if lp is not None else cover_lp(sub)
    if lp is None:
        return None
    a, lower = lp.a, lp.lower
    n = a.shape[0]
    level = max(math.ceil(bound - _TOL), lower)
    sees = a.getnnz(axis=1) > 0
    keep = np.zeros(n, dtype=bool)
    keep[~sees] = level - lower >= 1  # a bridge: one station to spare
    for c, value in lp.lp_value.items():
        members = np.flatnonzero((lp.cand_comp == c) & sees)
        budget = level - (lower - lp.need[c])
        fits = value + lp.reduced[members] <= budget + _TOL
        left = budget - 1  # stations after j itself
        if left <= 1:
            fits &= _exact(a[members][:, lp.target_comp == c].toarray() > 0, left)
        keep[members] = fits
    return Floor(level=level, keep=np.flatnonzero(keep), lower=lower)


def _exact(seen: np.ndarray, left: int) -> np.ndarray:
    """Which rows of ``seen`` (one component's candidates x its targets) are in a cover of ``1 + left`` rows (``left``
    0 or 1): the row sees everything, or one other row sees everything it misses."""
    missed = ~seen
    if left <= 0:
        return np.asarray(~missed.any(axis=1), dtype=bool)
    m = missed.astype(np.int32)
    return np.asarray(((m @ m.T) == 0).any(axis=1), dtype=bool).reshape(seen.shape[0])


#: the probe runs only where a plan of the floor's size can use at most this share of the block's candidates (beyond
#: it the restricted model is not much smaller than the block's own, whose cut loop asks the same question; Baalbek's
#: site with doors keeps 44 % at its floor 20, the 4-ha plant 95 % at 21)
KEEP_SHARE = 0.75


@dataclass(frozen=True, kw_only=True)
class ProbeRecord:
    """One probe: the plan size it tested (``level`` stations), the candidates it kept of the block's, its outcome
    (``refuted``: no connected plan of that size, so the bound is one more; ``found``: a plan of that size, optimal;
    ``open``: its work ran out first) and the CP-SAT work, rounds and cuts it took."""

    level: int
    candidates: int
    of: int
    outcome: str
    work: float
    rounds: int
    cuts: int


def probe(block: BlockSolver, o: MilpOptions, work: float) -> list[ProbeRecord]:
    """Probe ``block`` (a unit-cost block of one or more registration groups, k = 1, single precision, on a backend
    that stops on counted work) at its floor, then one station higher while the floor keeps few candidates, within
    ``work`` CP-SAT seconds in all; raises the block's bound on each refuted level (a row of its model too), takes a better plan found on the
    way, and closes the block when its plan meets its bound. Returns what each probe did."""
    done: list[ProbeRecord] = []
    if not _probes(block, o):
        return done
    unit = float(block.cost[0])
    lp = cover_lp(block.sub)  # the same LP at every level: solved once
    while not block.done and block.incumbent is not None and work - sum(p.work for p in done) > 1e-3:
        floor = floor_candidates(block.sub, block.bound / unit, lp)
        if floor is None:
            break
        block.bound = max(block.bound, floor.lower * unit)
        if floor.level >= len(block.incumbent):
            break
        if floor.keep.size > KEEP_SHARE * block.sub.shape[0]:
            break
        record = _probe_once(block, o, floor, work - sum(p.work for p in done))
        done.append(record)
        if record.outcome == "refuted":  # the block's own search then looks no lower (the objective floor)
            block.bound = max(block.bound, (floor.level + 1) * unit)
            n = block.sub.shape[0]
            block.backend.add_rows([(np.arange(n), np.ones(n), float(floor.level + 1))])
        if record.outcome != "refuted":
            break
    if block.incumbent is not None and len(block.incumbent) <= math.ceil(block.bound / unit - _TOL):
        block.done = True
    return done


def _probes(block: BlockSolver, o: MilpOptions) -> bool:
    """Whether the probe applies: registration groups, k = 1, single precision, the cut loop on a work-limited
    backend, unit costs, an open block with a plan."""
    return (
        o.floor_probe
        and block.groups is not None
        and block.adj is not None
        and o.k == 1
        and o.precision == "single"
        and o.connectivity_method == "loop"
        and CAPABILITIES[o.backend].work_limit
        and not block.done
        and block.incumbent is not None
        and block.cost.size > 0
        and bool(np.all(block.cost == block.cost[0]))
    )


def _probe_once(block: BlockSolver, o: MilpOptions, floor: Floor, work: float) -> ProbeRecord:
    """The block on ``floor.keep`` with the cap ``sum x <= level``, run for ``work`` CP-SAT seconds at most."""
    assert block.groups is not None and block.adj is not None
    m = block.sub.shape[1]
    local = CoverInstance(by_candidate=block.sub, cost=block.cost, groups=tuple(block.groups))
    inner = BlockSolver(
        local, block.sub, block.adj, floor.keep, np.arange(m), (), replace(o, tree_bound=False), block.deadline
    )
    level_cost = floor.level * float(block.cost[0])
    if not inner.done:
        inner.backend.add_rows([(np.arange(floor.keep.size), -inner.cost, -level_cost)])
        inner.run(block.deadline, work)
    found = inner.incumbent is not None and float(inner.cost[inner.incumbent].sum()) <= level_cost + 1e-9
    if inner.incumbent is not None:
        chosen = [int(floor.keep[i]) for i in inner.incumbent]
        if block.incumbent is None or len(chosen) < len(block.incumbent):
            block.incumbent = chosen
    refuted = not found and (inner.done or inner.infeasible)
    return ProbeRecord(
        level=floor.level,
        candidates=int(floor.keep.size),
        of=int(block.sub.shape[0]),
        outcome="found" if found else "refuted" if refuted else "open",
        work=round(inner.work_used, 3),
        rounds=inner.rounds,
        cuts=inner.cuts,
    )
