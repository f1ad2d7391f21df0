"""Presolve of the cover: dominated candidates, duplicate targets, forced candidates.

Dominance is the trap here: dropping a candidate whose coverage is a subset of another's is valid for the plain cover
only. Under the registration constraint a dominated candidate can be the only bridge between two others, so there a
candidate i is dropped only when some kept j of the same group covers everything i covers AND is linked to every
station i is linked to that was not dropped before i (then j can take i's place in any connected plan: see
:func:`dominated`).
"""

from __future__ import annotations

import functools
from collections.abc import Hashable, Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from planner.coverage.overlap import group_ids

#: how many neighbours of the candidate under test the replacers are tried on before all (:meth:`_Relation.covers`)
_PROBES = (16, 256)
#: replacers x neighbours up to which :meth:`_Relation.covers` tries all neighbours at once (no probes first)
_ONE_SHOT = 8_192
#: a relation among at most this many candidates is also held as bits
_BITS_MAX = 16_384


@dataclass(frozen=True, kw_only=True)
class PresolveReport:
    candidates_in: int
    targets_in: int
    dominated: int = 0
    duplicate_targets: int = 0
    forced: int = 0
    kept_candidates: tuple[int, ...] = ()
    kept_targets: tuple[int, ...] = ()
    forced_candidates: tuple[int, ...] = field(default=())
    #: seconds the presolve took, and the overlap links among the kept candidates (None: no overlap rule)
    time_s: float = 0.0
    links: int | None = None

    def to_dict(self) -> dict[str, int | float]:
        out: dict[str, int | float] = {
            "candidates_in": self.candidates_in,
            "targets_in": self.targets_in,
            "dominated_removed": self.dominated,
            "duplicate_targets_removed": self.duplicate_targets,
            "forced": self.forced,
            "candidates_out": len(self.kept_candidates),
            "targets_out": len(self.kept_targets),
            "time_s": round(self.time_s, 2),
        }
        if self.links is not None:
            out["links"] = self.links
        return out


def presolve_order(a: sp.csr_matrix, cost: np.ndarray) -> np.ndarray:
    """The order :func:`dominated` considers candidates in: largest coverage first, then cheapest, then lowest index."""
    return np.lexsort((np.arange(a.shape[0]), np.asarray(cost, float), -np.diff(a.tocsr().indptr)))


def dominated(
    a: sp.csr_matrix, cost: np.ndarray, adj: sp.csr_matrix | None = None, groups: Sequence[Hashable] | None = None
) -> np.ndarray:
    """Mask of candidates that another candidate can always replace (module docstring), considered from the largest
    coverage down (among identical ones the lowest index stays).

    Why only the neighbours not dropped before i count: replace the dropped candidates of an optimal connected plan by
    their replacers in this order; when i's turn comes the ones dropped before it are out of the plan already, so i's
    neighbours in the plan are among those j is linked to (a replacer is kept, never dropped). A candidate covering
    nothing goes when no neighbour of it is left, or for such a j.

    The replacers of i are the kept candidates, considered before it, of its group, no dearer, that see every piece i
    sees. Where the candidate x candidate product is cheap (:data:`PRODUCT_WORK`) those supersets are found for every
    i at once under the overlap rule, a block of rows at a time (:func:`_supersets`), and the walk in order only asks
    which of them are kept; else each piece keeps the list of kept candidates that see it and i is checked against
    the shortest of its pieces' lists only (work in proportion to the pairs of the coverage matrix when few candidates
    stay). Without the relation no walk is needed (:func:`_dominated_plain`). All give the same mask.
    """
    a = a.astype(bool).tocsr()
    a.sort_indices()
    n = a.shape[0]
    size = np.diff(a.indptr)
    cost = np.asarray(cost, float)
    order = presolve_order(a, cost)
    gid = np.zeros(n, dtype=np.int64) if groups is None else group_ids(groups)
    if adj is None:
        plain = _dominated_plain(a, size, cost, order, gid)
        if plain is not None:
            return plain
        return _dominated_by_pieces(a, size, cost, order, gid, None)
    rel = _Relation(adj)
    sup = _supersets(a, size, cost, gid, order)
    if sup is None:
        return _dominated_by_pieces(a, size, cost, order, gid, rel)
    ptr, js = sup
    removed = np.zeros(n, dtype=bool)
    kept = np.zeros(n, dtype=bool)
    for i in order.tolist():
        if size[i] == 0:
            if rel is None or _no_bridge(rel, i, removed, kept, cost, gid):
                removed[i] = True  # covers nothing: dropped unless it may be the only link between others
                continue
        elif ptr[i + 1] > ptr[i]:
            inside = js[ptr[i] : ptr[i + 1]]
            inside = inside[kept[inside]]
            if inside.size and (rel is None or rel.covers(inside, rel.row(i, removed))):
                removed[i] = True
                continue
        kept[i] = True
    return removed


#: the most multiply-adds (sum over pieces of their seers squared) for which :func:`dominated` forms the candidate x
#: candidate product (in blocks); beyond it, the walk over the pieces' lists of kept seers
PRODUCT_WORK = 300_000_000
#: multiply-adds per block of rows of that product (bounds its memory too)
_BLOCK_WORK = 2_000_000


def _supersets(
    a: sp.csr_matrix, size: np.ndarray, cost: np.ndarray, gid: np.ndarray, order: np.ndarray
) -> tuple[np.ndarray, np.ndarray] | None:
    """For every candidate i (CSR: ``js[ptr[i]:ptr[i + 1]]``, ascending) the candidates j that could replace it in
    :func:`dominated`: j sees every piece i sees, comes before i in ``order``, is no dearer and of i's group. None where
    the product would cost more than :data:`PRODUCT_WORK`."""
    n, n_t = a.shape
    deg = np.bincount(a.indices, minlength=n_t).astype(np.int64)
    if int((deg * deg).sum()) > PRODUCT_WORK:
        return None
    rank = np.empty(n, dtype=np.int64)
    rank[order] = np.arange(n)
    f = a.astype(np.int32)
    ft = f.T.tocsr()
    per_row = np.bincount(np.repeat(np.arange(n), size), weights=deg[a.indices], minlength=n)
    block = (np.cumsum(per_row) - per_row) // _BLOCK_WORK  # rows in blocks of about _BLOCK_WORK multiply-adds
    bounds = np.concatenate([[0], np.flatnonzero(np.diff(block)) + 1, [n]])
    rows, cols = [np.zeros(0, dtype=np.int64)], [np.zeros(0, dtype=np.int64)]
    for lo, hi in zip(bounds[:-1].tolist(), bounds[1:].tolist()):
        p = (f[lo:hi] @ ft).tocsr()
        r = np.repeat(np.arange(lo, hi), np.diff(p.indptr))
        c = p.indices.astype(np.int64)
        ok = (p.data == size[r]) & (rank[c] < rank[r]) & (cost[c] <= cost[r]) & (gid[c] == gid[r])
        rows.append(r[ok])
        cols.append(c[ok])
    r, c = np.concatenate(rows), np.concatenate(cols)
    by = np.lexsort((c, r))
    ptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(r, minlength=n), out=ptr[1:])
    return ptr, c[by]


#: the most bits (candidates x pieces) of the coverage matrix :func:`_dominated_plain` holds packed (32 MiB)
PLAIN_BITS = 2**28
#: (candidate, possible replacer) pairs :func:`_dominated_plain` tests at once (a few rows at a time; bounds memory)
_PLAIN_PAIRS = 1_000_000


def _dominated_plain(
    a: sp.csr_matrix, size: np.ndarray, cost: np.ndarray, order: np.ndarray, gid: np.ndarray
) -> np.ndarray | None:
    """:func:`dominated` without the relation, all candidates at once: i goes when it covers nothing or when *any*
    j before it in ``order``, no dearer, of its group, sees every piece it sees. Kept or not does not matter here: a
    dropped such j was dropped for a kept k before it, no dearer, of the group, seeing all j sees, and k replaces i
    (so the mask is the walk's). i is paired with the no dearer seers of its rarest piece (each piece's seers held by
    cost, so those are a prefix), and the pairs are thinned one piece of i at a time, rarest first, in the coverage
    matrix held as bits. None where those bits would pass :data:`PLAIN_BITS`."""
    n, n_t = a.shape
    if n * n_t > PLAIN_BITS:
        return None
    rank = np.empty(n, dtype=np.int64)
    rank[order] = np.arange(n)
    by_cost = np.argsort(cost, kind="stable")
    seers = a[by_cost].T.tocsr()  # each piece's seers, by their place in by_cost
    seers.sort_indices()
    deg = np.diff(seers.indptr)
    key = np.repeat(np.arange(n_t, dtype=np.int64), deg) * n + seers.indices  # ascending
    row = np.repeat(np.arange(n), size)
    piece = a.indices[np.lexsort((a.indices, deg[a.indices], row))]  # each row's pieces, rarest first
    pattern = sp.csr_matrix((np.ones(a.nnz, dtype=bool), a.indices, a.indptr), shape=a.shape)  # stored entries
    bits = np.zeros((n, (n_t + 7) // 8), dtype=np.uint8)
    step = max(1, 2**22 // max(n_t, 1))
    for lo in range(0, n, step):  # packed a block of rows at a time
        bits[lo : lo + step] = np.packbits(pattern[lo : lo + step].toarray(), axis=1, bitorder="little")
    removed = size == 0
    todo = np.flatnonzero(~removed)
    first = piece[a.indptr[todo]]
    reach = np.searchsorted(cost[by_cost], cost[todo], side="right")  # places of the no dearer: below reach
    count = np.searchsorted(key, first * n + reach, side="left") - seers.indptr[first]
    many = np.cumsum(count) // _PLAIN_PAIRS  # rows in chunks of about _PLAIN_PAIRS pairs
    for chunk in np.split(np.arange(todo.size), np.flatnonzero(np.diff(many)) + 1):
        i = np.repeat(todo[chunk], count[chunk])
        j = by_cost[seers.indices[_ranges(seers.indptr[first[chunk]], count[chunk])]]
        ok = (rank[j] < rank[i]) & (gid[j] == gid[i])
        i, j = i[ok], j[ok]
        k = 1  # j sees i's piece 0
        while i.size:
            removed[i[size[i] <= k]] = True  # j sees every piece of i
            left = (size[i] > k) & ~removed[i]
            i, j = i[left], j[left]
            t = piece[a.indptr[i] + k]
            sees = (bits[j, t >> 3] >> (t & 7).astype(np.uint8)) & 1 == 1
            i, j = i[sees], j[sees]
            k += 1
    return removed


def _ranges(starts: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """The positions starts[0] .. starts[0] + sizes[0] - 1, then those of the next range, and so on."""
    return np.repeat(starts - (np.cumsum(sizes) - sizes), sizes) + np.arange(int(sizes.sum()))


def _dominated_by_pieces(
    a: sp.csr_matrix, size: np.ndarray, cost: np.ndarray, order: np.ndarray, gid: np.ndarray, rel: _Relation | None
) -> np.ndarray:
    """:func:`dominated` by the pieces' lists of kept seers (no candidate x candidate product)."""
    n, n_t = a.shape
    removed = np.zeros(n, dtype=bool)
    kept = np.zeros(n, dtype=bool)
    kept_by_piece: list[list[int]] = [[] for _ in range(n_t)]
    mark = np.zeros(n_t, dtype=np.int32)  # scratch: the pieces of the candidate under test
    for i in order.tolist():
        cols = a.indices[a.indptr[i] : a.indptr[i + 1]]
        if size[i] == 0:
            if rel is None or _no_bridge(rel, i, removed, kept, cost, gid):
                removed[i] = True  # covers nothing: dropped unless it may be the only link between others
                continue
        elif _replaced(a, i, cols, kept_by_piece, mark, cost, rel, removed, gid):
            removed[i] = True
            continue
        kept[i] = True
        for t in cols.tolist():
            kept_by_piece[t].append(i)
    return removed


def _row_sums(indptr: np.ndarray, indices: np.ndarray, rows: np.ndarray, mark: np.ndarray) -> np.ndarray:
    """sum(mark[indices of row r]) for each r of ``rows`` of a CSR pattern, gathered in one pass (0 for an empty row)."""
    starts = indptr[rows]
    sizes = indptr[rows + 1] - starts
    pos = np.repeat(starts - (np.cumsum(sizes) - sizes), sizes) + np.arange(int(sizes.sum()))
    out = np.zeros(sizes.size, dtype=np.int64)
    full = sizes > 0  # reduceat over the non-empty rows only (an empty one would take its next's first value)
    if full.any():
        out[full] = np.add.reduceat(mark[indices[pos]], (np.cumsum(sizes) - sizes)[full])
    return out


def _replaced(
    a: sp.csr_matrix,
    i: int,
    cols: np.ndarray,
    kept_by_piece: list[list[int]],
    mark: np.ndarray,
    cost: np.ndarray,
    rel: _Relation | None,
    removed: np.ndarray,
    gid: np.ndarray,
) -> bool:
    """Whether a kept candidate of i's group, no dearer (under ``rel``, linked to all of i's links not dropped so
    far), sees every piece i sees."""
    lists = [kept_by_piece[t] for t in cols.tolist()]
    shortest = np.asarray(min(lists, key=len), dtype=np.int64)
    if shortest.size == 0:
        return False
    shortest = shortest[(cost[shortest] <= cost[i]) & (gid[shortest] == gid[i])]
    if shortest.size == 0:
        return False
    mark[cols] = 1
    try:  # how many of i's pieces each j sees: its row's marks summed, all rows at once
        seen = _row_sums(a.indptr, a.indices, shortest, mark)
    finally:
        mark[cols] = 0
    inside = shortest[seen == cols.size]
    if rel is None or inside.size == 0:
        return inside.size > 0
    return rel.covers(inside, rel.row(i, removed))


def _no_bridge(
    rel: _Relation, i: int, removed: np.ndarray, kept: np.ndarray, cost: np.ndarray, gid: np.ndarray
) -> bool:
    """Whether a candidate covering nothing can go under the overlap rule: no neighbour of it is left, or a kept j of
    its group, no dearer, is linked to every neighbour of i left (j then stands in for it)."""
    nb = rel.row(i, removed)
    if nb.size == 0:
        return True
    v = int(nb[0])  # j is v or a neighbour of v
    js = np.append(rel.row(v), v)
    js = js[(js != i) & kept[js] & (cost[js] <= cost[i]) & (gid[js] == gid[i])]
    return rel.covers(js, nb)


class _Relation:
    """The overlap relation of :func:`dominated`: CSR rows and, among at most ``_BITS_MAX`` candidates, rows of bits
    too (n^2 / 8 bytes: 32 MiB at 16,384)."""

    def __init__(self, adj: sp.csr_matrix) -> None:
        self.adj = adj.astype(np.int32).tocsr()
        n = self.adj.shape[0]
        self._deg = np.diff(self.adj.indptr)
        self._near = np.zeros(n, dtype=np.int32)  # scratch: the neighbours of the candidate under test
        self.bits: np.ndarray | None = None
        if n <= _BITS_MAX:
            self.bits = np.zeros((n, (n + 7) // 8), dtype=np.uint8)
            step = max(1, 2**22 // max(n, 1))
            for lo in range(0, n, step):  # packed a block of rows at a time
                dense = self.adj[lo : lo + step].toarray() != 0
                self.bits[lo : lo + step] = np.packbits(dense, axis=1, bitorder="little")

    def row(self, i: int, removed: np.ndarray | None = None) -> np.ndarray:
        """The neighbours of i (those not ``removed``)."""
        nb = self.adj.indices[self.adj.indptr[i] : self.adj.indptr[i + 1]]
        return nb if removed is None else nb[~removed[nb]]

    def covers(self, js: np.ndarray, nb: np.ndarray) -> bool:
        """Whether some j of ``js`` is linked to every candidate of ``nb`` but itself. With bits, most j fail on a few
        of nb: all are tried on ``_PROBES`` of nb spread over it first, and only those that pass on the rest. Else |N(j)
        & nb| = |nb| - [j in nb], summed over the rows of js."""
        ptr = self.adj.indptr
        js = js[self._deg[js] >= nb.size - 1]
        if js.size == 0:
            return False
        if self.bits is not None:
            if js.size * nb.size <= _ONE_SHOT:  # few pairs: all at once
                got = (self.bits[js[:, None], nb >> 3] >> (nb & 7).astype(np.uint8)) & 1
                return bool(((got == 1) | (js[:, None] == nb)).all(axis=1).any())
            for probe in [p for p in _PROBES if p < nb.size] + [nb.size]:  # a few of nb, more of them, then all
                ks = nb[_spread(nb.size, probe)] if probe < nb.size else nb
                got = (self.bits[js[:, None], (ks >> 3)[None, :]] >> (ks & 7)[None, :].astype(np.uint8)) & 1
                js = js[np.all((got == 1) | (js[:, None] == ks[None, :]), axis=1)]
                if js.size == 0:
                    return False
            return True
        near = self._near
        near[nb] = 1
        try:
            return bool(np.any(_row_sums(ptr, self.adj.indices, js, near) == nb.size - near[js]))
        finally:
            near[nb] = 0


@functools.lru_cache(maxsize=4096)
def _spread(size: int, probe: int) -> np.ndarray:
    """``probe`` positions spread evenly over ``range(size)``, first and last included (asked again and again)."""
    return np.linspace(0, size - 1, probe).astype(np.int64)


def duplicate_targets(by_target: sp.csr_matrix) -> np.ndarray:
    """Mask of targets whose candidate set repeats an earlier target's."""
    seen: set[bytes] = set()
    dup = np.zeros(by_target.shape[0], dtype=bool)
    for t in range(by_target.shape[0]):
        key = np.sort(by_target.indices[by_target.indptr[t] : by_target.indptr[t + 1]]).tobytes()
        dup[t] = key in seen
        seen.add(key)
    return dup


def implied_targets(by_target: sp.csr_matrix) -> np.ndarray:
    """Mask of targets whose cover follows from another's: if every candidate that sees t' also sees t, covering t'
    covers t (valid for k = 1 in the single-precision mode). Duplicates keep the lowest index.

    t goes when some t' with a candidate set strictly inside t's exists, or an earlier t' with the same set: the
    earliest of equal sets is never implied by an equal one, so it stands for every later one (the same mask as
    taking the targets one at a time and counting only the equal ones not yet implied)."""
    b = by_target.astype(np.int64).tocsr()
    size = np.diff(b.indptr)
    inter = (b @ b.T).tocoo()
    t, r, vals = inter.row, inter.col, inter.data
    sub = (vals == size[r]) & (r != t) & (size[r] > 0) & ((size[r] < size[t]) | (r < t))
    out = np.zeros(b.shape[0], dtype=bool)
    out[t[sub]] = True
    return out


def forced(by_target: sp.csr_matrix, k: int) -> np.ndarray:
    """Candidates that must be chosen: the only k that see some target."""
    counts = np.diff(by_target.indptr)
    must = np.zeros(by_target.shape[1], dtype=bool)
    must[by_target.indices[np.repeat(counts == k, counts)]] = True
    return must
