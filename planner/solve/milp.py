"""The set-cover MILP with registration-overlap connectivity and precision, on any backend.

    minimise   sum_j c_j x_j
    subject to sum_{j sees t} x_j >= k                         every target t
               sum_j (sigma_req / sigma_tj)^2 x_j >= 1          every t (precision "combined")
               chosen stations of each group connected          (overlap relation, lazy cuts)

The problem is split into independent blocks (no shared target, no common
group), each presolved and warm-started from a connected greedy plan
(:mod:`planner.solve.block`), or, with no registration groups, from the
better of the greedy cover and CFT's cover shrunk by the local search
(:mod:`planner.solve.plain_start`). A block of one group first gets the ring bound
(:mod:`planner.solve.ring`), which closes A, B, C, Baalbek and building27
before any search; the others are solved, connectivity cuts added and the
block re-solved until its choice is connected. Objectives and bounds of the
blocks add up.
"""

from __future__ import annotations

import math
import time
from collections.abc import Hashable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from planner.core.checks import argument, count, flag, real
from planner.core.errors import UsageError
from planner.coverage.overlap import (
    DEFAULT_OVERLAP,
    SITE_SHARE,
    OverlapRule,
    SiteShare,
    group_ids,
    overlap_adjacency,
)
from planner.solve.backends import BACKENDS, NODE_LIMITED
from planner.solve.block import BlockSolver, lengths
from planner.solve.instance import CoverInstance
from planner.solve.lazy_links import OverlapLinks, linked_dominated
from planner.solve.plain_start import MOVES_PER_TARGET, plain_record
from planner.solve.presolve import (
    PresolveReport,
    dominated,
    duplicate_targets,
    forced,
    implied_targets,
)
from planner.solve.result import SolveResult, Status

PRECISION_MODES = ("single", "combined")
#: CP-SAT deterministic seconds a whole solve may spend (cpsat; about a minute of one core): a count of work, so
#: the plan is the same under any load; Baalbek's site with doors and the 4-ha plant end on it, the other bundled
#: sites are proven well within it
WORK_LIMIT = 25.0
#: branch-and-bound nodes per solve on the backends that take a node limit (:data:`NODE_LIMITED`)
NODE_LIMIT = 10_000
#: wall-clock cap of a work-limited MILP the tiles and windows run, as a multiple of its work limit
#: (:meth:`MilpOptions.with_work_limit`); None: no cap (a wall-clock limit is only a cap the user sets)
WALL_CAP: float | None = None
#: how registration connectivity is enforced: branch-and-cut in one SCIP tree (PySCIPOpt),
#: a single-commodity flow model, or the cut loop that re-solves after each round of cuts
CONNECTIVITY = ("auto", "bc", "flow", "loop")


@dataclass(frozen=True, kw_only=True)
class MilpOptions:
    """The MILP's options, each checked when made (:class:`UsageError` on a bad value). Every limit of the search
    is a count (CP-SAT work, nodes, rounds, moves, steps) unless the user sets ``time_limit_s``; a block with no
    registration groups gets the plain start (``plain_start``, ``plain_start_moves``), a connected one the local
    search of ``local_search_moves``."""

    backend: str = "cpsat"
    #: a wall-clock cap in seconds on the whole solve, only where the user sets one (None: none). A solve it
    #: cuts may depend on the machine's load: ``info["work"]["wall_cap_hit"]`` says so
    time_limit_s: float | None = None
    seed: int = 0
    threads: int = 1
    k: int = 1
    #: the registration rule: an :class:`OverlapRule`, ``None`` (none), or a :class:`SiteShare` (default): the
    #: site's own overlap share, resolved once per run with the site (0 means none; a bare ``solve`` has no
    #: site: :data:`DEFAULT_OVERLAP`)
    overlap: OverlapRule | SiteShare | None = SITE_SHARE
    precision: str = "single"
    greedy_starts: int = 50
    max_rounds: int = 500
    presolve: bool = True
    connectivity: str = "auto"
    layer_cuts: bool = False
    tree_bound: bool = False
    #: the ring bound (:mod:`planner.solve.ring`): a block of one registration group whose stations see runs
    #: of its wall gets the cheapest walk over its arcs as a lower bound (exact where every run is whole)
    ring_bound: bool = True
    #: steps of the Lagrangian ascent that adds the cover rows to the ring bound (a count: the same bound
    #: under any load; 0: the ring bound alone)
    ring_lagrange_steps: int = 500
    #: CP-SAT deterministic seconds for the whole solve (cpsat; None: none): with one thread the answer does not
    #: depend on the machine's load. Other backends ignore it
    work_limit: float | None = WORK_LIMIT
    #: branch-and-bound nodes per solve of the cut loop on scip, pulp-cbc and pyscipopt (None: none); highs and
    #: cbc take none, so there only the user's ``time_limit_s`` stops a solve short of its optimum
    node_limit: int | None = NODE_LIMIT
    #: swaps of the local search (:mod:`planner.solve.local_search`) that tries, once per incumbent size, to
    #: find a connected plan one station smaller, down to the block's bound (unit costs, k = 1; 0: off, the plain
    #: start's search included)
    local_search_moves: int = 500
    #: the plain start (:mod:`planner.solve.plain_start`): a block with no registration groups (unit costs, k = 1,
    #: single precision) starts from CFT's cover shrunk by the plain local search where that beats its greedy
    plain_start: bool = True
    #: moves of the plain start's local search per target of its block, a count set by the block's size (as the
    #: tiled plan's ``MOVES_PER_PIECE``; 0: CFT's cover unsearched)
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
        for name in ("presolve", "layer_cuts", "tree_bound", "ring_bound", "plain_start"):
            flag(getattr(self, name), name)
        real(self.plain_start_moves, "plain_start_moves", at_least=0)
        argument(self.overlap, (OverlapRule, SiteShare, type(None)), "overlap")
        if self.work_limit is not None:
            real(self.work_limit, "work_limit", above=0)

    @property
    def rule(self) -> OverlapRule | None:
        """The registration rule in force: a :class:`SiteShare` unresolved (no site at hand) is taken at the
        default share."""
        return self.overlap.rule(DEFAULT_OVERLAP) if isinstance(self.overlap, SiteShare) else self.overlap

    def with_work_limit(self, work_s: float, wall_cap: float | None = WALL_CAP) -> MilpOptions:
        """These options stopped on ``work_s`` deterministic seconds of CP-SAT work, under a wall-clock cap of
        ``wall_cap`` times as long (None: the user's cap ``time_limit_s``, if any)."""
        return replace(
            self, time_limit_s=self.time_limit_s if wall_cap is None else wall_cap * work_s, work_limit=work_s
        )

    @property
    def limits(self) -> dict[str, Any]:
        """The limits that stop this solve on its backend: its counted work (``work_limit`` CP-SAT deterministic
        seconds on cpsat, ``node_limit`` nodes per solve where the backend takes one) and the wall-clock cap."""
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
    """Solve the cover; the result's status is OPTIMAL only when every block was proven optimal and connected.

    Options come as a :class:`MilpOptions` or as keywords of it, e.g.
    ``solve(cover_instance(problem), backend="scip", time_limit_s=30, seed=1, threads=1)``.
    """
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
        return SolveResult(
            method="milp",
            status=Status.INFEASIBLE,
            selected=(),
            objective=None,
            time_s=time.perf_counter() - start,
            backend=o.backend,
            info={"targets_seen_by_fewer_than_k": bad[:20].tolist(), "count": int(bad.size)},
        )
    connect = o.rule is not None and instance.groups is not None
    report, solvers = block_solvers(instance, o, deadline)
    _share_out(solvers, deadline, o.work_limit if o.backend == "cpsat" else None)
    if any(b.infeasible for b in solvers):
        return SolveResult(
            method="milp",
            status=Status.INFEASIBLE,
            selected=(),
            objective=None,
            time_s=time.perf_counter() - start,
            backend=o.backend,
            info={"presolve": report.to_dict()},
        )
    if any(b.incumbent is None for b in solvers):
        return SolveResult(
            method="milp",
            status=Status.NO_SOLUTION,
            selected=(),
            objective=None,
            time_s=time.perf_counter() - start,
            backend=o.backend,
            info={"presolve": report.to_dict()},
        )
    selected: list[int] = [int(b.cands[i]) for b in solvers for i in (b.incumbent or ())]
    objective = float(sum(b.cost[b.incumbent].sum() for b in solvers))
    bound = float(
        sum(b.cost[b.incumbent].sum() if b.done else min(b.bound, b.cost[b.incumbent].sum()) for b in solvers)
    )
    all_optimal = all(b.done for b in solvers)
    rounds, cuts = sum(b.rounds for b in solvers), sum(b.cuts for b in solvers)
    status = Status.OPTIMAL if all_optimal else Status.FEASIBLE
    info = {
        "presolve": report.to_dict(),
        "rounds": rounds,
        "cuts": cuts,
        "connected": connect,
        "local_search_moves": sum(b.local_moves for b in solvers),
        "ring_bound": {
            "blocks": sum(b.ring is not None for b in solvers),
            "closed_before_search": sum(b.ring is not None and b.done and not b.rounds for b in solvers),
            "lagrange_steps": sum(b.lagrange_steps for b in solvers),
            "work_capped_blocks": sum(b.ring_work_capped for b in solvers),
        },
        "connectivity": o.connectivity_method if connect else "none",
    }
    if any(b.plain is not None for b in solvers):  # only then: a connected run's record stays as it was
        info["plain_start"] = plain_record([b.plain for b in solvers if b.plain is not None])
    limits = o.limits
    info["work"] = {
        "limit": limits["work_limit"],
        "used": round(sum(b.work_used for b in solvers), 3),
        "node_limit": limits["node_limit"],
        "wall_cap_s": limits["wall_cap_s"],
        # the user's wall-clock cap, not the counted work, ended the search: only then may the plan depend on the load
        "wall_cap_hit": not all_optimal and time.perf_counter() >= deadline,
    }
    return SolveResult(
        method="milp",
        status=status,
        selected=tuple(sorted(selected)),
        objective=objective,
        bound=objective if all_optimal else bound,
        time_s=time.perf_counter() - start,
        backend=o.backend,
        info=info,
    )


def block_solvers(
    instance: CoverInstance, o: MilpOptions, deadline: float = math.inf
) -> tuple[PresolveReport, list[BlockSolver]]:
    """The presolve report and one solver per independent block (smallest first), as :func:`solve` runs them;
    the registration rule applies when ``o.rule`` is set and the instance has groups. ``deadline``: the user's
    wall-clock cap as a ``time.perf_counter()`` instant, which the blocks' starts and searches keep too."""
    a = instance.by_candidate.astype(bool).tocsr()
    adj: sp.csr_matrix | OverlapLinks | None = None
    if o.rule is not None and instance.groups is not None:
        adj = instance.relation.astype(bool).tocsr() if instance.relation is not None else _adjacency(instance, a, o)
    report, adj = _presolve(instance, a, adj, o)
    keep_c = np.asarray(report.kept_candidates, dtype=np.int64)
    keep_t = np.asarray(report.kept_targets, dtype=np.int64)
    return report, [
        BlockSolver(instance, a, adj, bc, bt, report.forced_candidates, o, deadline)
        for bc, bt in _blocks(a, keep_c, keep_t, instance.groups)
    ]


def _adjacency(instance: CoverInstance, a: sp.csr_matrix, o: MilpOptions) -> sp.csr_matrix | OverlapLinks:
    """The overlap relation (C x C). Where the presolve will run dominance and the relation depends on the
    coverage alone (no ``max_link_m``, no links through openings), it is not formed here: the presolve forms
    it among the candidates it keeps (:func:`planner.solve.lazy_links.linked_dominated`)."""
    assert o.rule is not None and instance.groups is not None
    plain = (
        o.presolve
        and o.k == 1
        and o.precision == "single"
        and o.rule.max_link_m is None
        and (instance.links is None or instance.links.nnz == 0)
        and bool(np.all(lengths(instance) > 0))
    )
    if not plain:
        return overlap_adjacency(a, lengths(instance), o.rule, instance.groups, instance.xy, instance.links)[0]
    return OverlapLinks(lengths(instance), o.rule, group_ids(instance.groups))


def _share_out(solvers: list[BlockSolver], deadline: float, work_limit: float | None) -> None:
    """Pass 1: each block an equal share of what is left (a block that finishes early leaves its rest);
    pass 2: the blocks not yet proven share whatever is left. Shares are of CP-SAT work (deterministic
    seconds: every share, and so the plan, is the same under any load), else of the user's wall-clock cap;
    with neither, each block runs until it is proven or its node limit per solve ends its cut loop."""
    for first in (True, False):
        todo = solvers if first else [b for b in solvers if not b.done]
        for k, block in enumerate(todo):
            if work_limit is not None:
                left = work_limit - sum(b.work_used for b in solvers)
                if left > 1e-6:
                    block.run(deadline, block.work_used + left / (len(todo) - k))
                continue
            share = (deadline - time.perf_counter()) / (len(todo) - k)
            if share > 0:
                block.run(time.perf_counter() + share if math.isfinite(share) else math.inf)


def _presolve(
    instance: CoverInstance, a: sp.csr_matrix, adj: sp.csr_matrix | OverlapLinks | None, o: MilpOptions
) -> tuple[PresolveReport, sp.csr_matrix | None]:
    """The presolve's report and the overlap relation as a matrix (among the kept candidates where it came lazy)."""
    start = time.perf_counter()
    n_cand, n_targ = a.shape
    drop = np.zeros(n_cand, dtype=bool)
    if not o.presolve:
        assert not isinstance(adj, OverlapLinks)
        every = PresolveReport(
            candidates_in=n_cand,
            targets_in=n_targ,
            kept_candidates=tuple(range(n_cand)),
            kept_targets=tuple(range(n_targ)),
        )
        return every, adj
    if o.k == 1 and o.precision == "single":
        drop, dup, adj = _reduce(a, instance.cost, adj, instance.groups if adj is not None else None)
    elif o.precision == "single":
        dup = duplicate_targets(instance.by_target)
    else:
        dup = np.zeros(n_targ, dtype=bool)
    kept_c = np.flatnonzero(~drop)
    bt = a[kept_c].T.tocsr()
    must = forced(bt, o.k)
    assert not isinstance(adj, OverlapLinks)
    links = None if adj is None else int(adj[kept_c][:, kept_c].nnz // 2)
    report = PresolveReport(
        candidates_in=n_cand,
        targets_in=n_targ,
        dominated=int(drop.sum()),
        duplicate_targets=int(dup.sum()),
        forced=int(must.sum()),
        kept_candidates=tuple(kept_c.tolist()),
        kept_targets=tuple(np.flatnonzero(~dup).tolist()),
        forced_candidates=tuple(kept_c[must].tolist()),
        time_s=time.perf_counter() - start,
        links=links,
    )
    return report, adj


#: at most this many alternations of dominance and implied targets (each pass is a valid reduction)
_REDUCE_PASSES = 20


def _reduce(
    a: sp.csr_matrix, cost: np.ndarray, adj: sp.csr_matrix | OverlapLinks | None, groups: Sequence[Hashable] | None
) -> tuple[np.ndarray, np.ndarray, sp.csr_matrix | None]:
    """Dominated candidates and implied targets (k = 1, single precision), alternated until neither
    removes anything: dropping candidates makes more targets implied (every *remaining* seer of t' sees
    t) and dropping targets makes more candidates dominated. Each step keeps the connected optimum of
    the problem it is applied to (see :func:`dominated` and :func:`implied_targets`), so the last
    one's equals the first's. Polygon A (cached pool of scripts/bench/bench_connectivity.py): 958 candidates x
    1,618 targets after one pass, 574 x 361 after this (measured).
    Returns the masks of dropped candidates and targets, and the relation (formed among the kept candidates
    after the first pass where it came lazy)."""
    kc, kt = np.arange(a.shape[0]), np.arange(a.shape[1])
    for _ in range(_REDUCE_PASSES):
        if isinstance(adj, OverlapLinks):  # the first pass, on every candidate: indices are the instance's
            d, adj = linked_dominated(a, cost, adj)
        else:
            sub = adj[kc][:, kc].tocsr() if adj is not None else None
            d = dominated(a[kc][:, kt].tocsr(), cost[kc], sub, [groups[i] for i in kc] if groups is not None else None)
        kc = kc[~d]
        imp = implied_targets(a[kc][:, kt].T.tocsr())
        kt = kt[~imp]
        if not (d.any() or imp.any()):
            break
    drop, dup = np.ones(a.shape[0], dtype=bool), np.ones(a.shape[1], dtype=bool)
    drop[kc], dup[kt] = False, False
    return drop, dup, adj


def _blocks(a: sp.csr_matrix, keep_c: np.ndarray, keep_t: np.ndarray, groups) -> list[tuple[np.ndarray, np.ndarray]]:
    """Independent parts: candidates linked through shared targets or a common group.

    The components of one graph: candidates, then targets, then one node per group, a candidate joined to its
    targets and to its group's node (linear in the pairs and candidates; the candidate x candidate "same group"
    product it replaces grew as the kept candidates squared, 1.4 GiB on polygon C at a 1-m grid). The group
    nodes come last, so every component's lowest node, and with it the order of the labels, is as before."""
    sub = a[keep_c][:, keep_t].tocsr()
    nc, nt = sub.shape
    gid = group_ids([groups[i] for i in keep_c]) if groups is not None else np.zeros(0, dtype=np.int64)
    ng = int(gid.max(initial=-1)) + 1
    rows = np.concatenate([np.repeat(np.arange(nc), np.diff(sub.indptr)), np.arange(gid.size)])
    cols = np.concatenate([nc + sub.indices, nc + nt + gid])
    size = nc + nt + ng
    graph = sp.csr_matrix((np.ones(rows.size, dtype=bool), (rows, cols)), shape=(size, size))
    n, label = connected_components(graph, directed=False)
    out = []
    for b in range(n):
        members = np.flatnonzero(label == b)
        bc, bt = keep_c[members[members < nc]], keep_t[members[(members >= nc) & (members < nc + nt)] - nc]
        if bt.size:
            out.append((bc, bt))
    # smallest first: a small block is usually proven inside its share and leaves the rest, in one
    # piece, to the larger ones (polygon C: the outside block proves in ~7 s, the inside one then
    # runs on without the restart that a second pass costs); ties keep the component order
    return sorted(out, key=lambda b: b[0].size * b[1].size)
