"""The connected greedy's core: registration bundles grown together by gain, bridged, pruned, re-grown.

A *bundle* is the chosen stations of one registration group (a zone-side, or an accessible area); a plan is
registrable when every bundle is connected under the overlap relation ``adj``. :func:`bundle_cover` builds one in four
phases, in the manner of Jia and Lichti's hierarchical greedy:

1. **grow**: Chvatal's rule (most newly covered targets per unit cost) over the stations linked to their group's
   bundle and the first station of a group not yet opened; all bundles grow in one loop, so a target goes to
   whichever group sees it most cheaply;
2. **bridge**: where no such station gains, the cheapest overlap path (Dijkstra, each step costing the station it
   enters) from a bundle to a station of its group's component that gains, ranked by what the path covers per station;
3. **prune**: stations whose targets others also cover are dropped, latest first, when their bundle stays connected;
4. **re-grow**: each bundle of two or more stations is grown afresh, alone, for the targets only it covers, from its
   group's ``starts`` best seeds; the cheapest is kept if cheaper.

Invariants: after every step of 1-2 each group's chosen stations form one connected bundle inside one component of the
group's overlap graph; ``uncovered`` holds exactly the needed targets no chosen station sees; ``gain[c]`` is how many
of them candidate c sees. Phases 3-4 keep coverage and connectivity. A group opened in one component cannot later use
another: when that leaves a target unseen, the group is fixed to a component that sees it and the pass restarts (at
most once per group); a target whose seers all lie in one component fixes that component up front.

Complexity (C candidates, E overlap pairs, k stations taken): a pass is O(k C + nnz(A)) plus O(E log C) per bridge;
pruning is k connectivity checks; re-growing a group of m candidates costs ``starts`` passes on its m rows. Ties go to
the lowest index (no clock or random draws).

References: V. Chvatal, "A greedy heuristic for the set-covering problem", Math. Oper. Res. 4(3):233-235, 1979; F. Jia
and D. D. Lichti, "An efficient, hierarchical viewpoint planning strategy for terrestrial laser scanner networks",
ISPRS Annals IV-2:137-144, 2018, and "A model-based design system for terrestrial laser scanning networks in complex
sites", Remote Sensing 11(15):1749, 2019.
"""

from __future__ import annotations

from collections.abc import Hashable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.csgraph import connected_components, dijkstra

from planner.coverage.overlap import group_ids

#: bridged candidates per step whose whole path is scored exactly (ranked first by their own gain per path cost)
SHORTLIST = 32

Ints = NDArray[np.int64]
Flags = NDArray[np.bool_]


@dataclass(frozen=True)
class Graph:
    """What a pass reads: coverage both ways, the same-group overlap graph and its components, costs."""

    a: sp.csr_matrix  # C x T, int64 0/1
    by_target: sp.csr_matrix  # T x C
    adj: sp.csr_matrix  # C x C, symmetric, pairs of one group only
    steps: sp.csr_matrix  # adj with the edge u -> v weighing cost[v]: a path's length is what its stations cost
    gid: Ints  # group of each candidate, 0..G-1
    comp: Ints  # component of each candidate under adj (inside one group)
    cost: NDArray[np.float64]

    @classmethod
    def of(cls, a: sp.spmatrix, adj: sp.spmatrix, gid: Ints, cost: NDArray[np.float64]) -> Graph:
        n = a.shape[0]
        a = sp.csr_matrix(a, dtype=bool).astype(np.int64)
        e = sp.coo_matrix(adj)
        keep = (gid[e.row] == gid[e.col]) & (e.row != e.col)
        adj = sp.csr_matrix((np.ones(int(keep.sum())), (e.row[keep], e.col[keep])), shape=(n, n))
        adj.sum_duplicates()
        adj.data[:] = 1.0
        _, comp = connected_components(adj, directed=False)
        cost = np.asarray(cost, dtype=np.float64)
        return cls(a, a.T.tocsr(), adj, adj.multiply(cost[None, :]).tocsr(), gid, comp.astype(np.int64), cost)

    def rows(self, v: int) -> Ints:
        return self.a.indices[self.a.indptr[v] : self.a.indptr[v + 1]]

    def seers(self, targets: Ints) -> Ints:
        """The candidates seeing each of ``targets``, one entry per pair (rows of ``by_target`` read in place: a
        sparse slice per station taken cost more than the greedy step itself)."""
        ptr, ind = self.by_target.indptr, self.by_target.indices
        if targets.size == 1:
            return ind[ptr[targets[0]] : ptr[targets[0] + 1]]
        return np.concatenate([ind[a:b] for a, b in zip(ptr[targets].tolist(), ptr[targets + 1].tolist(), strict=True)])

    def sub(self, members: Ints, cols: Ints) -> Graph:
        """The graph of ``members`` (one group) on the targets ``cols``; this graph itself where those are all its
        candidates and targets (one group over the whole site: not copied)."""
        one = np.zeros(len(members), np.int64)
        if len(members) == self.a.shape[0] and len(cols) == self.a.shape[1] and not self.gid.any():
            return self
        return Graph.of(self.a[members][:, cols], self.adj[members][:, members], one, self.cost[members])


def _grow(g: Graph, need: Flags, fixed: Mapping[int, int], first: int | None = None) -> tuple[list[int], Flags]:
    """Phases 1-2 (module docstring): the stations in the order taken and the needed targets left unseen (none unless
    stuck). ``fixed``: group -> the component its bundle must lie in; ``first``: a station taken before the rule
    applies (a seed)."""
    n = g.a.shape[0]
    uncovered = need.copy()
    gain = np.asarray(g.a @ uncovered.astype(np.int64)).ravel()
    taken = np.zeros(n, dtype=bool)
    linked = np.zeros(n, dtype=bool)
    opened = np.full(int(g.gid.max(initial=-1)) + 1, -1, dtype=np.int64)  # the component of each group's bundle
    for grp, c in fixed.items():
        opened[grp] = c
    started = np.zeros(len(opened), dtype=bool)  # the group holds a station
    order: list[int] = []

    def take(path: Sequence[int]) -> None:
        for v in path:
            taken[v] = True
            order.append(int(v))
            started[g.gid[v]] = True
            if opened[g.gid[v]] < 0:
                opened[g.gid[v]] = g.comp[v]
            linked[g.adj.indices[g.adj.indptr[v] : g.adj.indptr[v + 1]]] = True
            rows = g.rows(v)
            newly = rows[uncovered[rows]]
            if newly.size:
                uncovered[newly] = False
                gain[:] -= np.bincount(g.seers(newly), minlength=n)

    if first is not None:
        take([first])
    while uncovered.any():
        home = opened[g.gid]
        inside = (home < 0) | (g.comp == home)
        useful = ~taken & (gain > 0) & inside
        pick = useful & (linked | ~started[g.gid])  # linked to its bundle, or a group's first station
        if pick.any():
            take([int(np.argmax(np.where(pick, gain / g.cost, -np.inf)))])  # first index among ties
            continue
        path = _bridge(g, useful & started[g.gid], taken, uncovered, gain, order)
        if path is None:
            break
        take(path)
    return order, uncovered


def _bridge(g: Graph, reach: Flags, taken: Flags, uncovered: Flags, gain: Ints, sources: list[int]) -> list[int] | None:
    """The overlap path from the chosen stations to one of ``reach`` that newly covers the most per unit of its cost
    (nodes from the bundle outward, the bundle excluded); None when none is reachable."""
    if not reach.any() or not sources:
        return None
    dist, pred, _ = dijkstra(g.steps, directed=True, indices=sources, min_only=True, return_predecessors=True)
    ends = np.flatnonzero(reach & np.isfinite(dist))
    if ends.size == 0:
        return None
    ends = ends[np.lexsort((ends, -gain[ends] / dist[ends]))][:SHORTLIST]
    best: list[int] | None = None
    best_key = (np.inf, 0)
    for v in ends.tolist():
        path = [v]
        while not taken[pred[path[-1]]]:
            path.append(int(pred[path[-1]]))
        seen = np.unique(np.concatenate([g.rows(u) for u in path]))
        key = (-int(uncovered[seen].sum()) / float(g.cost[path].sum()), v)
        if key < best_key:
            best, best_key = path[::-1], key
    return best


def induced(adj: sp.csr_matrix, nodes: Sequence[int]) -> sp.csr_matrix:
    """``adj[nodes][:, nodes]`` (CSR, its entries and their values), read from the rows of ``nodes`` in place: scipy's
    column selection costs far more for the few stations of a plan, asked again and again."""
    idx = np.asarray(nodes, dtype=np.int64).ravel()
    k = idx.size
    if k == 0 or getattr(adj, "format", None) != "csr" or np.unique(idx).size != k:  # scipy's own selection
        return adj[idx][:, idx]
    pos = np.full(adj.shape[0], -1, dtype=np.int64)
    pos[idx] = np.arange(k)
    starts = adj.indptr[idx].astype(np.int64)
    lens = adj.indptr[idx + 1] - starts
    first = np.cumsum(lens) - lens  # where each row's entries begin among those taken
    take = np.repeat(starts - first, lens) + np.arange(int(lens.sum()))
    cols = pos[adj.indices[take]]
    inside = cols >= 0
    indptr = np.zeros(k + 1, dtype=np.int64)
    np.cumsum(np.bincount(np.repeat(np.arange(k), lens)[inside], minlength=k), out=indptr[1:])
    return sp.csr_matrix((adj.data[take][inside], cols[inside], indptr), shape=(k, k))


def _connected(adj: sp.csr_matrix, nodes: Sequence[int]) -> bool:
    if len(nodes) <= 1:
        return True
    return bool(connected_components(induced(adj, nodes), directed=False)[0] == 1)


def _prune(g: Graph, need: Flags, order: Sequence[int]) -> list[int]:
    """Phase 3: drop, latest taken first, each station whose needed targets another chosen one also sees, when its
    group's other stations stay connected without it."""
    chosen = list(order)
    count = np.asarray(g.a[chosen].sum(axis=0)).ravel() if chosen else np.zeros(g.a.shape[1], np.int64)
    for v in reversed(order):
        rows = g.rows(v)
        if np.any(need[rows] & (count[rows] <= 1)):
            continue
        rest = [u for u in chosen if u != v and g.gid[u] == g.gid[v]]
        if not _connected(g.adj, rest):
            continue
        chosen.remove(v)
        count[rows] -= 1
    return chosen


def _regrow(g: Graph, need: Flags, chosen: Sequence[int], starts: int) -> list[int]:
    """Phase 4: each group holding two or more stations re-grown alone for the needed targets no other group's station
    sees, from its ``starts`` candidates that see most of them; the cheapest plan kept when cheaper than the group's
    current one (groups in the order of their first chosen station)."""
    plan = list(chosen)
    for grp in dict.fromkeys(int(g.gid[v]) for v in chosen):
        mine = [v for v in plan if g.gid[v] == grp]
        if len(mine) < 2 or starts < 1:
            continue
        others = [v for v in plan if g.gid[v] != grp]
        left = need & ~(np.asarray(g.a[others].sum(axis=0)).ravel() > 0) if others else need.copy()
        members = np.flatnonzero(g.gid == grp)
        cols = np.flatnonzero(left)
        if cols.size == 0:  # the other groups see all it does
            plan = others
            continue
        sub = g.sub(members, cols)
        all_cols = np.ones(len(cols), dtype=bool)
        seen = np.asarray(sub.a.sum(axis=1)).ravel()
        best, best_cost = mine, float(g.cost[mine].sum())
        seeds = np.argsort(-seen, kind="stable")[:starts]
        for s in seeds[seen[seeds] > 0].tolist():
            order, unseen = _grow(sub, all_cols, {}, first=s)
            if unseen.any():
                continue
            got = members[_prune(sub, all_cols, order)]
            if float(g.cost[got].sum()) < best_cost - 1e-9:
                best, best_cost = got.tolist(), float(g.cost[got].sum())
        plan = others + [int(v) for v in best]
    return plan


def _fixed_components(g: Graph, need: Flags) -> dict[int, int] | None:
    """Group -> component for every needed target whose seers all lie in one component (a connected cover must then
    use it); None when two such targets fix one group to two components (no connected cover exists)."""
    bt = g.by_target
    rows = np.flatnonzero(np.diff(bt.indptr) > 0)  # segments of the seen targets (empty rows have none)
    if rows.size == 0:
        return {}
    lab = g.comp[bt.indices]
    lo = np.minimum.reduceat(lab, bt.indptr[rows])
    hi = np.maximum.reduceat(lab, bt.indptr[rows])
    out: dict[int, int] = {}
    for c in np.unique(lo[(lo == hi) & need[rows]]).tolist():
        grp = int(g.gid[np.flatnonzero(g.comp == c)[0]])
        if out.setdefault(grp, c) != c:
            return None
    return out


def bundle_cover(
    by_candidate: sp.spmatrix,
    adj: sp.spmatrix,
    groups: Sequence[Hashable],
    cost: NDArray[np.float64],
    need: Flags,
    starts: int = 50,
) -> list[int] | None:
    """A cover of the targets ``need`` whose every group's stations are connected under ``adj`` (sorted), or None when
    some needed target is seen by no candidate or no connected choice was found (module docstring). ``adj``: C x C
    symmetric overlap relation (pairs across groups ignored); ``cost`` > 0; ``starts``: seeds tried per group when
    re-growing its bundle (phase 4; 0: no re-growing)."""
    gid = group_ids(groups)
    g = Graph.of(by_candidate, adj, gid, np.asarray(cost, dtype=np.float64))
    need = np.asarray(need, dtype=bool)
    if np.any(need & (np.diff(g.by_target.indptr) == 0)):
        return None
    fixed = _fixed_components(g, need)
    for _ in range(int(gid.max(initial=-1)) + 2):
        if fixed is None:
            return None
        order, unseen = _grow(g, need, fixed)
        if not unseen.any():
            plan = _prune(g, need, _regrow(g, need, _prune(g, need, order), starts))
            return sorted(plan)
        t = int(np.flatnonzero(unseen)[0])  # fix a seer's group to the seer's component, then start again
        seers = g.by_target.indices[g.by_target.indptr[t] : g.by_target.indptr[t + 1]]
        free = [int(s) for s in np.sort(seers) if int(g.gid[s]) not in fixed]
        if not free:
            return None
        fixed = {**fixed, int(g.gid[free[0]]): int(g.comp[free[0]])}
    return None
