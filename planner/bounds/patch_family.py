"""The family of patches the quick cover over patches starts from, formed without a patch x patch product where a
narrower test gives the same answer (:mod:`planner.bounds.patch_cover` reduces it, :mod:`planner.bounds.plane_refine`
lays the grid).

- :func:`undominated`: the patches no other patch replaces as a plain cover does (U(P) holds U(Q) and low(P) <=
  low(Q), P before Q in :func:`planner.solve.presolve.presolve_order`): the same rows as
  :func:`planner.solve.presolve.dominated` with ``low`` as the cost. A P that holds U(Q) sees Q's rarest piece, so only
  the patches that see it are tested, all pairs at once as packed bits. The relation is transitive and the order
  strict, so a Q that any earlier P holds is held by a kept one: testing against every earlier patch, kept or not,
  gives the mask of the walk that tests against the kept ones only.
- :func:`link_matrix`: the relaxed links (:func:`planner.bounds.plane_refine.relaxed_links`: shared wall > 0 and at
  least f min(low), in float32 with 1 mm of slack toward linking) as a dense boolean matrix, the form the reduction's
  bit tests take them in: a block of patches against the later patches that see one of its pieces, over those pieces.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

#: pairs tested at a time as packed bits
PAIRS = 65_536
#: patches per block of the link product
_BLOCK = 512
#: the link is taken when the float32 shared length is within this of f min(low) (m): as
#: :func:`planner.bounds.plane_refine.relaxed_links`, never a link fewer than the exact test
_SLACK_M = 1e-3


def bits(a: sp.csr_matrix) -> NDArray[np.uint64]:
    """The rows of ``a`` as bits, packed into 64-bit words."""
    packed = np.packbits(a.astype(bool).toarray(), axis=1, bitorder="little")
    pad = (-packed.shape[1]) % 8
    return np.ascontiguousarray(np.pad(packed, ((0, 0), (0, pad)))).view(np.uint64)


def rarest(a: sp.csr_matrix, count: NDArray[np.int64]) -> NDArray[np.int64]:
    """For every row of ``a``, the column it holds with the least ``count`` (the lowest such index; 0 for an empty
    row)."""
    out = np.zeros(a.shape[0], dtype=np.int64)
    full = np.flatnonzero(np.diff(a.indptr) > 0)
    if full.size:
        key = count[a.indices].astype(np.int64) * (a.shape[1] + 1) + a.indices
        out[full] = np.minimum.reduceat(key, a.indptr[full]) % (a.shape[1] + 1)
    return out


def expand(indptr: NDArray[np.int64], rows: NDArray[np.int64]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """For each of ``rows`` of a CSR pattern, its entries' positions: (which of ``rows``, position in ``indices``)."""
    deg = indptr[rows + 1] - indptr[rows]
    which = np.repeat(np.arange(rows.size), deg)
    return which, np.repeat(indptr[rows] - np.cumsum(deg) + deg, deg) + np.arange(int(deg.sum()))


def earlier_pairs(
    a: sp.csr_matrix, pos: NDArray[np.int64], low: NDArray[np.float64] | None = None
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Every (Q, P) of rows of ``a`` with P before Q in the order ``pos`` (a permutation) and P holding all Q holds
    (and, with ``low``, low[P] <= low[Q]), Q ascending and each Q's P in the order. A P that holds Q's columns holds
    each of them, so P is among the rows before Q that hold Q's column with the fewest such rows: only those are
    tested (as packed bits)."""
    a = a.astype(bool).tocsr()
    n = a.shape[0]
    seers = a.T.tocsr()  # each column's rows in the order
    col = np.repeat(np.arange(seers.shape[0]), np.diff(seers.indptr))
    seers.indices = seers.indices[np.lexsort((pos[seers.indices], col))]
    rank = np.arange(seers.indices.size) - seers.indptr[col]  # rows before this one in its column's list
    best = np.full(n, np.iinfo(np.int64).max, dtype=np.int64)
    np.minimum.at(best, seers.indices, rank * (seers.shape[0] + 1) + col)
    q = np.flatnonzero(np.diff(a.indptr))
    c, before = best[q] % (seers.shape[0] + 1), best[q] // (seers.shape[0] + 1)
    which = np.repeat(np.arange(q.size), before)
    at = np.repeat(seers.indptr[c] - np.cumsum(before) + before, before) + np.arange(int(before.sum()))
    q, p = q[which], seers.indices[at].astype(np.int64)
    size = np.diff(a.indptr)
    ok = size[p] >= size[q]
    if low is not None:
        ok &= low[p] <= low[q]
    q, p = q[ok], p[ok]
    rows = bits(a)
    holds = np.zeros(q.size, dtype=bool)
    for lo in range(0, q.size, PAIRS):
        x, y = q[lo : lo + PAIRS], p[lo : lo + PAIRS]
        holds[lo : lo + PAIRS] = ~(rows[x] & ~rows[y]).any(axis=1)
    return q[holds], p[holds]


def undominated(u: sp.csr_matrix, low: NDArray[np.float64]) -> NDArray[np.int64]:
    """The rows of ``u`` (patches x pieces) that :func:`planner.solve.presolve.dominated` keeps with ``low`` as the
    cost (module docstring), ascending."""
    u = u.astype(bool).tocsr()
    n = u.shape[0]
    size = np.diff(u.indptr)
    pos = np.empty(n, dtype=np.int64)
    pos[np.lexsort((np.arange(n), low, -size))] = np.arange(n)
    q, _ = earlier_pairs(u, pos, low)
    gone = size == 0
    gone[q] = True
    return np.flatnonzero(~gone)


def link_matrix(
    u: sp.csr_matrix, low: NDArray[np.float64], lengths: NDArray[np.float64], share: float
) -> NDArray[np.bool_]:
    """The relaxed links among the rows of ``u`` (module docstring): symmetric, no diagonal. The rows are taken in
    blocks in the order of their first piece, so that a block sees a stretch of the ring; each block is multiplied with
    the rows after it in that order that see one of its pieces (found as packed bits), over those pieces only."""
    n = u.shape[0]
    u = u.astype(bool).tocsr()
    u.sort_indices()
    has = np.diff(u.indptr) > 0
    first = np.full(n, -1, dtype=np.int64)
    first[has] = u.indices[u.indptr[:-1][has]]
    perm = np.argsort(first, kind="stable")
    pos = np.empty(n, dtype=np.int64)
    pos[perm] = np.arange(n)
    ub = u.astype(np.float32).toarray()
    packed = bits(u)
    w = ub * lengths.astype(np.float32)[None, :]
    need = (share * low).astype(np.float32)
    out = np.zeros((n, n), dtype=bool)  # each pair once (the later row in the order as the column), then mirrored
    for i in range(0, n, _BLOCK):
        rows = perm[i : i + _BLOCK]
        mask = np.bitwise_or.reduce(packed[rows], axis=0)
        later = np.flatnonzero((pos >= i) & (packed & mask[None, :]).any(axis=1))
        seen = np.flatnonzero(ub[rows].any(axis=0))
        shared = w[rows][:, seen] @ ub[later][:, seen].T
        ok = shared > 0
        ok &= shared + np.float32(_SLACK_M) >= np.minimum(need[rows, None], need[None, later])
        ok &= pos[later][None, :] > pos[rows][:, None]
        out[np.ix_(rows, later)] = ok
    out |= _transposed(out)
    return out


def _transposed(x: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """A copy of the square ``x`` transposed, a tile at a time (a whole transpose runs across the cache)."""
    n = x.shape[0]
    out = np.empty_like(x)
    for i in range(0, n, _BLOCK):
        for j in range(0, n, _BLOCK):
            out[j : j + _BLOCK, i : i + _BLOCK] = x[i : i + _BLOCK, j : j + _BLOCK].T
    return out
