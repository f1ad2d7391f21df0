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

A move costs O(targets and links of the two stations it flips, and the seers of the targets they leave or see) plus one
articulation pass on S's links: :meth:`_State.flip` keeps each target's count and the sum of its seers in S (so the
only seer of a target is known), each station's loss, each candidate's gain as a sum of offsets of its unseen targets
and their count (a weight rise is one tick added to every unseen target), the links inside S, how many of S's stations each
candidate is linked to, and the few candidates configuration checking bars. The graph steps are in
:mod:`planner.solve.local_moves`; where S's stations are densely linked to each other (a floor grid's plan links nearly
every pair), the components come from a scan-first forest and the articulation pass walks a sparse certificate of two
such forests. Every count is a whole number, so the scores are the ones recomputed from scratch, move for move. Ties
go to the candidate unchanged longest, then to the lowest index, and draws to a generator of fixed seed: the result
depends only on the input, ``moves`` and ``seed`` (no clock).
"""

from __future__ import annotations

import bisect
import math
import time
from collections.abc import Hashable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from planner.coverage.overlap import group_ids
from planner.solve.connectivity import path_to_nearest
from planner.solve.local_moves import Graph, Links, certificate, distinct, first_of, gather, scan_forest, walk

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


class _State:
    """The chosen set S with its target counts, weights, scores, links, components and configuration flags, each kept
    up to date by :meth:`flip` (a move reads and writes the rows of the few stations it touches, not all of S's)."""

    def __init__(
        self, a: sp.csr_matrix, adj: sp.csr_matrix, gid: np.ndarray, need: np.ndarray, chosen: Sequence[int]
    ) -> None:
        if not a.has_canonical_format:  # a target listed twice in a row counts once
            a = a.copy()
            a.sum_duplicates()
        self.a, self.at, self.adj, self.gid = a, a.T.tocsr(), adj, gid
        self.a_len, self.at_len = np.diff(a.indptr), np.diff(self.at.indptr)  # targets per candidate, seers per target
        n = a.shape[0]
        self.weight = need.astype(np.float64)
        self.need = need
        self.in_s = np.zeros(n, dtype=bool)
        self.members: list[int] = []  # S, ascending
        self.barred: dict[int, int] = {}  # the candidates configuration checking bars, and the flip that barred each
        self.flips = 0
        self.last = np.zeros(a.shape[1], dtype=np.int64)  # each target's last flip of a seer
        self.mark = np.zeros(n, dtype=bool)  # scratch, all False between uses
        self.label_of, self.links_to = np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64)  # scratch
        self.w_link = 1.0
        self.stamp = np.zeros(n, dtype=np.int64)  # move of each candidate's last change
        self.cnt = np.zeros(a.shape[1], dtype=np.int64)  # stations of S seeing each target
        self.own = np.zeros(a.shape[1], dtype=np.int64)  # the sum of their indices: the one seer where cnt is 1
        self.loss = np.zeros(n, dtype=np.float64)  # the weight of the targets only this station of S sees
        self.near = np.zeros(n, dtype=np.int64)  # how many stations of S each candidate is linked to
        self.groups = np.zeros(int(gid.max(initial=-1)) + 1, dtype=np.int64)  # stations of S in each group
        self.nbr: dict[int, set[int]] = {}  # each station's linked stations in S
        self._graph: Graph | None = None
        self._unseen: np.ndarray | None = None
        self.tick = 0  # weight rises so far: an unseen target's weight is its offset plus this
        self.offset = np.zeros(a.shape[1], dtype=np.int64)
        self.unseen_sum = np.zeros(n, dtype=np.int64)  # per candidate: the sum of its unseen targets' offsets
        self.unseen_count = np.zeros(n, dtype=np.int64)  # and their count
        self._pending: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []  # targets, offsets and signs to apply
        self._tracked = False
        self.open = np.zeros(a.shape[1], dtype=bool)  # the targets to cover that S leaves unseen (once tracked)
        for c in dict.fromkeys(int(c) for c in chosen):
            self.flip(c, 0)
        self.barred.clear()
        unseen = self.unseen()
        self._tracked = True
        self._unseen_by(unseen, 1)

    def _targets(self, c: int) -> np.ndarray:
        return self.a.indices[self.a.indptr[c] : self.a.indptr[c + 1]]

    def unseen(self) -> np.ndarray:
        """The targets to cover that S leaves unseen, ascending."""
        if self._unseen is None:
            self._unseen = np.flatnonzero(self.open) if self._tracked else np.flatnonzero(self.need & (self.cnt == 0))
        return self._unseen

    def flip(self, c: int, step: int) -> None:
        """Add c to S or remove it at move ``step``; the candidates sharing a target with c may come back."""
        self.stamp[c] = step
        t = self._targets(c)
        row = self.adj.indices[self.adj.indptr[c] : self.adj.indptr[c + 1]]
        cnt = self.cnt[t]
        before = self._graph
        if self.in_s[c]:
            two = t[cnt == 2]  # the other seer becomes the only one
            np.add.at(self.loss, self.own[two] - c, self.weight[two])
            self.cnt[t] = cnt - 1
            self.own[t] -= c
            self._unseen_by(t[(cnt == 1) & self.need[t]], 1)
            self.loss[c] = 0.0
            self.near[row] -= 1
            self.groups[self.gid[c]] -= 1
            for w in self.nbr.pop(c):
                self.nbr[w].discard(c)
        else:
            one = t[cnt == 1]  # its only seer shares it now
            np.subtract.at(self.loss, self.own[one], self.weight[one])
            self.loss[c] = self.weight[t[cnt == 0]].sum()
            self.cnt[t] = cnt + 1
            self.own[t] += c
            self._unseen_by(t[(cnt == 0) & self.need[t]], -1)
            self.near[row] += 1
            self.groups[self.gid[c]] += 1
            linked = set(row[self.in_s[row]].tolist())
            self.nbr[c] = linked
            for w in linked:
                self.nbr[w].add(c)
        self.in_s[c] = not self.in_s[c]
        if self.in_s[c]:
            bisect.insort(self.members, c)
        else:
            self.members.remove(c)
        self.flips += 1
        self.last[t] = self.flips
        if self.in_s[c]:
            self.barred.pop(c, None)
        else:
            self.barred[c] = self.flips
        self._unseen = None
        self._graph = None if self.in_s[c] or before is None else before.without(c, self.groups)

    def _unseen_by(self, t: np.ndarray, sign: int) -> None:
        """Targets ``t`` that S leaves unseen from now (``sign`` 1) or sees from now (-1): their seers' sums of offsets
        and counts, from which :meth:`gains` reads any candidate's gain, are updated when next read (one gather for
        the few targets of a move's two flips)."""
        if not self._tracked or t.size == 0:
            return
        self.open[t] = sign > 0
        if sign > 0:
            self.offset[t] = self.weight[t].astype(np.int64) - self.tick
        self._pending.append((t, sign * self.offset[t], np.full(t.size, sign, dtype=np.int64)))

    def gains(self, cand: np.ndarray | None = None) -> np.ndarray:
        """The weight of the unseen targets each candidate (of ``cand``; all where None) sees: the sum of their offsets
        plus the weight rises since, times their count (whole numbers: the sum of their weights, exactly)."""
        if self._pending:
            t, value, sign = (np.concatenate(x) for x in zip(*self._pending))
            self._pending.clear()
            row, col = gather(self.at, t)
            np.add.at(self.unseen_sum, col, value[row])
            np.add.at(self.unseen_count, col, sign[row])
        if cand is None:
            return (self.unseen_sum + self.tick * self.unseen_count).astype(np.float64)
        return (self.unseen_sum[cand] + self.tick * self.unseen_count[cand]).astype(np.float64)

    def bump(self) -> None:
        """The weights of the unseen targets grow by one."""
        self.weight[self.unseen()] += 1.0
        self.tick += 1

    def allowed(self, cand: np.ndarray) -> np.ndarray:
        """Configuration checking for ``cand`` (ascending): False for a candidate removed and not changed since, none
        sharing a target with it flipped after (each target's last flip is kept, so only the few barred candidates
        are looked at, when asked)."""
        ok = np.ones(len(cand), dtype=bool)
        if not self.barred:
            return ok
        who = np.fromiter(self.barred, dtype=np.int64, count=len(self.barred))
        when = np.fromiter(self.barred.values(), dtype=np.int64, count=len(who))
        where, col = gather(self.a, who)
        last = np.zeros(len(who), dtype=np.int64)
        np.maximum.at(last, where, self.last[col])
        for c in who[last > when].tolist():  # a candidate sharing a target flipped since: free for good
            del self.barred[c]
        still = who[last <= when]
        k = np.searchsorted(cand, still)
        inside = k < len(cand)
        k = k[inside]
        ok[k[cand[k] == still[inside]]] = False
        return ok

    def graph(self) -> Graph:
        """S's components (:class:`Graph`), from its links kept by :meth:`flip`; where S's stations have more than
        ``_DENSE`` links inside S each, from a scan-first forest that stops once every station is reached."""
        if self._graph is None:
            idx = np.array(self.members, dtype=np.int64)
            links = int(self.near[idx].sum())
            if links > _DENSE * len(idx):
                pos = np.full(self.a.shape[0], -1, dtype=np.int64)
                pos[idx] = np.arange(len(idx))
                parent, label, n = scan_forest(self.adj, idx, pos)
                self._graph = Graph(idx=idx, links=Links(tree=parent, pos=pos), label=label, n=n, groups=self.groups)
            else:
                where = {c: i for i, c in enumerate(self.members)}
                sub = [[where[w] for w in self.nbr[c]] for c in self.members]
                n, walked, out = walk(sub)
                self._graph = Graph(idx=idx, links=Links(lists=sub), label=np.array(walked), n=n, groups=self.groups)
                self._graph.split = np.array(out, dtype=np.int64)
        return self._graph

    def touched(self, cand: np.ndarray | None = None) -> np.ndarray:
        """How many of S's components each candidate (of ``cand``, ascending; all where None) is linked to."""
        g = self.graph()
        cand = np.arange(self.a.shape[0]) if cand is None else cand
        out = (self.near[cand] > 0).astype(np.int64)  # S in one component per group: linked or not
        if g.parts > 0:  # else linked to the largest component where it has more links to S than to the others
            self.bridging()
            assert g.linked is not None
            row, col, lab = g.linked
            self.mark[cand] = True
            keep = self.mark[col]
            self.mark[cand] = False
            at = np.searchsorted(cand, col[keep])
            pairs = distinct(lab[keep] * len(cand) + at)  # distinct (component, candidate)
            links = np.bincount(at, minlength=len(cand))
            out = (self.near[cand] > links) + np.bincount(pairs % len(cand), minlength=len(cand))
        return out

    def bridging(self) -> np.ndarray:
        """The candidates linked to two or more of S's components, ascending (S in pieces). Only the links of the
        components but the largest are gathered: such a candidate is linked to one of them, and it is linked to the
        largest where it has more links to S than to them."""
        g = self.graph()
        if g.bridging is None:
            big = g.label != int(np.argmax(np.bincount(g.label)))
            row, col = gather(self.adj, g.idx[big])
            lab = g.label[big][row]
            self.label_of[col] = lab  # one of each candidate's components: a link to another is a second
            two = col[lab != self.label_of[col]]
            np.add.at(self.links_to, col, 1)
            also = col[self.near[col] > self.links_to[col]]  # and linked to the largest
            self.links_to[col] = 0
            g.linked = (row, col, lab)
            g.bridging = distinct(np.concatenate([two, also]))
        return g.bridging

    def removal_cost(self) -> np.ndarray:
        """loss(s) + w_link * split(s) for each station of S (order of ``graph().idx``)."""
        g = self.graph()
        if g.links is None:  # a graph kept from before a removal: built again, with its links
            self._graph = None
            g = self.graph()
        if g.split is None:
            assert g.links is not None and g.links.tree is not None
            g.split = np.array(walk(certificate(self.adj, g.idx, g.links))[2], dtype=np.int64)
        split = np.where(self.groups[self.gid[g.idx]] == 1, 0, g.split)  # the group leaves S, its parts stay 0
        return self.loss[g.idx] + self.w_link * split

    def add_score(self, cand: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """gain(c) - w_link * (parts change), and the parts change, of candidates ``cand`` joining S. gain(c): the weight
        of the unseen targets c sees, from its sum of their offsets and their count kept by :meth:`flip` (whole
        numbers: the same value as summing the weights)."""
        gain = self.gains(cand)
        change = np.where(self.groups[self.gid[cand]] > 0, 1 - self.touched(cand), 0)
        return gain - self.w_link * change, change


#: S's links are walked whole while its stations have at most this many links inside S each
_DENSE = 64


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
        idx, parts = st.graph().idx, st.graph().parts
        if parts == 0 and st.unseen().size == 0:
            best = tuple(int(i) for i in idx)
            history.append((step, len(best)))
            if len(best) <= max(floor, 1):
                break
            _drop(st, step)
            continue
        cost = st.removal_cost()
        free = np.where(until[idx] > step, np.inf, cost)
        st.flip(int(idx[first_of(free if np.isfinite(free).any() else cost, st.stamp[idx])]), step)
        c, parts = _pick_add(st, rng)
        if c >= 0:
            st.flip(c, step)
            until[c] = step + tabu + 1
        st.bump()
        if parts > 0:
            st.w_link += 1.0
    return Shrunk(best, len(plan), step, tuple(history))


def _drop(st: _State, step: int) -> None:
    """Drop the station of least removal cost (ties: longest unchanged, then lowest index): S one smaller."""
    idx = st.graph().idx
    st.flip(int(idx[first_of(st.removal_cost(), st.stamp[idx])]), step)


def _pick_add(st: _State, rng: np.random.Generator) -> tuple[int, int]:
    """The candidate to add, and the parts S will be in: best score among the seers of one drawn unseen target and the
    candidates linked to two parts of S, allowed by configuration checking (all of them when none is); -1 where the
    removal left a connected cover (a start in pieces can have a station no part needs)."""
    g = st.graph()
    idx, label, parts = g.idx, g.label, g.parts
    unseen = st.unseen()
    pool: list[np.ndarray] = []
    if unseen.size:
        t = int(unseen[rng.integers(unseen.size)])
        pool.append(st.at.indices[st.at.indptr[t] : st.at.indptr[t + 1]])
    if parts > 0:
        pool.append(st.bridging())
    cand = distinct(np.concatenate(pool)) if pool else np.zeros(0, dtype=np.int64)
    cand = cand[~st.in_s[cand]]
    allowed = cand[st.allowed(cand)]
    cand = allowed if allowed.size else cand
    if cand.size == 0 and parts == 0:  # the removal left a connected cover: nothing to add (-1)
        return -1, 0
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
    k = first_of(-score, st.stamp[cand])
    return int(cand[k]), parts + int(change[k])
