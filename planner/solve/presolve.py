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

from planner.coverage.overlap import group_ids
from planner.solve.lazy_links import LazyLinks


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


def presolve_order(a: sp.csr_matrix, cost: np.ndarray) -> np.ndarray:
    """The order :func:`dominated` considers candidates in: largest coverage first, then cheapest, then lowest index."""
    return np.lexsort((np.arange(a.shape[0]), np.asarray(cost, float), -np.diff(a.tocsr().indptr)))


def dominated(a: sp.csr_matrix, cost: np.ndarray, adj: sp.csr_matrix | LazyLinks | None = None,
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
    stay (on a 1-m grid over a building of small rooms: 25 kept of 35,729). ``adj`` may be a
    :class:`planner.solve.lazy_links.LazyLinks` formed in :func:`presolve_order`: rows are then formed as asked
    and those of dropped candidates let go.
    """
    a = a.astype(bool).tocsr()
    a.sort_indices()
    n, n_t = a.shape
    size = np.diff(a.indptr)
    cost = np.asarray(cost, float)
    order = presolve_order(a, cost)
    gid = np.zeros(n, dtype=np.int64) if groups is None else group_ids(groups)
    removed = np.zeros(n, dtype=bool)
    kept_rank: dict[int, int] = {}
    kept_by_piece: list[list[int]] = [[] for _ in range(n_t)]
    mark = np.zeros(n_t, dtype=np.int32)  # scratch: the pieces of the candidate under test
    near = np.zeros(n, dtype=np.int32)  # scratch: the overlap neighbours of the candidate under test
    if isinstance(adj, sp.spmatrix):
        adj = adj.astype(np.int32).tocsr()
    for rank, i in enumerate(order.tolist()):
        cols = a.indices[a.indptr[i]:a.indptr[i + 1]]
        if size[i] == 0:
            if adj is None or _no_bridge(adj, i, removed, kept_rank, cost, groups):
                removed[i] = True  # covers nothing: dropped unless it may be the only link between others
                _let_go(adj, i)
                continue
        elif _replaced(a, i, cols, kept_by_piece, mark, near, cost, adj, groups, gid):
            removed[i] = True
            _let_go(adj, i)
            continue
        kept_rank[i] = rank
        for t in cols.tolist():
            kept_by_piece[t].append(i)
    return removed


def _let_go(adj: sp.csr_matrix | LazyLinks | None, i: int) -> None:
    if isinstance(adj, LazyLinks):
        adj.drop(i)


def _nbrs(adj: sp.csr_matrix | LazyLinks, i: int) -> np.ndarray:
    """The overlap neighbours of i."""
    return adj.row(i) if isinstance(adj, LazyLinks) else adj.indices[adj.indptr[i]:adj.indptr[i + 1]]


def _segment_sums(values: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """The sums of consecutive runs of ``values`` of lengths ``sizes`` (0 for an empty run)."""
    out = np.zeros(sizes.size, dtype=np.int64)
    full = sizes > 0  # reduceat over the non-empty runs only (an empty one would take its next's first value)
    if full.any():
        out[full] = np.add.reduceat(values, (np.cumsum(sizes) - sizes)[full])
    return out


def _row_sums(indptr: np.ndarray, indices: np.ndarray, rows: np.ndarray, mark: np.ndarray) -> np.ndarray:
    """sum(mark[indices of row r]) for each r of ``rows`` of a CSR pattern, gathered in one pass."""
    starts = indptr[rows]
    sizes = indptr[rows + 1] - starts
    pos = np.repeat(starts - (np.cumsum(sizes) - sizes), sizes) + np.arange(int(sizes.sum()))
    return _segment_sums(mark[indices[pos]], sizes)


def _replaced(a: sp.csr_matrix, i: int, cols: np.ndarray, kept_by_piece: list[list[int]], mark: np.ndarray,
              near: np.ndarray, cost: np.ndarray, adj: sp.csr_matrix | LazyLinks | None,
              groups: Sequence[Hashable] | None, gid: np.ndarray) -> bool:
    """Whether a kept candidate, no dearer and of i's group (linked to all of i's links under ``adj``), sees
    every piece i sees."""
    lists = [kept_by_piece[t] for t in cols.tolist()]
    shortest = np.asarray(min(lists, key=len), dtype=np.int64)
    if shortest.size == 0:
        return False
    shortest = shortest[cost[shortest] <= cost[i]]
    if groups is not None:
        shortest = shortest[gid[shortest] == gid[i]]
    if shortest.size == 0:
        return False
    mark[cols] = 1
    try:  # how many of i's pieces each j sees: its row's marks summed, all rows at once
        seen = _row_sums(a.indptr, a.indices, shortest, mark)
    finally:
        mark[cols] = 0
    inside = shortest[seen == cols.size]
    if adj is None or inside.size == 0:
        return inside.size > 0
    ni = _nbrs(adj, i)
    near[ni] = 1  # j must be linked to every neighbour of i but itself: |N(j) & N(i)| = |N(i)| - [j in N(i)]
    try:
        if isinstance(adj, LazyLinks):  # kept rows are held: |N(j) & N(i)| for every j at once
            rows = [adj.row(j) for j in inside.tolist()]
            sizes = np.fromiter((r.size for r in rows), dtype=np.int64, count=len(rows))
            shared = _segment_sums(near[np.concatenate(rows)], sizes)
        else:
            shared = _row_sums(adj.indptr, adj.indices, inside, near)
        return bool(np.any(shared == ni.size - near[inside]))
    finally:
        near[ni] = 0


def _no_bridge(adj: sp.csr_matrix | LazyLinks, i: int, removed: np.ndarray, kept: dict[int, int], cost: np.ndarray,
               groups: Sequence[Hashable] | None) -> bool:
    """Whether a candidate covering nothing can go under the overlap rule: it has no neighbour, or a
    kept j of its group, no dearer, is linked to every neighbour of i (j then stands in for it)."""
    nb = _nbrs(adj, i)
    if nb.size == 0:
        return True
    v = int(nb[0])
    for j in [v, *_nbrs(adj, v).tolist()]:
        if j != i and not removed[j] and j in kept and cost[j] <= cost[i] and \
                (groups is None or groups[j] == groups[i]) and _links_cover(adj, i, j):
            return True
    return False


def _links_cover(adj: sp.csr_matrix | LazyLinks, i: int, j: int) -> bool:
    """Every overlap neighbour of i (other than j) is a neighbour of j."""
    ni = _nbrs(adj, i)
    ni = ni[ni != j]
    nj = _nbrs(adj, j)
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
