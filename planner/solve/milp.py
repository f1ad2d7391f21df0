"""The set-cover MILP with registration-overlap connectivity and precision, on any backend.

    minimise   sum_j c_j x_j
    subject to sum_{j sees t} x_j >= k                         every target t
               sum_j (sigma_req / sigma_tj)^2 x_j >= 1          every t (precision "combined")
               chosen stations of each group connected          (overlap relation, lazy cuts)

The problem is split into independent blocks (no shared target, no common group, :mod:`planner.solve.decompose`),
each presolved and warm-started from a connected greedy plan (:mod:`planner.solve.block`), or, with no registration
groups, from the better of the greedy cover and CFT's cover shrunk by the local search
(:mod:`planner.solve.plain_start`). A block of one group first gets the ring bound (:mod:`planner.solve.ring`), which
often closes it before any search; the others are solved, connectivity cuts added and the block re-solved until its
choice is connected. Objectives and bounds of the blocks add up. Every limit of the search is a count (CP-SAT work,
nodes, rounds, moves, steps), so the plan is the same under any load, unless the user sets a wall-clock cap.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, replace
from typing import Any

import numpy as np

from planner.core.checks import argument, count, flag, real
from planner.core.errors import UsageError
from planner.core.settings import DEFAULTS, PRECISION_MODES
from planner.coverage.overlap import DEFAULT_OVERLAP, SITE_SHARE, OverlapRule, SiteShare
from planner.solve.backends import BACKENDS, CAPABILITIES, NODE_LIMITED
from planner.solve.block import BlockSolver
from planner.solve.decompose import block_solvers
from planner.solve.floor import ProbeRecord, probe
from planner.solve.instance import CoverInstance
from planner.solve.plain_start import MOVES_PER_TARGET, plain_record
from planner.solve.result import MilpStats, RingStats, SolveResult, Status, WorkStats, gap_reason

__all__ = ["MilpOptions", "block_solvers", "solve"]

#: CP-SAT deterministic seconds a whole solve may spend (cpsat)
WORK_LIMIT: float = DEFAULTS["milp.work_limit"]
#: the share of a block's first CP-SAT work share that its floor probes may take (:mod:`planner.solve.floor`)
PROBE_SHARE = 0.25
#: the share of a block's first CP-SAT work share that its floor probes may take (:mod:`planner.solve.floor`)
PROBE_SHARE = 0.25
#: branch-and-bound nodes per solve on the backends that take a node limit (:data:`NODE_LIMITED`)
NODE_LIMIT = 10_000
#: wall-clock cap of a work-limited MILP the tiles and windows run, as a multiple of its work limit
#: (:meth:`MilpOptions.with_work_limit`); None: no cap (a wall-clock limit is only a cap the user sets)
WALL_CAP: float | None = None
#: how registration connectivity is enforced: branch-and-cut in one SCIP tree (PySCIPOpt), a single-commodity flow
#: model, or the cut loop that re-solves after each round of cuts
CONNECTIVITY = ("auto", "bc", "flow", "loop")


@dataclass(frozen=True, kw_only=True)
class MilpOptions:
    """The MILP's options, each checked when made (:class:`UsageError` on a bad value)."""

    backend: str = DEFAULTS["milp.backend"]
    #: a wall-clock cap in seconds on the whole solve (None: none); a solve it cuts may depend on the machine's load
    #: (``info["work"]["wall_cap_hit"]``)
    time_limit_s: float | None = DEFAULTS["milp.time_limit_s"]
    seed: int = DEFAULTS["milp.seed"]
    threads: int = 1
    k: int = DEFAULTS["milp.k"]
    #: the registration rule: an :class:`OverlapRule`, ``None`` (none), or a :class:`SiteShare` (default): the site's
    #: own overlap share, resolved once per run with the site (0 means none; a bare ``solve``: :data:`DEFAULT_OVERLAP`)
    overlap: OverlapRule | SiteShare | None = SITE_SHARE
    #: ``single``: each view meets sigma_req alone; ``combined``: the views of a point add information
    precision: str = DEFAULTS["milp.precision"]
    greedy_starts: int = 50
    max_rounds: int = 500
    presolve: bool = True
    connectivity: str = "auto"
    layer_cuts: bool = DEFAULTS["milp.layer_cuts"]
    tree_bound: bool = DEFAULTS["milp.tree_bound"]
    #: the ring bound (:mod:`planner.solve.ring`): a block of one registration group whose stations see runs of its
    #: wall gets the cheapest walk over its arcs as a lower bound (exact where every run is whole)
    ring_bound: bool = DEFAULTS["milp.ring_bound"]
    #: steps of the Lagrangian ascent that adds the cover rows to the ring bound (0: the ring bound alone)
    ring_lagrange_steps: int = 500
    #: CP-SAT deterministic seconds for the whole solve (cpsat; None: none): with one thread the answer does not
    #: depend on the machine's load
    work_limit: float | None = WORK_LIMIT
    #: CP-SAT deterministic seconds in a row without a better plan or bound after which a block stops (cpsat, with a
    #: ``work_limit``; None: it runs to the work limit): the last work seldom pays where the bound is the only doubt
    stall_work: float | None = DEFAULTS["milp.stall_work"]
    #: the floor probe (:mod:`planner.solve.floor`): before a block's cut loop, look for a connected plan of the
    #: bound's size among the candidates such a plan can use (cpsat, unit costs, k = 1, single precision)
    floor_probe: bool = True
    #: branch-and-bound nodes per solve of the cut loop on scip, pulp-cbc and pyscipopt (None: none); highs and
    #: cbc take none, so there only the user's ``time_limit_s`` stops a solve short of its optimum
    node_limit: int | None = NODE_LIMIT
    #: moves of the local search (:mod:`planner.solve.local_search`) that tries, once per incumbent size, to find a
    #: connected plan one station smaller, down to the block's bound (unit costs, k = 1; 0: off, the plain start's too)
    local_search_moves: int = DEFAULTS["milp.local_search_moves"]
    #: the plain start of a block with no registration groups (:mod:`planner.solve.plain_start`)
    plain_start: bool = True
    #: moves of the plain start's local search per target of its block (0: CFT's cover unsearched)
    plain_start_moves: float = MOVES_PER_TARGET

    def __post_init__(self) -> None:
        if self.connectivity not in CONNECTIVITY:
            raise UsageError(
                f"unknown connectivity method (known: {', '.join(CONNECTIVITY)})",
                field="connectivity",
                value=self.connectivity,
            )
        if self.connectivity == "bc" and self.backend != "pyscipopt":
            raise UsageError("branch-and-cut needs the pyscipopt backend", field="backend", value=self.backend)
        if self.backend not in BACKENDS:
            raise UsageError(f"unknown backend (known: {', '.join(BACKENDS)})", field="backend", value=self.backend)
        if self.precision not in PRECISION_MODES:
            raise UsageError("must be single or combined", field="precision", value=self.precision)
        for name, least in (
            ("k", 1),
            ("threads", 1),
            ("seed", 0),
            ("greedy_starts", 1),
            ("max_rounds", 1),
            ("local_search_moves", 0),
            ("ring_lagrange_steps", 0),
        ):
            count(getattr(self, name), name, least)
        if self.time_limit_s is not None:
            real(self.time_limit_s, "time_limit_s", above=0)
        if self.node_limit is not None:
            count(self.node_limit, "node_limit", 1)
        for name in ("presolve", "layer_cuts", "tree_bound", "ring_bound", "plain_start", "floor_probe"):
            flag(getattr(self, name), name)
        real(self.plain_start_moves, "plain_start_moves", at_least=0)
        argument(self.overlap, (OverlapRule, SiteShare, type(None)), "overlap")
        for name in ("work_limit", "stall_work"):
            if getattr(self, name) is not None:
                real(getattr(self, name), name, above=0)

    @property
    def rule(self) -> OverlapRule | None:
        """The registration rule in force: a :class:`SiteShare` unresolved (no site at hand) at the default share."""
        return self.overlap.rule(DEFAULT_OVERLAP) if isinstance(self.overlap, SiteShare) else self.overlap

    def with_work_limit(self, work_s: float, wall_cap: float | None = WALL_CAP) -> MilpOptions:
        """These options stopped on ``work_s`` deterministic seconds of CP-SAT work, under a wall-clock cap of ``wall_cap``
        times as long (None: the user's cap ``time_limit_s``, if any), without the stall rule (the tiles and windows
        that take these split their work in small shares already)."""
        cap = self.time_limit_s if wall_cap is None else wall_cap * work_s
        return replace(self, time_limit_s=cap, work_limit=work_s, stall_work=None)

    @property
    def limits(self) -> dict[str, Any]:
        """The limits that stop this solve on its backend: ``work_limit`` on cpsat, ``node_limit`` where the backend
        takes one, and the wall-clock cap."""
        return {
            "work_limit": self.work_limit if self.backend == "cpsat" else None,
            "node_limit": self.node_limit if self.backend in NODE_LIMITED else None,
            "wall_cap_s": self.time_limit_s,
        }

    @property
    def connectivity_method(self) -> str:
        """The method ``auto`` stands for: branch-and-cut on pyscipopt, the cut loop elsewhere."""
        if self.connectivity != "auto":
            return self.connectivity
        return "bc" if self.backend == "pyscipopt" else "loop"


def solve(instance: CoverInstance, options: MilpOptions | None = None, **overrides: Any) -> SolveResult:
    """Solve the cover, with a :class:`MilpOptions` or keywords of it (``solve(instance, backend="scip", seed=1)``);
    the result's status is OPTIMAL only when every block was proven optimal and connected."""
    argument(instance, CoverInstance, "instance")
    unknown = sorted(set(overrides) - set(MilpOptions.__dataclass_fields__))
    if unknown:
        raise UsageError("not a MilpOptions field", field=unknown[0], value=overrides[unknown[0]])
    o = replace(options or MilpOptions(), **overrides) if overrides else (options or MilpOptions())
    start = time.perf_counter()
    deadline = math.inf if o.time_limit_s is None else start + o.time_limit_s
    counts = np.diff(instance.by_target.indptr)
    if np.any(counts < o.k):
        bad = np.flatnonzero(counts < o.k)
        info = {"targets_seen_by_fewer_than_k": bad[:20].tolist(), "count": int(bad.size)}
        return SolveResult.no_plan("milp", Status.INFEASIBLE, start, o.backend, info)
    report, solvers = block_solvers(instance, o, deadline)
    ran = _share_out(solvers, deadline, o)
    if any(b.infeasible for b in solvers) or any(b.incumbent is None for b in solvers):
        status = Status.INFEASIBLE if any(b.infeasible for b in solvers) else Status.NO_SOLUTION
        return SolveResult.no_plan("milp", status, start, o.backend, {"presolve": report.to_dict()})
    selected: list[int] = [int(b.cands[i]) for b in solvers for i in (b.incumbent or ())]
    objective = float(sum(b.cost[b.incumbent].sum() for b in solvers))
    # a proven block's bound is its incumbent's cost: with every block proven, the bound is the objective
    bound = float(
        sum(b.cost[b.incumbent].sum() if b.done else min(b.bound, b.cost[b.incumbent].sum()) for b in solvers)
    )
    all_optimal = all(b.done for b in solvers)
    # the user's wall-clock cap, not the counted work, ended the search: only then may the plan depend on the load
    capped = not all_optimal and time.perf_counter() >= deadline
    stats = _stats(solvers, o, o.rule is not None and instance.groups is not None, capped, ran)
    status = Status.OPTIMAL if all_optimal else Status.FEASIBLE
    info = {"presolve": report.to_dict(), **stats.to_dict()}
    if not all_optimal and (reason := gap_reason(stats, objective, bound)) is not None:
        info["gap_reason"] = reason
    return SolveResult.timed(
        "milp", status, sorted(selected), objective, start, bound=bound, backend=o.backend, info=info, stats=stats
    )


def _stats(solvers: list[BlockSolver], o: MilpOptions, connect: bool, capped: bool, ran: _Run) -> MilpStats:
    """What the blocks (and their floor probes) did, summed; ``capped``: the user's wall-clock cap ended the search."""
    plain = [b.plain for b in solvers if b.plain is not None]
    limits = o.limits
    used = round(sum(b.work_used for b in solvers) + ran.probe_work, 3)
    stall = o.stall_work if limits["work_limit"] is not None else None
    stop = "proven" if all(b.done for b in solvers) else "wall_cap" if capped else "node_limit"
    if stop == "node_limit" and limits["work_limit"] is not None:
        stop = "work_limit" if used >= limits["work_limit"] - 1e-3 or not any(ran.stalled) else "stalled"
    return MilpStats(
        rounds=sum(b.rounds for b in solvers),
        cuts=sum(b.cuts for b in solvers),
        connected=connect,
        local_search_moves=sum(b.local_moves for b in solvers),
        ring_bound=RingStats(
            blocks=sum(b.ring is not None for b in solvers),
            closed_before_search=sum(b.ring is not None and b.done and not b.rounds for b in solvers),
            lagrange_steps=sum(b.lagrange_steps for b in solvers),
            work_capped_blocks=sum(b.ring_work_capped for b in solvers),
        ),
        connectivity=o.connectivity_method if connect else "none",
        plain_start=plain_record(plain) if plain else None,
        work=WorkStats(
            limits["work_limit"], used, limits["node_limit"], limits["wall_cap_s"], capped, stall, any(ran.stalled)
        ),
        floor=tuple(asdict(p) for block in ran.probes for p in block),
        stop=stop,
    )


def _share_out(solvers: list[BlockSolver], deadline: float, o: MilpOptions) -> _Run:
    """Pass 1: each block an equal share of what is left (a block that finishes early leaves its rest), its floor
    probes first (:mod:`planner.solve.floor`, at most :data:`PROBE_SHARE` of the share); pass 2: the blocks neither
    proven nor stalled share whatever is left. Shares are of CP-SAT work, else of the user's wall-clock cap; with
    neither, each block runs until it is proven or its node limit per solve ends its cut loop."""
    work_limit = o.work_limit if CAPABILITIES[o.backend].work_limit else None
    ran = _Run(probes=[[] for _ in solvers], stalled=[False] * len(solvers))
    for first in (True, False):
        todo = [k for k, b in enumerate(solvers) if first or not (b.done or ran.stalled[k])]
        for n, k in enumerate(todo):
            block = solvers[k]
            if work_limit is not None:
                left = work_limit - sum(b.work_used for b in solvers) - ran.probe_work
                if left > 1e-6:
                    share = left / (len(todo) - n)
                    if first:
                        ran.probes[k] = probe(block, o, share * PROBE_SHARE)
                        share -= sum(p.work for p in ran.probes[k])
                    ran.stalled[k] = _run(block, deadline, block.work_used + share, o.stall_work)
                continue
            share = (deadline - time.perf_counter()) / (len(todo) - n)
            if share > 0:
                block.run(time.perf_counter() + share if math.isfinite(share) else math.inf)
    return ran


def _run(block: BlockSolver, deadline: float, until: float, stall: float | None) -> bool:
    """Run ``block`` until its CP-SAT work reaches ``until``; with ``stall``, one round of its cut loop at a time (a
    round is never cut short), stopping at the end of a round once ``stall`` CP-SAT seconds have passed since the last
    better plan or bound (or since the start). Whether it stopped so (stalled)."""
    if block.done or stall is None:
        block.run(deadline, until)
        return False
    o, last, state = block.o, block.work_used, _state(block)
    try:
        while not block.done and block.rounds < o.max_rounds:
            rounds, before = block.rounds, block.work_used
            block.o = replace(o, max_rounds=rounds + 1)  # the block's loop runs one round
            block.run(deadline, until)
            if block.rounds == rounds or block.work_used >= until - 1e-6 or block.work_used <= before:
                return False  # out of work, or the loop stopped on its own (pass 2 takes it up as before)
            if _state(block) != state:
                last, state = block.work_used, _state(block)
            elif block.work_used - last >= stall - 1e-9:
                return True
    finally:
        block.o = o
    return False


def _state(block: BlockSolver) -> tuple[float, float]:
    """A block's plan cost and bound: what a stall leaves unchanged."""
    return (math.inf if block.incumbent is None else float(block.cost[block.incumbent].sum()), float(block.bound))


@dataclass(frozen=True, kw_only=True)
class _Run:
    """What :func:`_share_out` did besides the blocks' own loops: each block's floor probes and whether it stalled."""

    probes: list[list[ProbeRecord]]
    stalled: list[bool]

    @property
    def probe_work(self) -> float:
        return sum(p.work for block in self.probes for p in block)
