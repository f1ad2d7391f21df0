"""Dominance under the overlap rule with the relation formed among the kept candidates only.

The connected MILP needs the overlap relation among the candidates the presolve keeps; the presolve, as
:func:`planner.solve.presolve.dominated` states it, drops i for a kept j of its group, no dearer, that sees every
piece i sees and is linked to every neighbour k of i but j itself. Formed whole, that relation costs the sum over the
pieces of their seers squared, far too much on a fine grid. Two facts make the relation among the kept enough.

*Only the neighbours not dropped before i count* (the replacement argument of
:func:`planner.solve.presolve.dominated`): an optimal connected plan over the kept candidates remains.

*A shorter neighbour is j's neighbour anyway.* With C(j) >= C(i) the shared wall s(j, k) >= s(i, k) for every k and
L_j >= L_i (L: covered length). If L_k <= L_i, k linked to i means s(i, k) >= rho min(L_i, L_k) = rho L_k = rho
min(L_j, L_k), so k is linked to j (the other tests of the rule, s > 0 and s >= min_shared_m, only grow with s). In
floating point too: s(j, k) sums a superset of the lengths s(i, k) sums, in the same (piece) order, and rounding is
monotone. This needs a rule without ``max_link_m`` (a distance test is not monotone in coverage).

So candidates are taken longest coverage first: a neighbour k of i that still matters (L_k > L_i) came before i, and
is kept when it was not dropped. i is tested against the kept candidates only: one product of its coverage row with
theirs gives, at once, the kept supersets of i (count of shared pieces = |C(i)|) and its links to the kept. A link k
of i need not be looked up for j when s(i, k) already passes the rule against j (rho min(L_j, L_k) <= s(i, k)); the
rest are looked up in j's row of the relation among the kept, which this builds as it goes and hands on. Work: the sum
over pieces of (seers x kept seers), plus the relation among the kept. Identical coverage rows of a group are tested
once (the cheapest, then the first, stays in their place; the others are dropped with it or for it: same links, same
pieces).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.coverage.gram import BLOCK_ENTRIES, Keep
from planner.coverage.overlap import OverlapRule, link_filter

Ints = NDArray[np.int64]
Floats = NDArray[np.float64]

#: candidates tested per block (one product each for the block's coverage rows against the kept ones)
BLOCK_ROWS = 512
#: (replacer, hard link) pairs looked up at once in the relation among the kept (:meth:`_Kept.replaces`)
_PAIRS = 4096
#: the slack of the rule's share test (:func:`planner.coverage.overlap.link_filter`)
_SLACK = 1e-9


@dataclass(frozen=True, eq=False)
class OverlapLinks:
    """The overlap relation of a coverage matrix under ``rule``, not formed: ``lengths`` of the pieces, the group of
    each candidate (``gid``). :func:`linked_dominated` forms it among the candidates it keeps."""

    lengths: NDArray[np.float64]
    rule: OverlapRule
    gid: NDArray[np.int64]


def representatives(a: sp.csr_matrix, cost: NDArray[np.float64], gid: NDArray[np.int64]) -> NDArray[np.int64]:
    """Indices (ascending) of one candidate per distinct (group, coverage row): the cheapest, then the first."""
    a = a.tocsr()
    a.sort_indices()
    order = np.lexsort((np.arange(a.shape[0]), np.asarray(cost, float)))
    seen: set[tuple[int, bytes]] = set()
    keep = []
    for i in order.tolist():
        key = (int(gid[i]), a.indices[a.indptr[i] : a.indptr[i + 1]].tobytes())
        if key not in seen:
            seen.add(key)
            keep.append(i)
    return np.sort(np.asarray(keep, dtype=np.int64))


def length_order(a: sp.csr_matrix, cost: NDArray[np.float64], covered: NDArray[np.float64]) -> NDArray[np.int64]:
    """Longest covered length first, then most pieces, cheapest, lowest index (a superset comes before)."""
    return np.lexsort((np.arange(a.shape[0]), np.asarray(cost, float), -np.diff(a.indptr), -covered))


def linked_dominated(
    a: sp.csr_matrix, cost: NDArray[np.float64], links: OverlapLinks
) -> tuple[NDArray[np.bool_], sp.csr_matrix]:
    """Mask of the candidates dropped (see the module docstring) and the overlap relation among the others (n x n,
    boolean, symmetric)."""
    if links.rule.max_link_m is not None or not np.all(np.asarray(links.lengths) > 0):
        raise ValueError("needs pieces of length > 0 and no distance limit on links (not monotone in coverage)")
    a = a.astype(bool).tocsr()
    a.sort_indices()
    n = a.shape[0]
    lengths = np.asarray(links.lengths, float)
    # no float copy of the whole matrix (24 B a pair for two): the rows a block needs are cast per block
    covered = np.asarray(a @ lengths, dtype=np.float64).ravel()
    cost = np.asarray(cost, float)
    _, keep = link_filter(links.rule, covered, links.gid)
    reps = representatives(a, cost, links.gid)
    order = reps[length_order(a[reps], cost[reps], covered[reps])]
    state = _Kept(n)
    removed = np.ones(n, dtype=bool)
    size = np.diff(a.indptr)
    rho = links.rule.overlap
    lo = 0
    while lo < order.size:
        block = order[lo : lo + max(1, min(BLOCK_ROWS, BLOCK_ENTRIES // max(len(state.kept), 1)))]
        lo += block.size
        cols = np.concatenate([np.asarray(state.kept, dtype=np.int64), block])
        ptr, col, theta, link, sup, hard = _block_pairs(
            a, lengths, block, cols, size, cost, links.gid, keep, covered, rho
        )
        for r, i in enumerate(block.tolist()):
            if size[i] == 0:
                continue  # covers nothing, so no links: no bridge either
            span = slice(ptr[r], ptr[r + 1])
            c = col[span]
            alive = state.is_kept[c]  # kept before the block, or in it before i
            js = c[alive & sup[span]]
            if js.size:
                need = alive & hard[span]
                if not need.any() or state.replaces(js, c[need], theta[span][need], rho * covered[js]):
                    continue
            removed[i] = False
            state.add(i, c[alive & link[span]])
    return removed, state.relation()


def _block_pairs(
    a: sp.csr_matrix,
    lengths: Floats,
    block: Ints,
    cols: Ints,
    size: Ints,
    cost: Floats,
    gid: Ints,
    keep: Keep,
    covered: Floats,
    rho: float,
) -> tuple[Ints, Ints, Floats, NDArray[np.bool_], NDArray[np.bool_], NDArray[np.bool_]]:
    """Every pair (i of ``block``, c of ``cols``) sharing a piece, row by row (``ptr``): c, theta = the wall shared
    plus the rule's slack, whether the rule links them, whether c could replace i (sees all of i's pieces, no dearer,
    i's group) and whether c is a *hard* link of i: linked, longer than i, and not linked to every longer j by the
    shared wall alone (rho L_c > theta; only those are looked up in the relation, see :meth:`_Kept.replaces`).

    One complex product gives both the wall shared (real part: the same sums, in the same order, as the product of
    the real matrices, since (1 + 0i)(l + 1i) = l + 1i exactly) and the count of pieces shared (imaginary part: sums
    of ones), for the price of about one real product."""
    right = a[cols].T.tocsr()  # pieces x cols, each entry the piece's length + 1i (0 where stored False)
    weight = np.where(right.data, np.repeat(lengths, np.diff(right.indptr)) + 1j, 0)
    right = sp.csr_matrix((weight, right.indices, right.indptr), shape=right.shape)
    both = (a[block].astype(np.complex128) @ right).tocsr()  # a row's pairs in any order: none depends on it
    shared, count = both.data.real.copy(), both.data.imag
    r = np.repeat(block, np.diff(both.indptr))
    c = cols[both.indices]
    sup = (count == size[r]) & (cost[c] <= cost[r]) & (gid[c] == gid[r]) & (c != r)
    link = keep(r, c, shared)
    theta = shared + _SLACK
    hard = link & (covered[c] > covered[r]) & (rho * covered[c] > theta)
    return both.indptr, c, theta, link, sup, hard


class _Kept:
    """The kept candidates in the order kept and the overlap relation among them as a bit matrix (one bit per kept
    candidate: on a fine grid a large share of the pairs are linked, and bits hold that in less)."""

    def __init__(self, n: int) -> None:
        self.kept: list[int] = []
        self.is_kept = np.zeros(n, dtype=bool)
        self._pos = np.full(n, -1, dtype=np.int64)
        self._bits = np.zeros((64, 8), dtype=np.uint8)

    def add(self, i: int, nbrs: NDArray[np.int64]) -> None:
        """Keep i, linked to the kept ``nbrs``."""
        p = len(self.kept)
        if p == self._bits.shape[0]:  # room for twice as many
            grown = np.zeros((2 * p, 2 * self._bits.shape[1]), dtype=np.uint8)
            grown[:p, : self._bits.shape[1]] = self._bits
            self._bits = grown
        self.kept.append(i)
        self.is_kept[i] = True
        self._pos[i] = p
        q = self._pos[nbrs]
        row = np.zeros(8 * self._bits.shape[1], dtype=bool)
        row[q] = True
        self._bits[p] = np.packbits(row, bitorder="little")
        self._bits[q, p >> 3] |= np.uint8(1 << (p & 7))

    def replaces(self, js: Ints, ks: Ints, theta: Floats, reach: Floats) -> bool:
        """Whether some kept j of ``js`` is linked to every kept k of ``ks`` with ``theta`` of k < ``reach`` of j, but
        j itself (the hard links of the candidate under test: those the shared wall does not link to j already). All
        pairs at once where they are few, else the j shortest first (``reach`` ascending: fewest links to look up), a
        few rows of the table at a time."""
        q = self._pos[ks]
        byte, bit = q >> 3, (q & 7).astype(np.uint8)
        step = max(1, _PAIRS // ks.size)
        if js.size > step:
            by = np.argsort(reach, kind="stable")
            js, reach = js[by], reach[by]
        for lo in range(0, js.size, step):
            j, lim = js[lo : lo + step, None], reach[lo : lo + step, None]
            linked = (self._bits[self._pos[j], byte] >> bit) & 1
            if ((linked == 1) | (theta >= lim) | (ks == j)).all(axis=1).any():
                return True
        return False

    def relation(self) -> sp.csr_matrix:
        """The relation among the kept (n x n), unpacked a block of rows at a time."""
        n, m = self.is_kept.size, len(self.kept)
        kept = np.asarray(self.kept, dtype=np.int64)
        rows, cols = [], []
        step = max(1, BLOCK_ENTRIES // max(8 * self._bits.shape[1], 1))
        for lo in range(0, m, step):
            r, c = np.nonzero(np.unpackbits(self._bits[lo : lo + step], axis=1, bitorder="little")[:, :m])
            rows.append(kept[r + lo])
            cols.append(kept[c])
        r = np.concatenate(rows) if rows else np.zeros(0, np.int64)
        c = np.concatenate(cols) if cols else np.zeros(0, np.int64)
        out = sp.csr_matrix((np.ones(r.size, dtype=bool), (r, c)), shape=(n, n))
        out.sort_indices()
        return out
