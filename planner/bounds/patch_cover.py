"""A lower bound on the connected cover over patches without a search: the family reduced, then the ring walk with the
cover rows added back by multipliers (:mod:`planner.bounds.walk_dual`).

**Reduction** (:func:`reduced`). Two steps that keep the connected optimum, alternated until neither removes anything
(or :data:`REDUCE_PASSES` passes): a target whose cover follows from another's goes (:func:`implied`, the mask of
:func:`planner.solve.presolve.implied_targets`: every patch that sees t' sees t; patches only go afterwards, so it stays
implied), and so does a patch Q for which a patch P kept before it in a strict order covers every target Q covers and
is linked to every neighbour of Q not gone before it (:func:`linked_dominated`, the rule of
:func:`planner.solve.presolve.dominated` with the covers and the links as bits). Replace the patches gone from an optimal connected cover by their P in the same order: at Q's turn those gone
before it are out of the cover already, so Q's neighbours in it are P's, and P is never replaced: a connected cover,
no larger.

**Bound** (:func:`ring_lagrange_bound`). Every connected cover of the reduced family covers its targets, so (implied
targets) every required piece, so the pieces its patches see: the ring walk over their arcs is a lower bound
(:mod:`planner.solve.ring`), and so is its Lagrangian L(lambda) for every lambda >= 0 on the targets; the multipliers
are found by column generation over walks (:mod:`planner.bounds.walk_dual`, which reaches the Lagrangian dual where a
subgradient ascent oscillated: polygon A's inside 8 -> 9, C's 10 -> 11 and 12), pricing at most :data:`ASCENT_STEPS`
walks and :data:`WALK_WORK` walk units (counts: the
same bound under any load). Costs are one per patch, so the bound is the ceiling of the best value.

**Cost** (:func:`family_bound`, the whole of it from the grid's patches). Each test that would take a patch x patch or
target x target product looks only where an answer can be: a target implied by t' is seen by the patch of t' that sees
fewest targets, a patch that covers Q sees Q's rarest target; so each gives the full test's answer (a test checks
them against each other) at a fraction of its work (:mod:`planner.bounds.patch_family` for the family and its links).
The walks' dual's master is one HiGHS model kept warm. Polygon C's inside (5,208 undominated patches, 4.2 million
links): 3.2-3.6 CPU-s -> 1.4-1.6 on a loaded machine, the same bound (12) over the same 902 patches.
"""

from __future__ import annotations

import math
from typing import SupportsInt, TypeAlias

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.bounds.patch_family import PAIRS, bits, earlier_pairs, expand, link_matrix, rarest, undominated
from planner.bounds.walk_dual import walk_dual_bound
from planner.solve.ring import ring_graph

#: walks the column generation prices at most
ASCENT_STEPS = 50
#: walk units (links of the lifted graph x anchors, per walk) it may spend (polygon A's and C's insides: 9-21 walks of
#: 2-4e7 units)
WALK_WORK = 1e9
#: dominators tried per patch in one pass, earliest first (fewer only removes less: still sound)
_PROBE = 64
#: patches per block of the link test in :func:`near_linked_dominated`
_BLOCK = 1024
#: grid cells either way within which :func:`near_linked_dominated` looks for a patch to take another's place
_NEAR = 2
#: passes of the reduction at most: each keeps the optimum, and past the third they remove a few patches in a pass
#: (polygon C's inside: 2,376 -> 1,287 -> 980 -> 902 patches, then 881, 880, 880)
REDUCE_PASSES = 3

#: links among patches: a symmetric matrix with no diagonal, sparse or dense
Links: TypeAlias = sp.csr_matrix | NDArray[np.bool_]


def dense(adj: Links) -> NDArray[np.bool_]:
    """``adj`` as a dense boolean matrix (itself where it is one)."""
    return adj if isinstance(adj, np.ndarray) else np.asarray(adj.astype(bool).toarray())


def linked_dominated(a: sp.csr_matrix, adj: Links) -> NDArray[np.bool_]:
    """Mask of the patches (rows of ``a``, patches x targets) that go (module docstring), taken in a strict order
    (larger cover first, then index): Q goes when a patch P kept before it covers every target Q covers and is linked
    to every neighbour of Q (``adj``: symmetric, no diagonal) not gone before Q, P itself aside; of the P that cover
    Q, the first :data:`_PROBE` in the order are tried. A P that covers Q sees Q's rarest target, so only the kept
    patches that see it are tested (the covers and the links as packed bits)."""
    n = a.shape[0]
    a = a.tocsr()
    size = a.getnnz(axis=1)
    order = np.lexsort((np.arange(n), -size))
    pos = np.empty(n, dtype=np.int64)
    pos[order] = np.arange(n)
    linked = np.packbits(dense(adj), axis=1, bitorder="little")
    q_of, p_of = earlier_pairs(a, pos)  # the P before Q that cover all Q covers, in the order
    ptr = np.concatenate([[0], np.cumsum(np.bincount(q_of, minlength=n))]).tolist()
    own = np.left_shift(np.uint8(1), (p_of & 7).astype(np.uint8))  # each P's own bit, left out of its test
    gone = np.zeros(n, dtype=bool)
    kept = np.zeros(n, dtype=bool)
    live = np.full((n + 7) // 8, 255, dtype=np.uint8)  # bits of the patches not gone
    kept_order = np.zeros(n, dtype=np.int64)  # the kept patches in the order, the first n_kept of them
    n_kept = 0
    for q in order.tolist():
        lo, hi = ptr[q], ptr[q + 1]
        if size[q] and lo < hi:
            at = lo + np.flatnonzero(kept[p_of[lo:hi]])[:_PROBE]
            ps, bit = p_of[at], own[at]
        elif size[q]:
            at = ps = bit = np.zeros(0, dtype=np.int64)
        else:
            ps = kept_order[: min(n_kept, _PROBE)]
            bit = np.left_shift(np.uint8(1), (ps & 7).astype(np.uint8))
        if ps.size:
            miss = (linked[q] & live)[None, :] & ~linked[ps]
            miss[np.arange(ps.size), ps >> 3] &= ~bit
            if not miss.any(axis=1).all():
                gone[q] = True
                live[q >> 3] &= ~np.left_shift(np.uint8(1), np.uint8(q & 7))
                continue
        kept[q] = True
        kept_order[n_kept] = q
        n_kept += 1
    return gone


def implied(a: sp.csr_matrix) -> NDArray[np.bool_]:
    """:func:`planner.solve.presolve.implied_targets` of ``a`` (patches x targets) without the target x target
    product: t goes when some t' whose patch set S(t') is inside S(t) is strictly smaller, or equal and earlier. Such a
    t is seen by the patch of S(t') that sees the fewest targets, so only those pairs are tested (S as packed bits)."""
    a = a.tocsr()
    n, n_t = a.shape
    seers = a.T.tocsr()
    count = np.diff(seers.indptr)
    rows = bits(seers)
    live = np.flatnonzero(count)
    if live.size == 0:
        return np.zeros(n_t, dtype=bool)
    # the patch of each S(t') that sees the fewest targets
    narrow = rarest(seers, np.diff(a.indptr))[live]
    which, at = expand(a.indptr, narrow)
    tp, t = live[which], a.indices[at].astype(np.int64)  # t', and t a target its narrowest patch sees
    ok = (t != tp) & ((count[tp] < count[t]) | ((count[tp] == count[t]) & (tp < t)))
    tp, t = tp[ok], t[ok]
    out = np.zeros(n_t, dtype=bool)
    for lo in range(0, t.size, PAIRS):
        x, y = tp[lo : lo + PAIRS], t[lo : lo + PAIRS]
        out[y[~(rows[x] & ~rows[y]).any(axis=1)]] = True
    return out


def near_linked_dominated(a: sp.csr_matrix, adj: Links, cells: NDArray[np.int64]) -> NDArray[np.bool_]:
    """Mask of the patches that a patch within :data:`_NEAR` grid cells replaces, all at once: Q goes when some P
    before it in the strict order of :func:`linked_dominated` covers every target Q covers and is linked to every
    neighbour of Q, P itself aside. ``cells``: each row's (column, row) on the grid of patches.

    Why all at once: each Q names one such P; the chain Q -> P -> ... ends at a kept patch rep(Q) (the order is strict),
    which covers all Q covers. If Q and R are linked, each step of Q's chain keeps a link to R unless the chain meets R
    (then rep(Q) = rep(R)); then each step of R's chain keeps a link to rep(Q) unless it meets it. So rep(Q) and rep(R)
    are linked or equal, and a connected cover mapped through rep stays a connected cover, no larger."""
    n = a.shape[0]
    size = a.getnnz(axis=1)
    pos = np.empty(n, dtype=np.int64)
    pos[np.lexsort((np.arange(n), -size))] = np.arange(n)
    ix, iy = cells[:, 0] - cells[:, 0].min(initial=0), cells[:, 1] - cells[:, 1].min(initial=0)
    span = int(iy.max(initial=0)) + 2 * _NEAR + 1
    code = (ix + _NEAR) * span + iy + _NEAR
    at = np.full(int(code.max(initial=0)) + _NEAR * span + _NEAR + 1, -1, dtype=np.int64)
    at[code] = np.arange(n)
    linked = np.packbits(dense(adj), axis=1, bitorder="little")
    out = np.zeros(n, dtype=bool)
    for dx in range(-_NEAR, _NEAR + 1):
        for dy in range(-_NEAR, _NEAR + 1):
            p = at[code + dx * span + dy]
            q = np.flatnonzero((p >= 0) & ~out)
            p = p[q]
            q, p = q[pos[p] < pos[q]], p[pos[p] < pos[q]]
            held = np.asarray(a[q].multiply(a[p]).sum(axis=1)).ravel() == size[q]
            q, p = q[held], p[held]
            for lo in range(0, q.size, _BLOCK):
                qq, pp = q[lo : lo + _BLOCK], p[lo : lo + _BLOCK]
                miss = linked[qq] & ~linked[pp]
                miss[np.arange(qq.size), pp >> 3] &= ~np.left_shift(np.uint8(1), (pp & 7).astype(np.uint8))
                out[qq[~miss.any(axis=1)]] = True
    return out


def reduced(
    a: sp.csr_matrix, adj: Links, cells: NDArray[np.int64] | None = None
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The patches and targets kept by the reduction (module docstring, at most :data:`REDUCE_PASSES` passes): row and
    column indices of ``a``. With
    ``cells`` (each row's place on a grid of patches) a first pass replaces patches by near ones
    (:func:`near_linked_dominated`), which costs little and leaves the products of the others small."""
    kc, kt = np.arange(a.shape[0]), np.arange(a.shape[1])
    a, links = a.tocsr(), dense(adj)  # the rows and columns kept so far: each pass cuts what the last one left
    for _ in range(REDUCE_PASSES):
        imp = implied(a)
        kt = kt[~imp]
        a = a[:, np.flatnonzero(~imp)].tocsr()
        if cells is not None:
            keep = np.flatnonzero(~near_linked_dominated(a, links, cells))
            kc, a, links, cells = kc[keep], a[keep].tocsr(), links[keep][:, keep], None
        gone = linked_dominated(a, links)
        keep = np.flatnonzero(~gone)
        kc, a, links = kc[keep], a[keep].tocsr(), links[keep][:, keep]
        if not (gone.any() or imp.any()):
            break
    return kc, kt


def ring_lagrange_bound(
    a: sp.csr_matrix,
    targets: NDArray[np.int64],
    adj: Links,
    target: SupportsInt,
    steps: int = ASCENT_STEPS,
    work: float = WALK_WORK,
) -> int:
    """A lower bound on the connected cover of the columns ``targets`` of ``a`` (patches x pieces in cyclic order;
    covering them covers every column) under the links ``adj``, each patch costing one: the ring walk over the arcs of
    the pieces the patches see, then its Lagrangian dual over the target rows (:mod:`planner.bounds.walk_dual`),
    stopping once the bound reaches ``target``; 0 where the walk is not formed."""
    a = a.tocsr()
    seen = np.flatnonzero(a.getnnz(axis=0))
    if seen.size == 0 or a.shape[0] == 0:
        return 0
    graph = ring_graph(a[:, seen].tocsr(), np.ones(seen.size, dtype=bool), sp.csr_matrix(dense(adj)))
    if graph is None:
        return 0
    cost = np.ones(a.shape[0])
    steps = min(steps, int(work // max(1, graph.graph.nnz * len(graph.anchors))))
    # the cheapest walk from every anchor (the walk itself among them) starts the dual, whose best value is at least it
    value, _ = walk_dual_bound(graph, a[:, targets].astype(np.float64).tocsr(), cost, target, max(steps, 0))
    return max(0, math.ceil(value - 1e-6)) if math.isfinite(value) else 0


def family_bound(
    u: sp.csr_matrix,
    low: NDArray[np.float64],
    cells: NDArray[np.int64],
    lengths: NDArray[np.float64],
    required: NDArray[np.bool_],
    share: float,
    target: SupportsInt,
    most: int,
) -> tuple[int, int] | None:
    """The quick cover's bound over the patches ``u`` (patches x pieces, with ``low`` and their grid ``cells``): the
    undominated ones (:func:`planner.bounds.patch_family.undominated`), their relaxed links
    (:func:`planner.bounds.patch_family.link_matrix`), the reduction and :func:`ring_lagrange_bound`. (bound, patches
    kept); None where more than ``most`` patches are undominated (their links would be formed pairwise)."""
    keep = undominated(u, low)
    if keep.size > most:
        return None
    u, low, cells = u[keep].tocsr(), low[keep], cells[keep]
    links = link_matrix(u, low, lengths, share)
    a = u[:, np.flatnonzero(required)].tocsr()
    kc, kt = reduced(a, links, cells)
    return ring_lagrange_bound(a[kc], kt, links[np.ix_(kc, kc)], target), int(kc.size)
