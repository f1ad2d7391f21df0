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

from planner.coverage.gram import filtered_gram


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
    """
    a = a.astype(np.int64).tocsr()
    size = np.diff(a.indptr)
    # only the pairs (i, j) where j sees everything i sees: |i & j| == |i|, built in row blocks
    inter = filtered_gram(a, None, lambda i, j, v: np.abs(v - size[i]) < 0.5)
    order = sorted(range(a.shape[0]), key=lambda i: (-size[i], cost[i], i))
    removed = np.zeros(a.shape[0], dtype=bool)
    kept_rank: dict[int, int] = {}
    for rank, i in enumerate(order):
        if size[i] == 0 and (adj is None or _no_bridge(adj, i, removed, kept_rank, cost, groups)):
            removed[i] = True  # covers nothing: dropped unless it may be the only link between others
            continue
        row = inter.indices[inter.indptr[i]:inter.indptr[i + 1]]
        vals = inter.data[inter.indptr[i]:inter.indptr[i + 1]]
        for j in row[(vals == size[i]) & (row != i)]:
            if removed[j] or j not in kept_rank or cost[j] > cost[i]:
                continue
            if groups is not None and groups[j] != groups[i]:
                continue
            if adj is not None and not _links_cover(adj, i, j):
                continue
            removed[i] = True
            break
        if not removed[i]:
            kept_rank[i] = rank
    return removed


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
    ni = set(adj.indices[adj.indptr[i]:adj.indptr[i + 1]].tolist()) - {j}
    nj = set(adj.indices[adj.indptr[j]:adj.indptr[j + 1]].tolist())
    return ni <= nj


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
