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
        ptr, col, shared, link, sup = _block_pairs(a, lengths, block, cols, size, cost, links.gid, keep)
        for r, i in enumerate(block.tolist()):
            if size[i] == 0:
                continue  # covers nothing, so no links: no bridge either
            span = slice(ptr[r], ptr[r + 1])
            c = col[span]
            alive = state.is_kept[c]  # kept before the block, or in it before i
            nb = alive & link[span]
            js = c[alive & sup[span]]
            if js.size and _replaceable(js, c[nb], shared[span][nb], covered, i, rho, state):
                continue
            removed[i] = False
            state.add(i, c[nb])
    return removed, state.relation()


def _block_pairs(
    a: sp.csr_matrix, lengths: Floats, block: Ints, cols: Ints, size: Ints, cost: Floats, gid: Ints, keep: Keep
) -> tuple[Ints, Ints, Floats, NDArray[np.bool_], NDArray[np.bool_]]:
    """Every pair (i of ``block``, c of ``cols``) sharing a piece, row by row (``ptr``): c, the wall shared, whether
    the rule links them, and whether c could replace i (sees all of i's pieces, no dearer, i's group)."""
    right = (a[cols].astype(np.float64) @ sp.diags(lengths)).T.tocsr()
    left = a[block].astype(np.float64)
    shared = (left @ right).tocsr()
    count = (left @ sp.csr_matrix((np.ones(right.nnz), right.indices, right.indptr), shape=right.shape)).tocsr()
    shared.sort_indices()
    count.sort_indices()  # the same pattern as shared's: every piece has a length > 0
    r = np.repeat(block, np.diff(shared.indptr))
    c = cols[shared.indices]
    sup = (count.data == size[r]) & (cost[c] <= cost[r]) & (gid[c] == gid[r]) & (c != r)
    return shared.indptr, c, shared.data, keep(r, c, shared.data), sup


def _replaceable(sup: Ints, nb_c: Ints, nb_s: Floats, covered: Floats, i: int, rho: float, state: _Kept) -> bool:
    """Whether some kept superset j of i (``sup``) is linked to every kept neighbour k of i longer than i (``nb_c``,
    sharing ``nb_s`` with i) but j itself; a k is looked up only where s(i, k) < rho min(L_j, L_k)."""
    longer = covered[nb_c] > covered[i]
    hard_c, theta = nb_c[longer], nb_s[longer] + _SLACK
    live = rho * covered[hard_c] > theta  # s(i, k) passes against every j when rho L_k <= s(i, k)
    hard_c, theta = hard_c[live], theta[live]
    by = np.argsort(theta, kind="stable")
    hard_c, theta = hard_c[by], theta[by]
    sup = sup[np.argsort(covered[sup], kind="stable")]  # shortest first: fewest links to look up
    reach = np.searchsorted(theta, rho * covered[sup], side="left")  # hard for j: theta_k < rho L_j
    for j, m in zip(sup.tolist(), reach.tolist()):
        need = hard_c[:m]
        need = need[need != j]
        if need.size == 0 or state.linked_to_all(j, need):
            return True
    return False


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

    def linked_to_all(self, j: int, ks: NDArray[np.int64]) -> bool:
        """Whether kept j is linked to every kept k of ``ks``."""
        q = self._pos[ks]
        row = self._bits[self._pos[j]]
        return bool(np.all((row[q >> 3] >> (q & 7)) & 1))

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
