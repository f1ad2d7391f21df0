"""Presolve of the cover: dominated candidates, duplicate targets, forced candidates.

Dominance is the trap here: dropping a candidate whose coverage is a subset of
another's is valid for the plain cover only. Under the registration
constraint a dominated candidate can be the only bridge between two others,
so there a candidate i is dropped only when some j of the same group covers
everything i covers AND is linked to every station i is linked to (then j can
take i's place in any connected plan).
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp



@dataclass(frozen=True)
class PresolveReport:
    candidates_in: int
    targets_in: int
    dominated: int = 0
    duplicate_targets: int = 0
    forced: int = 0
    kept_candidates: tuple[int, ...] = ()
    kept_targets: tuple[int, ...] = ()
    forced_candidates: tuple[int, ...] = field(default=())

    def to_dict(self) -> dict[str, int]:
        return {"candidates_in": self.candidates_in, "targets_in": self.targets_in, "dominated_removed": self.dominated,
                "duplicate_targets_removed": self.duplicate_targets, "forced": self.forced,
                "candidates_out": len(self.kept_candidates), "targets_out": len(self.kept_targets)}


def dominated(a: sp.csr_matrix, cost: np.ndarray, adj: sp.csr_matrix | None = None,
              groups: Sequence[Hashable] | None = None) -> np.ndarray:
    """Mask of candidates that another candidate can always replace (see the module docstring).

    Candidates are considered from the largest coverage down; among identical
    ones the lowest index stays. A candidate is only ever replaced by one that
    stays, so removing them all at once is sound.

    No candidate x candidate product is formed: candidate i can only be replaced by a *kept* candidate that
    sees every piece of i, and such a candidate sees i's piece with the fewest kept candidates. So each
    piece keeps the list of kept candidates that see it, and i is checked against the shortest of its
    pieces' lists only (a scratch mark of i's pieces, then |C(j) & C(i)| = |C(i)| for each j of that list).
    Work is the sum of those checks, in proportion to the pairs of the coverage matrix when few candidates
    stay (on a 1-m grid over a building of small rooms: 25 kept of 35,729).
    """
    a = a.astype(bool).tocsr()
    a.sort_indices()
    n, n_t = a.shape
    size = np.diff(a.indptr)
    cost = np.asarray(cost, float)
    order = np.lexsort((np.arange(n), cost, -size))
    removed = np.zeros(n, dtype=bool)
    kept_rank: dict[int, int] = {}
    kept_by_piece: list[list[int]] = [[] for _ in range(n_t)]
    mark = np.zeros(n_t, dtype=np.int32)  # scratch: the pieces of the candidate under test
    near = np.zeros(n, dtype=np.int32)  # scratch: the overlap neighbours of the candidate under test
    adj = None if adj is None else adj.astype(np.int32).tocsr()
    for rank, i in enumerate(order.tolist()):
        cols = a.indices[a.indptr[i]:a.indptr[i + 1]]
        if size[i] == 0:
            if adj is None or _no_bridge(adj, i, removed, kept_rank, cost, groups):
                removed[i] = True  # covers nothing: dropped unless it may be the only link between others
                continue
        elif _replaced(a, i, cols, kept_by_piece, mark, near, cost, adj, groups):
            removed[i] = True
            continue
        kept_rank[i] = rank
        for t in cols.tolist():
            kept_by_piece[t].append(i)
    return removed


def _replaced(a: sp.csr_matrix, i: int, cols: np.ndarray, kept_by_piece: list[list[int]], mark: np.ndarray,
              near: np.ndarray, cost: np.ndarray, adj: sp.csr_matrix | None, groups: Sequence[Hashable] | None) -> bool:
    """Whether a kept candidate, no dearer and of i's group (linked to all of i's links under ``adj``), sees
    every piece i sees."""
    lists = [kept_by_piece[t] for t in cols.tolist()]
    shortest = np.asarray(min(lists, key=len), dtype=np.int64)
    if shortest.size == 0:
        return False
    shortest = shortest[cost[shortest] <= cost[i]]
    if groups is not None:
        shortest = shortest[[groups[j] == groups[i] for j in shortest.tolist()]]
    if shortest.size == 0:
        return False
    mark[cols] = 1
    try:  # how many of i's pieces each j sees, in one sparse product
        seen = np.asarray(a[shortest].astype(np.int32) @ mark).ravel()
    finally:
        mark[cols] = 0
    inside = shortest[seen == cols.size]
    if adj is None or inside.size == 0:
        return inside.size > 0
    ni = adj.indices[adj.indptr[i]:adj.indptr[i + 1]]
    near[ni] = 1  # j must be linked to every neighbour of i but itself: |N(j) & N(i)| = |N(i)| - [j in N(i)]
    try:
        shared = np.asarray(adj[inside] @ near).ravel()
        return bool(np.any(shared == ni.size - near[inside]))
    finally:
        near[ni] = 0


def _no_bridge(adj: sp.csr_matrix, i: int, removed: np.ndarray, kept: dict[int, int], cost: np.ndarray,
               groups: Sequence[Hashable] | None) -> bool:
    """Whether a candidate covering nothing can go under the overlap rule: it has no neighbour, or a
    kept j of its group, no dearer, is linked to every neighbour of i (j then stands in for it)."""
    nb = adj.indices[adj.indptr[i]:adj.indptr[i + 1]]
    if nb.size == 0:
        return True
    v = int(nb[0])
    for j in [v, *adj.indices[adj.indptr[v]:adj.indptr[v + 1]].tolist()]:
        if j != i and not removed[j] and j in kept and cost[j] <= cost[i] and \
                (groups is None or groups[j] == groups[i]) and _links_cover(adj, i, j):
            return True
    return False


def _links_cover(adj: sp.csr_matrix, i: int, j: int) -> bool:
    """Every overlap neighbour of i (other than j) is a neighbour of j."""
    ni = adj.indices[adj.indptr[i]:adj.indptr[i + 1]]
    ni = ni[ni != j]
    nj = adj.indices[adj.indptr[j]:adj.indptr[j + 1]]
    return ni.size <= nj.size and bool(np.isin(ni, nj).all())


def duplicate_targets(by_target: sp.csr_matrix) -> np.ndarray:
    """Mask of targets whose candidate set repeats an earlier target's."""
    seen: set[bytes] = set()
    dup = np.zeros(by_target.shape[0], dtype=bool)
    for t in range(by_target.shape[0]):
        key = np.sort(by_target.indices[by_target.indptr[t]:by_target.indptr[t + 1]]).tobytes()
        if key in seen:
            dup[t] = True
        seen.add(key)
    return dup


def implied_targets(by_target: sp.csr_matrix) -> np.ndarray:
    """Mask of targets whose cover follows from another's: if every candidate that sees t' also sees t,
    covering t' covers t (valid for k = 1 in the single-precision mode). Duplicates keep the lowest index."""
    b = by_target.astype(np.int64).tocsr()
    size = np.diff(b.indptr)
    inter = (b @ b.T).tocsr()
    out = np.zeros(b.shape[0], dtype=bool)
    for t in range(b.shape[0]):
        row = inter.indices[inter.indptr[t]:inter.indptr[t + 1]]
        vals = inter.data[inter.indptr[t]:inter.indptr[t + 1]]
        sub = (vals == size[row]) & (row != t) & ((size[row] < size[t]) | (row < t))
        # a smaller-or-equal candidate set inside t's; equal sets: only the earlier one implies
        sub &= ~out[row] | (size[row] < size[t])
        if np.any(sub & (size[row] > 0)):
            out[t] = True
    return out


def forced(by_target: sp.csr_matrix, k: int) -> np.ndarray:
    """Candidates that must be chosen: the only k that see some target."""
    counts = np.diff(by_target.indptr)
    must = np.zeros(by_target.shape[1], dtype=bool)
    for t in np.flatnonzero(counts == k):
        must[by_target.indices[by_target.indptr[t]:by_target.indptr[t + 1]]] = True
    return must
