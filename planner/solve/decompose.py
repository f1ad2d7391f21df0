"""The MILP's decomposition: the presolve (dominated candidates, implied targets, forced stations) and the independent
blocks (no shared target, no common group), each with its :class:`BlockSolver`."""

from __future__ import annotations

import math
import time
from collections.abc import Hashable, Sequence
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from planner.coverage.overlap import group_ids, overlap_adjacency
from planner.solve.block import BlockSolver
from planner.solve.instance import CoverInstance
from planner.solve.lazy_links import OverlapLinks, linked_dominated
from planner.solve.presolve import PresolveReport, dominated, duplicate_targets, forced, implied_targets

if TYPE_CHECKING:
    from planner.solve.milp import MilpOptions


def block_solvers(
    instance: CoverInstance, o: MilpOptions, deadline: float = math.inf
) -> tuple[PresolveReport, list[BlockSolver]]:
    """The presolve report and one solver per independent block (smallest first), as :func:`solve` runs them; the
    registration rule applies when ``o.rule`` is set and the instance has groups. ``deadline``: the user's wall-clock
    cap as a ``time.perf_counter()`` instant, which the blocks' starts and searches keep too."""
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
    """The overlap relation (C x C). Where the presolve will run dominance and the relation depends on the coverage
    alone (no ``max_link_m``, no links through openings), it is not formed here: the presolve forms it among the
    candidates it keeps (:func:`planner.solve.lazy_links.linked_dominated`)."""
    assert o.rule is not None and instance.groups is not None
    plain = (
        o.presolve
        and o.k == 1
        and o.precision == "single"
        and o.rule.max_link_m is None
        and (instance.links is None or instance.links.nnz == 0)
        and bool(np.all(instance.lengths_m > 0))
    )
    if not plain:
        return overlap_adjacency(a, instance.lengths_m, o.rule, instance.groups, instance.xy, instance.links)[0]
    return OverlapLinks(instance.lengths_m, o.rule, group_ids(instance.groups))


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
    """Dominated candidates and implied targets (k = 1, single precision), alternated until neither removes anything:
    dropping candidates makes more targets implied and dropping targets makes more candidates dominated. Each step
    keeps the connected optimum of the problem it is applied to, so the last one's equals the first's. Returns the
    masks of dropped candidates and targets, and the relation (formed among the kept where it came lazy)."""
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
    """Independent parts: the components of one graph of candidates, targets and then groups, a candidate joined to
    its targets and its group (linear in the pairs, not the candidates squared of a "same group" product; the group
    nodes last, so the labels follow the candidates' order)."""
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
    # smallest first: a small block is usually proven inside its share and leaves the rest to the larger ones; ties
    # keep the component order
    return sorted(out, key=lambda b: b[0].size * b[1].size)
