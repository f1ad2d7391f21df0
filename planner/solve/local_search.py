"""Fewer stations for a connected plan (a block's incumbent, a tiled plan): two-phase moves with row weighting.

:func:`shrink` searches the objective

    f(S) = sum of the weights of the targets S leaves unseen + w_link * sum_g (parts of g in S - 1),

with the moves of RWLS (Gao et al., "An efficient local search heuristic with row weighting for the unicost set
covering problem", EJOR 246(3), 2015) and configuration checking (Wang et al., "A weighting-based local search
heuristic algorithm for the set covering problem", CEC 2014):

1. when S is a connected cover it is kept and the station of least removal cost is dropped (S one smaller); else
2. remove the non-tabu station of least removal cost ``loss(s) + w_link * split(s)`` (``loss``: the weight of the
   targets only s sees; ``split``: the parts its removal adds, one articulation-point pass); then
3. add, among the seers of one unseen target (drawn by a seeded generator) and, while S is in pieces, the candidates
   linked to two of its parts, the one of best ``gain(c) - w_link * (1 - parts c touches)`` allowed by configuration
   checking (a removed candidate comes back only after a candidate sharing a target with it changed state);
4. the weights of the unseen targets, and w_link while S is in pieces, grow by one.

A candidate is scored only when it sees a target S leaves unseen or bridges two parts: a move costs O(targets and links
of the few stations and candidates it touches) plus one components and one articulation pass on the chosen stations.
Where the stations are densely linked to each other (a floor grid's plan links nearly every pair), the components
come from a scan-first forest that stops once every station is reached and the articulation pass walks a sparse
certificate of two such forests (:func:`certificate`): O(stations x links of the few rows read). Ties go to the candidate unchanged longest, then to the lowest index, and draws to a generator of fixed seed: the
result depends only on the input, ``moves`` and ``seed`` (no clock).
"""

from __future__ import annotations

import math
import time
from collections.abc import Hashable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from planner.coverage.overlap import group_ids
from planner.solve.connectivity import path_to_nearest

#: moves between two looks at the clock where the user set a wall-clock cap
_CLOCK_EVERY = 64


@dataclass(frozen=True)
class Shrunk:
    """``selected``: the smallest connected cover found (sorted); ``start``: stations given; ``moves``: moves made (at
    most the budget); ``history``: (move, stations) of each smaller connected cover found."""

    selected: tuple[int, ...]
    start: int
    moves: int
    history: tuple[tuple[int, int], ...] = ()

    @property
    def removed(self) -> int:
        return self.start - len(self.selected)


def _gather(m: sp.csr_matrix, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(position in ``rows``, column) of every stored entry of the rows ``rows`` of ``m``, without building a sparse
    matrix (faster for the many small gathers of a move)."""
    rows = np.asarray(rows, dtype=np.int64)
    if rows.size == 0:
        return np.zeros(0, dtype=np.int64), m.indices[:0]
    start, stop = m.indptr[rows], m.indptr[rows + 1]
    ind = m.indices
    cols = np.concatenate([ind[a:b] for a, b in zip(start.tolist(), stop.tolist(), strict=True)])
    return np.repeat(np.arange(len(rows)), stop - start), cols


class _State:
    """The chosen set S with its target counts, weights, components and configuration flags."""

    def __init__(
        self, a: sp.csr_matrix, adj: sp.csr_matrix, gid: np.ndarray, need: np.ndarray, chosen: Sequence[int]
    ) -> None:
        self.a, self.at, self.adj, self.gid = a, a.T.tocsr(), adj, gid
        self.weight = need.astype(np.float64)
        self.need = need
        self.in_s = np.zeros(a.shape[0], dtype=bool)
        self.in_s[list(chosen)] = True
        self.cnt = np.bincount(_gather(a, np.asarray(chosen, dtype=np.int64))[1], minlength=a.shape[1])
        self.conf = np.ones(a.shape[0], dtype=bool)
        self.w_link = 1.0
        self.stamp = np.zeros(a.shape[0], dtype=np.int64)  # move of each candidate's last change
        # how many stations of S each candidate is linked to, kept as S changes (a dense relation is not gathered)
        self.near = np.bincount(_gather(adj, np.asarray(chosen, dtype=np.int64))[1], minlength=a.shape[0])
        self._graph: tuple[np.ndarray, _Links, np.ndarray, int, np.ndarray] | None = None

    def _targets(self, c: int) -> np.ndarray:
        return self.a.indices[self.a.indptr[c] : self.a.indptr[c + 1]]

    def unseen(self) -> np.ndarray:
        return np.flatnonzero(self.need & (self.cnt == 0))

    def flip(self, c: int, step: int) -> None:
        """Add c to S or remove it at move ``step``; the candidates sharing a target with c may come back."""
        self.stamp[c] = step
        t = self._targets(c)
        self.cnt[t] += -1 if self.in_s[c] else 1
        self.near[self.adj.indices[self.adj.indptr[c] : self.adj.indptr[c + 1]]] += -1 if self.in_s[c] else 1
        self.in_s[c] = not self.in_s[c]
        self.conf[_gather(self.at, t)[1]] = True
        self.conf[c] = bool(self.in_s[c])
        self._graph = None

    def graph(self) -> tuple[np.ndarray, _Links, np.ndarray, int, np.ndarray]:
        """S (sorted), its overlap subgraph (:class:`_Links`), each station's component label (in order of each
        component's lowest station), the sum over groups of (components - 1), and for every candidate the number of
        S's components it is linked to."""
        if self._graph is None:
            idx = np.flatnonzero(self.in_s)
            pos = np.full(self.a.shape[0], -1, dtype=np.int64)
            pos[idx] = np.arange(len(idx))
            if _dense_inside(self.adj, idx, pos):
                self._graph = self._dense(idx, pos)
                return self._graph
            row, col = _gather(self.adj, idx)
            keep = pos[col] >= 0  # _gather lists the rows in order: the kept entries are already CSR
            indptr = np.concatenate([[0], np.cumsum(np.bincount(row[keep], minlength=len(idx)))])
            sub = (indptr.tolist(), pos[col[keep]].tolist())  # S's overlap subgraph as CSR lists (a few hundred links)
            n, label = _components(len(idx), *sub)
            parts = int(n - np.unique(self.gid[idx]).size)
            touched = np.zeros(self.a.shape[0], dtype=np.int64)
            if parts == 0:  # one component per group: linked or not
                touched[col] = 1
            else:  # distinct (candidate, component) pairs: a bool table a row per component (faster than np.unique)
                touched = _touched(n, label[row], col, self.a.shape[0])
            self._graph = (idx, _Links(lists=sub), label, parts, touched)
        return self._graph

    def _dense(self, idx: np.ndarray, pos: np.ndarray) -> tuple[np.ndarray, _Links, np.ndarray, int, np.ndarray]:
        """:meth:`graph` where S's stations have many links each: the components from a scan-first forest that stops
        once every station is reached (a few rows when nearly every pair is linked), the links to S from the counts
        kept by :meth:`flip`; S's links are gathered only when S is in pieces."""
        parent, label, n = scan_forest(self.adj, idx, pos)
        parts = int(n - np.unique(self.gid[idx]).size)
        if parts == 0:
            touched = (self.near > 0).astype(np.int64)
        else:
            row, col = _gather(self.adj, idx)
            touched = _touched(n, label[row], col, self.a.shape[0])
        return idx, _Links(tree=parent, pos=pos), label, parts, touched

    def removal_cost(self) -> np.ndarray:
        """loss(s) + w_link * split(s) for each station of S (order of ``graph()[0]``)."""
        idx, links = self.graph()[:2]
        row, col = _gather(self.a, idx)
        loss = np.bincount(row, weights=(self.weight * (self.cnt == 1))[col], minlength=len(idx))
        split = _split(links.lists if links.lists is not None else certificate(self.adj, idx, links))
        _, g, size = np.unique(self.gid[idx], return_inverse=True, return_counts=True)
        split[size[g] == 1] = 0  # the only station of its group: the group leaves S, its parts stay 0
        return loss + self.w_link * split

    def add_score(self, cand: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """gain(c) - w_link * (parts change), and the parts change, of candidates ``cand`` joining S."""
        idx, touched = self.graph()[0], self.graph()[4]
        row, col = _gather(self.a, cand)
        gain = np.bincount(row, weights=(self.weight * (self.cnt == 0))[col], minlength=len(cand))
        change = np.where(np.isin(self.gid[cand], self.gid[idx]), 1 - touched[cand], 0)
        return gain - self.w_link * change, change


#: S's links are gathered whole while its stations have at most this many links inside S each (:func:`_dense_inside`)
_DENSE, _PROBE = 64, 8


def _dense_inside(adj: sp.csr_matrix, idx: np.ndarray, pos: np.ndarray) -> bool:
    """Whether S's stations have more than ``_DENSE`` links inside S each (estimated from its first ``_PROBE`` rows): a
    plant's stations have hundreds of links to the pool, few to each other; a floor grid's link nearly all pairs."""
    degree, col = float(np.diff(adj.indptr)[idx].sum()), _gather(adj, idx[:_PROBE])[1]
    return bool(
        degree > _DENSE * len(idx) and np.count_nonzero(pos[col] >= 0) / max(col.size, 1) * degree > _DENSE * len(idx)
    )


@dataclass(frozen=True, kw_only=True)
class _Links:
    """S's overlap subgraph: as CSR lists (``lists``), or, where it is dense, as a scan-first spanning forest
    (``tree``: each station's parent, -1 for a root, by position in S; ``pos``: each candidate's position, -1 off S)."""

    lists: tuple[list[int], list[int]] | None = None
    tree: np.ndarray | None = None
    pos: np.ndarray | None = None


def _touched(n: int, label: np.ndarray, col: np.ndarray, size: int) -> np.ndarray:
    """For each of ``size`` candidates, how many of the ``n`` components hold a station linked to it (``label``: the
    component of each link's station, ``col``: its candidate)."""
    hit = np.zeros((n, size), dtype=bool)
    hit[label, col] = True
    return hit.sum(axis=0, dtype=np.int64)


def scan_forest(
    adj: sp.csr_matrix, idx: np.ndarray, pos: np.ndarray, avoid: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, int]:
    """A scan-first (breadth-first) spanning forest of the subgraph of ``adj`` on the nodes ``idx`` (``pos``: each
    node's position in ``idx``, -1 elsewhere), less the links of the forest ``avoid`` (a parent per position) where
    given: each position's parent (-1 for a root), its component, numbered in order of each component's lowest
    position, and the number of components. Each tree grows from the lowest position not yet reached, and the search
    stops once every position is reached: on a dense graph a few rows are read, not all of them."""
    m = len(idx)
    parent = np.full(m, -1, dtype=np.int64)
    label = np.full(m, -1, dtype=np.int64)
    ptr, ind = adj.indptr, adj.indices
    left, k = m, 0
    for root in range(m):
        if label[root] >= 0:
            continue
        label[root] = k
        left -= 1
        queue, head = [root], 0
        while head < len(queue) and left > 0:
            u = queue[head]
            head += 1
            nb = pos[ind[ptr[idx[u]] : ptr[idx[u] + 1]]]
            nb = nb[nb >= 0]
            if avoid is not None:
                nb = nb[(nb != avoid[u]) & (avoid[nb] != u)]
            new = nb[label[nb] < 0]
            label[new] = k
            parent[new] = u
            left -= new.size
            queue += new.tolist()
        k += 1
    return parent, label, k


def certificate(adj: sp.csr_matrix, idx: np.ndarray, links: _Links) -> tuple[list[int], list[int]]:
    """A sparse subgraph of S's links (CSR lists, by position in S) with, for every station v, the components of S's
    graph without v: the forest ``links.tree`` and a scan-first forest of S's links less the first's (Cheriyan, Kao
    and Thurimella, "Scan-first search and sparse certificates: an improved parallel algorithm for k-vertex
    connectivity", SIAM J. Comput. 22(1):157-174, 1993; k = 2). :func:`_split` then walks at most 2 (n - 1) links,
    not the ones of a few hundred stations nearly all linked to each other (a plan on a fine floor grid)."""
    assert links.tree is not None and links.pos is not None
    first = links.tree
    second = scan_forest(adj, idx, links.pos, avoid=first)[0]
    child = [np.flatnonzero(f >= 0) for f in (first, second)]
    r = np.concatenate([child[0], first[child[0]], child[1], second[child[1]]])
    c = np.concatenate([first[child[0]], child[0], second[child[1]], child[1]])
    order = np.lexsort((c, r))
    ptr = np.concatenate([[0], np.cumsum(np.bincount(r, minlength=len(idx)))])
    return ptr.tolist(), c[order].tolist()


def _components(n: int, ptr: list[int], ind: list[int]) -> tuple[int, np.ndarray]:
    """The number of components of the graph of ``n`` nodes given as CSR lists, and each node's label (in order of
    each component's lowest node): a depth-first pass on Python lists, faster than scipy for a plan's few."""
    label = [-1] * n
    k = 0
    for root in range(n):
        if label[root] >= 0:
            continue
        label[root] = k
        stack = [root]
        while stack:
            v = stack.pop()
            for w in ind[ptr[v] : ptr[v + 1]]:
                if label[w] < 0:
                    label[w] = k
                    stack.append(w)
        k += 1
    return k, np.array(label, dtype=np.int64)


def _split(sub: tuple[list[int], list[int]]) -> np.ndarray:
    """Components added to its own component by removing each node (-1 for an isolated node): one iterative
    articulation-point pass (Hopcroft-Tarjan), O(nodes + links). ``sub``: the graph as CSR lists (indptr, indices)."""
    ptr, ind = sub
    n = len(ptr) - 1
    disc, low, out = [-1] * n, [0] * n, [0] * n
    clock = 0
    for root in range(n):
        if disc[root] >= 0:
            continue
        disc[root] = low[root] = clock
        clock += 1
        children = 0
        stack = [(root, -1, ptr[root])]
        while stack:
            v, parent, i = stack[-1]
            if i < ptr[v + 1]:
                stack[-1] = (v, parent, i + 1)
                w = ind[i]
                if disc[w] < 0:
                    disc[w] = low[w] = clock
                    clock += 1
                    stack.append((w, v, ptr[w]))
                    children += v == root
                elif w != parent and disc[w] < low[v]:
                    low[v] = disc[w]
                continue
            stack.pop()
            if parent >= 0:
                low[parent] = min(low[parent], low[v])
                if parent != root and low[v] >= disc[parent]:
                    out[parent] += 1
        out[root] = children - 1
    return np.array(out, dtype=np.int64)


def unlinked(n: int) -> tuple[sp.csr_matrix, tuple[str, ...]]:
    """The links and groups that make :func:`shrink` a plain cover search: no links, each of the ``n`` candidates its
    own group, so any cover is "connected"."""
    return sp.csr_matrix((n, n), dtype=bool), tuple(str(i) for i in range(n))


def shrink(
    a: sp.csr_matrix,
    adj: sp.csr_matrix,
    groups: Sequence[Hashable],
    plan: Sequence[int],
    moves: int = 5000,
    floor: int = 1,
    seed: int = 0,
    tabu: int = 2,
    deadline: float = math.inf,
) -> Shrunk:
    """The smallest connected cover found from ``plan`` within ``moves`` moves (module docstring), ``plan`` itself when
    none smaller is found. ``a``: C x T boolean coverage (the targets to cover are those ``plan`` covers); ``adj``: C x
    C symmetric overlap adjacency, links within a group only; ``moves``: the move budget (0: ``plan`` as it is);
    ``floor``: stop at this many stations (a proven lower bound); ``tabu``: moves a station added may not be removed;
    ``deadline``: the user's wall-clock cap as a ``time.perf_counter()`` instant, looked at every :data:`_CLOCK_EVERY`
    moves.
    """
    best = tuple(sorted(int(i) for i in plan))
    a = a.astype(np.float64).tocsr()
    adj = adj.astype(bool).tocsr()
    need = np.asarray(a[list(best)].sum(axis=0)).ravel() > 0
    if moves <= 0 or len(best) <= max(floor, 1):
        return Shrunk(best, len(best), 0)
    st = _State(a, adj, group_ids(groups), need, best)
    rng = np.random.default_rng(seed)
    until = np.zeros(a.shape[0], dtype=np.int64)  # move before which a station added may not leave
    _drop(st, 0)
    history: list[tuple[int, int]] = []
    step = 0
    capped = math.isfinite(deadline)
    for step in range(1, moves + 1):
        if capped and step % _CLOCK_EVERY == 0 and time.perf_counter() >= deadline:
            break
        idx, parts = st.graph()[0], st.graph()[3]
        if parts == 0 and st.unseen().size == 0:
            best = tuple(int(i) for i in idx)
            history.append((step, len(best)))
            if len(best) <= max(floor, 1):
                break
            _drop(st, step)
            continue
        cost = st.removal_cost()
        free = np.where(until[idx] > step, np.inf, cost)
        st.flip(int(idx[_first(free if np.isfinite(free).any() else cost, st.stamp[idx])]), step)
        c, parts = _pick_add(st, rng)
        st.flip(c, step)
        until[c] = step + tabu + 1
        st.weight[st.unseen()] += 1.0
        if parts > 0:
            st.w_link += 1.0
    return Shrunk(best, len(plan), step, tuple(history))


def _first(key: np.ndarray, stamp: np.ndarray) -> int:
    """Position of the least ``key``; ties to the least ``stamp`` (longest unchanged), then the lowest index."""
    return int(np.lexsort((stamp, key))[0])


def _drop(st: _State, step: int) -> None:
    """Drop the station of least removal cost (ties: longest unchanged, then lowest index): S one smaller."""
    idx = st.graph()[0]
    st.flip(int(idx[_first(st.removal_cost(), st.stamp[idx])]), step)


def _pick_add(st: _State, rng: np.random.Generator) -> tuple[int, int]:
    """The candidate to add, and the parts S will be in: best score among the seers of one drawn unseen target and the
    candidates linked to two parts of S, allowed by configuration checking (all of them when none is)."""
    idx, _, label, parts, touched = st.graph()
    unseen = st.unseen()
    pool: list[np.ndarray] = []
    if unseen.size:
        t = int(unseen[rng.integers(unseen.size)])
        pool.append(st.at.indices[st.at.indptr[t] : st.at.indptr[t + 1]])
    if parts > 0:
        pool.append(np.flatnonzero(touched >= 2))
    cand = np.unique(np.concatenate(pool)) if pool else np.zeros(0, dtype=np.int64)
    cand = cand[~st.in_s[cand]]
    allowed = cand[st.conf[cand]]
    cand = allowed if allowed.size else cand
    if cand.size == 0:  # a cover in parts no one candidate links: a step of the shortest chain between parts
        gid = st.gid[idx]
        pairs = np.unique(np.stack([gid, label]), axis=1)  # (group, component), sorted by group
        g = pairs[0][np.flatnonzero(np.diff(pairs[0]) == 0)[0]]  # the first group in two or more parts
        first = label[np.flatnonzero(gid == g)[0]]
        wanted = np.zeros(st.a.shape[0], dtype=bool)
        wanted[idx[(gid == g) & (label != first)]] = True
        path = path_to_nearest(st.adj.astype(np.float64), idx[label == first], wanted)
        return (int(path[-1]) if path else int(np.flatnonzero(~st.in_s)[0])), parts
    score, change = st.add_score(cand)
    k = _first(-score, st.stamp[cand])
    return int(cand[k]), parts + int(change[k])
