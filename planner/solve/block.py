"""One independent block of the connected MILP: its backend model, the cuts found so far, its best plan.

:func:`planner.solve.milp.solve` makes one :class:`BlockSolver` per block (no shared target, no common registration
group). Before any search a block of one group whose targets are all wall pieces gets the ring bound and its
Lagrangian ascent (:mod:`planner.solve.ring`); then :meth:`BlockSolver.run` solves, cuts disconnected answers off and
re-solves until its plan is connected and proven, or its work (or the user's wall-clock cap) is used up.
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from planner.solve.backends import Outcome, Row
from planner.solve.connectivity import (
    connected_greedy,
    connectivity_cuts,
    disconnected_groups,
    essential_targets,
    group_members,
    neighbour_cuts,
    repair,
)
from planner.solve.flow import FlowModel
from planner.solve.greedy import greedy_cover
from planner.solve.instance import CoverInstance
from planner.solve.local_search import shrink
from planner.solve.plain_start import plain_start
from planner.solve.registry import make_backend
from planner.solve.result import Status
from planner.solve.ring import RingBound, RingGraph, lagrangian_bound, ring_graph
from planner.solve.separators import layer_cuts
from planner.solve.treebound import add_tree_bound

if TYPE_CHECKING:
    from planner.solve.milp import MilpOptions
    from planner.solve.plain_start import PlainStart

#: steps of the Lagrangian ascent before the local search is tried (the rest of the budget comes after it)
_FIRST_STEPS = 50
#: re-grow seeds of the connected greedy (:func:`planner.solve.bundles.bundle_cover`, phase 4) in a block with floor
#: or ceiling patches: the MILP and the local search improve on its start
SURFACE_STARTS = 1
#: CP-SAT rounds of a block with floor or ceiling patches: on hundreds of stations a round costs several CPU seconds
#: per deterministic second and lifts the cover LP's bound a few stations (polygon B with floors: 629 -> 633 in 8
#: rounds, 70 CPU-s); its plans come from the greedy and the local search after each round
SURFACE_ROUNDS = 2
#: CP-SAT work (deterministic seconds) of one such round: 2 rounds of 2 lift polygon B's bound to 633 in ~17 CPU-s
#: (a single round of 25 took 65 CPU-s for the same bound)
SURFACE_ROUND_WORK = 2.0
#: the ascent's work budget, in walk units (each step's multi-source walk costs the lifted graph's links times its
#: sources): a fine grid, whose walks grow with its links, stops on it instead of running for minutes
RING_WORK = 5e9


def _rows(m: sp.spmatrix, lb: float) -> list[Row]:
    """One row ``sum_j m[t, j] x_j >= lb`` per row t of ``m``."""
    m = m.astype(np.float64).tocsr()
    return [
        (m.indices[m.indptr[t] : m.indptr[t + 1]], m.data[m.indptr[t] : m.indptr[t + 1]], lb) for t in range(m.shape[0])
    ]


class BlockSolver:
    """One independent block: its backend model (with the cuts found so far) and its best connected plan."""

    def __init__(
        self,
        instance: CoverInstance,
        a: sp.csr_matrix,
        adj: sp.csr_matrix | None,
        cands: np.ndarray,
        targets: np.ndarray,
        forced_all: tuple[int, ...],
        o: MilpOptions,
        deadline: float = math.inf,
    ) -> None:
        self.o, self.cands, self.deadline = o, cands, deadline
        self.sub = a[cands][:, targets].tocsr()
        self.cost = instance.cost[cands]
        self.adj = adj[cands][:, cands].tocsr() if adj is not None else None
        self.groups = [instance.groups[i] for i in cands] if (adj is not None and instance.groups is not None) else None
        # its capabilities say which optional members (watch, work_limit, cuts, connect) it has
        self.backend: Any = make_backend(o.backend, len(cands), self.cost, o.node_limit)
        self.essential: dict = {}  # set with the model: only the search uses it
        self.integral = bool(np.all(self.cost == np.round(self.cost)))
        self._duals: np.ndarray | None = None  # the cover LP's duals, solved once for the ascent
        self.incumbent: list[int] | None = None
        self.flow: FlowModel | None = None
        # floor and ceiling patches (targets of no wall length) make a block of hundreds of stations, where each of the
        # connected greedy's re-grow seeds costs a whole greedy pass (stations x candidates): one seed there
        self.surfaces = not bool(np.all(instance.lengths_m[targets] > 0))
        if self.groups is not None and o.k == 1 and o.precision == "single":
            starts = min(o.greedy_starts, SURFACE_STARTS) if self.surfaces else o.greedy_starts
            self.incumbent = connected_greedy(
                self.sub, self.adj, self.groups, self.cost, np.ones(self.sub.shape[1], dtype=bool), starts
            )
        elif self.groups is None and o.k == 1 and o.precision == "single":
            g = greedy_cover(self.sub, weights=self.cost)
            self.incumbent = list(g.selected) if g.status is Status.FEASIBLE else None
        self.rounds, self.cuts, self._backend_cuts = 0, 0, 0
        self.plain: PlainStart | None = plain_start(self.sub, self.cost, self.groups, self.incumbent, o, deadline)
        if self.plain is not None:  # no registration groups: the better of greedy and CFT's searched cover
            self._better(list(self.plain.selected))
        self.bound, self.local_moves = (self.plain.bound, self.plain.moves) if self.plain else (0.0, 0)
        self.done = self.infeasible = False
        self._seen: list[tuple[list[int], dict]] = []  # disconnected solutions of the current solve, with parts
        self._shrunk: set[float] = set()  # incumbent costs the local search started from
        self.ring: RingBound | None = None
        self.lagrange_steps = 0
        self.ring_work_capped = False  # the ascent stopped at RING_WORK before its steps
        # the ring bound orders a block's wall pieces round its outline: a floor or ceiling patch lies on no ring, and
        # its columns, appended after the walls, would stretch every arc over them (a bound near nothing for an ascent
        # whose walks grow with the square of the candidates)
        if o.ring_bound and not self.surfaces:
            self._ring(a, targets)
        if not self.done:  # a block the ring bound closed needs no model
            self._model(instance, a, targets, forced_all)

    def _model(
        self, instance: CoverInstance, a: sp.csr_matrix, targets: np.ndarray, forced_all: tuple[int, ...]
    ) -> None:
        """The block's rows on its backend: cover (and precision) rows, forced candidates, and with registration
        groups the neighbour cuts and the rows of the connectivity method."""
        o, cands = self.o, self.cands
        rows = _rows(self.sub.T, float(o.k))
        if o.precision == "combined" and instance.info is not None:
            rows += _rows(instance.info[cands][:, targets].T, 1.0)
        self.backend.add_rows(rows)
        pos = {int(c): k for k, c in enumerate(cands)}
        self.backend.fix([pos[c] for c in forced_all if c in pos])
        if self.groups is None:
            return
        self.essential = essential_targets(self.sub, self.groups)
        if not self.surfaces:  # with floor patches nearly every pair is linked: a row as long as the block, no cut
            self.backend.add_rows(neighbour_cuts(self.adj, self.sub, self.groups, self.essential))
        if o.layer_cuts:
            self.backend.add_rows(self._layers())
        if o.tree_bound and o.k == 1:
            add_tree_bound(self.backend, a[cands].tocsr(), instance.lengths_m, self.adj, self.groups)
        if o.connectivity_method == "bc":
            self.backend.connect(self.adj, self.groups, self.sub, self.essential)
        elif o.connectivity_method == "flow":
            self.flow = FlowModel(self.backend, self.adj, self.groups, self.essential, self.cost, self.incumbent)
        if o.connectivity_method == "loop" and self.backend.capabilities.watch:
            self.backend.watch = self._watch

    def _ring(self, a: sp.csr_matrix, targets: np.ndarray) -> None:
        """Before any search, for a block of one registration group (k = 1, single precision): the ring bound over
        every piece its candidates see (its walk the incumbent when a connected cover), ``_FIRST_STEPS`` steps of the
        Lagrangian ascent, then the local search and, unless the first steps gave up, the rest of the ascent. Closes
        the block when the incumbent meets the bound (the local search comes second: one ascent step often closes what
        it would take long to find)."""
        o = self.o
        if self.groups is None or self.adj is None or len(set(self.groups)) != 1 or o.k != 1 or o.precision != "single":
            return
        seen = a[self.cands].tocsr()
        pos = np.flatnonzero(seen.getnnz(axis=0))
        graph = ring_graph(seen[:, pos].tocsr(), np.isin(pos, targets), self.adj)
        self.ring = graph.walk(self.cost) if graph is not None and np.all(self.cost > 0) else None
        if graph is None or self.ring is None:
            return
        self.bound = max(self.bound, self.ring.bound)
        walk = list(self.ring.walk)
        if np.all(self.sub[walk].getnnz(axis=0) > 0) and not disconnected_groups(self.adj, self.groups, walk):
            self._better(walk)
        self.done = self._closed()
        if self.done or self.incumbent is None:
            return
        self._ascend(graph, min(_FIRST_STEPS, o.ring_lagrange_steps))
        if not self.done:
            self._shrink()
            self.done = self._closed()
        if not self.done and self.lagrange_steps == min(_FIRST_STEPS, o.ring_lagrange_steps):
            self._ascend(graph, o.ring_lagrange_steps - self.lagrange_steps)  # not when the first part gave up

    def _ascend(self, graph: RingGraph, steps: int) -> None:
        """The Lagrangian ascent from the cover LP's duals toward the incumbent, ``steps`` steps at most and, over all
        its calls, :data:`RING_WORK` walk units (a count: the bound does not depend on the load)."""
        per_step = max(1, graph.graph.nnz * len(graph.anchors))
        allowed = int(RING_WORK // per_step) - self.lagrange_steps
        self.ring_work_capped = self.ring_work_capped or allowed < steps
        steps = min(steps, allowed)
        if steps <= 0 or self.incumbent is None:
            return
        sub = self.sub.astype(np.float64).tocsr()
        if self._duals is None:
            lp = linprog(self.cost, A_ub=-sub.T, b_ub=-np.ones(sub.shape[1]), bounds=(0, None), method="highs")
            if lp.status != 0:
                return
            self._duals = -lp.ineqlin.marginals
        best = float(self.cost[self.incumbent].sum())
        value, taken = lagrangian_bound(
            graph, sub, self.cost, self._duals, best, best - 1 + 1e-6 if self.integral else best - 1e-9, steps
        )
        self.lagrange_steps += taken
        self.bound = max(self.bound, value)
        self.done = self._closed()

    def _watch(self, selected: tuple[int, ...], objective: float) -> bool:
        """During a solve: keep a connected solution as the incumbent, remember a disconnected one for cuts."""
        chosen = list(selected)
        broken = disconnected_groups(self.adj, self.groups or [], chosen)
        if broken:
            self._seen.append((chosen, broken))
            return False
        self._better(chosen)
        return False

    def _layers(self) -> list[Row]:
        groups = self.groups or []
        members = group_members(groups, range(len(groups)))
        return [
            cut
            for g, m in members.items()
            if self.essential.get(g) is not None
            for cut in layer_cuts(self.adj, self.sub, np.asarray(m), self.essential[g])
        ]

    def _better(self, chosen: list[int]) -> None:
        if self.incumbent is None or self.cost[chosen].sum() < self.cost[self.incumbent].sum() - 1e-9:
            self.incumbent = chosen

    @property
    def work_used(self) -> float:
        """CP-SAT deterministic seconds this block has spent (0 on other backends)."""
        return float(self.backend.work_used) if self.backend.capabilities.work_limit else 0.0

    def run(self, deadline: float, work_until: float | None = None) -> None:
        """Solve, cut and re-solve until the choice is connected and proven optimal, the deadline, the block's CP-SAT
        work reaches ``work_until`` (when given), a solve stopped on its limit finds nothing to cut (a re-solve of
        the same model would give the same answer), or, in a block with floor or ceiling patches, after
        :data:`SURFACE_ROUNDS` rounds."""
        if work_until is not None:
            self.backend.work_limit = work_until
        rounds = min(self.o.max_rounds, SURFACE_ROUNDS) if self.surfaces else self.o.max_rounds
        while not self.done and self.rounds < rounds:
            left = deadline - time.perf_counter()
            if left <= 0 or (work_until is not None and self.work_used >= work_until - 1e-6):
                return
            if self.surfaces and work_until is not None:  # a round's share, not the whole of what is left
                self.backend.work_limit = min(work_until, self.work_used + SURFACE_ROUND_WORK)
            hint: list[int] | dict[int, float] | None = self.incumbent
            if self.flow is not None and self.incumbent is not None:
                hint = self.flow.hint(self.incumbent)
            res = self.backend.solve(left, self.o.threads, self.o.seed, hint)
            self.rounds += 1
            if self.backend.capabilities.branch_and_cut:  # the cuts its handler added inside the search
                self.cuts += self.backend.cuts - self._backend_cuts
                self._backend_cuts = self.backend.cuts
            if res.bound is not None:
                self.bound = max(self.bound, res.bound)
            if res.outcome is Outcome.INFEASIBLE:
                self.infeasible = self.incumbent is None
                self.done = not self.infeasible
                return
            if res.outcome is Outcome.UNKNOWN:
                return
            chosen = list(res.selected)
            seen, self._seen = self._seen, []
            broken = disconnected_groups(self.adj, self.groups, chosen) if self.groups is not None else {}
            if not broken:
                self._better(chosen)
                self.done = res.outcome is Outcome.OPTIMAL
                if self.done:
                    continue
            new = []
            for sol, parts in ([(chosen, broken)] if broken else []) + [(s, p) for s, p in seen if s != chosen]:
                for g, comps in parts.items():
                    new += connectivity_cuts(self.adj, comps, self.sub, self.essential.get(g))
                fixed = repair(self.adj, self.cost, self.groups if self.groups is not None else [], sol)
                if fixed is not None:
                    self._better(fixed)
            self.backend.add_rows(new)
            self.cuts += len(new)
            self._shrink()
            self.done = self._closed()
            if not new and res.outcome is Outcome.FEASIBLE:
                return

    def _closed(self) -> bool:
        """Whether the incumbent is connected and meets the bound (integral costs: its ceiling)."""
        if self.incumbent is None or not (self.rounds or self.ring is not None):
            return False
        bound = np.ceil(self.bound - 1e-6) if self.integral else self.bound
        return bool(self.cost[self.incumbent].sum() <= bound + 1e-9)

    def _shrink(self) -> None:
        """Local search for a connected plan one station smaller, once per incumbent size, down to the bound."""
        o = self.o
        if (
            self.groups is None
            or self.incumbent is None
            or o.local_search_moves == 0
            or o.k != 1
            or o.precision != "single"
            or np.ptp(self.cost) > 0
        ):
            return
        size = float(self.cost[self.incumbent].sum())
        floor = int(np.ceil(self.bound / self.cost[0] - 1e-6))
        if size in self._shrunk or len(self.incumbent) <= floor:
            return
        self._shrunk.add(size)
        found = shrink(
            self.sub, self.adj, self.groups, self.incumbent, o.local_search_moves, floor, deadline=self.deadline
        )
        self.local_moves += found.moves
        self._better(list(found.selected))
