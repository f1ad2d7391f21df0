"""A connected plane bound by refinement: the connected cover over patches, split where its optimum sits.

**Relaxation.** The patches and their sets U(P), low(P) and relaxed links are the ring walk's
(:mod:`planner.bounds.plane_ring`), but U(P) is kept as a set instead of the smallest arc that holds it (on a concave
outline the arcs claim the hidden wall between the runs a station sees, and the walk can stay below the plan). A
connected plan of k stations anywhere, each replaced by the patch that holds it, is a connected cover of the zone-side's
pieces by at most k patches under the relaxed links: the optimum of that connected cover over the family (the connected
MILP, :func:`planner.solve.milp.solve`, given the relation) bounds every connected plan from below.

**Refinement.** Each patch of the optimum is split into its four quarters and the cover solved again. A quarter holds a
subset of its parent's positions, so its U lies within the parent's and its low is at least the parent's: whatever the
quarters do, the parent did, and the optimum never falls. It is repeated until the optimum reaches the plan's count (the
plan is then optimal over the plane), the steps are spent, a solve is not proven within its work (its proven lower bound
is kept), or the patches of the optimum cannot be split past :data:`MIN_PATCH_M`. This is the refinement of the exact
art-gallery solvers (Tozoni, de Rezende and de Souza, ACM TOMS 2016: witnesses and guard candidates refined where the
relaxation's optimum is not realised), here with the registration links.

**Quick bound** (:func:`quick_bound`; :func:`refined_bound` with no steps). The cover over one grid of patches, bounded
without a search: the family reduced (:mod:`planner.bounds.patch_cover`: replacements by near patches, dominance under
the links, implied targets) and the ring walk over it raised by its Lagrangian dual (:mod:`planner.bounds.walk_dual`). Any lower bound on the cover over
patches bounds every connected plan, so no optimum is needed; every limit is a count.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, SupportsInt

import numpy as np
import scipy.sparse as sp
import shapely
from numpy.typing import NDArray

from planner.bounds.patch_cover import family_bound
from planner.bounds.plane_patches import MIN_PATCH_M, SidePieces, grid_shape, live_box
from planner.coverage.overlap import SITE_SHARE
from planner.solve.instance import CoverInstance
from planner.solve.milp import MilpOptions, solve
from planner.solve.presolve import dominated
from planner.solve.result import Status

#: CP-SAT work (deterministic seconds, 1 thread) for each step's connected cover, with no wall-clock cap: a count, so
#: the bound is the same under any load
STEP_WORK_S = 60.0
#: the quick bound's patches over the box of a zone-side's regions (a count: the same bound under any load)
QUICK_PATCHES = 20_000
#: distinct patches (U, low) that no near patch dominates (:func:`near_dominated`) the quick bound takes on at the ring
#: walk's first side, whose grid it shares; past it, a coarser side (polygon C's inside: 7,040 at 3.26 m, taken)
QUICK_NEAR = 7_500
#: such patches aimed at on the coarser side: a side of its own costs its grown and shrunk regions and its grid again,
#: so it is kept small (polygon A's inside: 15,831 at 2.49 m -> 5.0-m patches, bound 9 as at 4.1 m, in half the time)
QUICK_COARSE = 4_000
#: the quick bound's undominated patches at most (the links among them are formed pairwise); past it, the coarser side
#: as above (polygon C's inside: 5,208 at 3.26 m -> 4.32-m patches, bound 11; at 3.26 m it is 12, in 3 CPU-s more)
QUICK_FAMILY = 6_000
#: grid cells either way within which :func:`near_dominated` looks for a dominating patch
_NEAR = 4
#: rows of the relaxed-link product formed at a time (a block of patches x all patches, float32)
_BLOCK = 512
#: the relaxed link is taken when the float32 shared length is within this of f min(low) (m): more links than the exact
#: test, never fewer, so the bound stays sound
_SLACK_M = 1e-3


@dataclass(frozen=True)
class Refined:
    """The refined bound of one zone-side (a lower bound on every connected plan) and how it was reached."""

    bound: int
    steps: int
    patches: int
    smallest_m: float
    proven: bool

    def to_dict(self) -> dict[str, Any]:
        return {
            "bound": self.bound,
            "steps": self.steps,
            "patches": self.patches,
            "smallest_patch_m": round(self.smallest_m, 4),
            "last_cover_proven": self.proven,
        }


class _Levels:
    """The grown and shrunk regions of the zone-side for patches of side ``h0 / 2**level``, indexed by STR-trees."""

    def __init__(self, pieces: SidePieces, h0: float) -> None:
        self.pieces, self.h0 = pieces, h0
        self._trees: dict[int, tuple[shapely.STRtree, shapely.STRtree]] = {}

    def side(self, level: int) -> float:
        return self.h0 / 2**level

    def sets(
        self, cx: NDArray[np.float64], cy: NDArray[np.float64], level: int
    ) -> tuple[sp.csr_matrix, NDArray[np.float64]]:
        """U (patches x pieces) and low of the patches of one level centred at (cx, cy)."""
        if level not in self._trees:
            g, s = self.pieces.shapes(self.side(level))
            self._trees[level] = (shapely.STRtree(g), shapely.STRtree(s))
        grow, shrink = self._trees[level]
        pts = shapely.points(cx, cy)
        pi, gi = grow.query(pts, predicate="within")
        u = sp.csr_matrix((np.ones(pi.size, dtype=bool), (pi, gi)), shape=(cx.size, len(self.pieces.outer)))
        si, sj = shrink.query(pts, predicate="within")
        low = np.zeros(cx.size)
        np.add.at(low, si, self.pieces.lengths[sj])
        return u, low


@dataclass
class _Family:
    """Patches: centres, levels, U and low (rows in step)."""

    cx: NDArray[np.float64]
    cy: NDArray[np.float64]
    level: NDArray[np.int64]
    u: sp.csr_matrix
    low: NDArray[np.float64]

    def keep(self, mask: NDArray[np.bool_]) -> _Family:
        return _Family(self.cx[mask], self.cy[mask], self.level[mask], self.u[mask].tocsr(), self.low[mask])

    def plus(self, other: _Family) -> _Family:
        return _Family(
            np.concatenate([self.cx, other.cx]),
            np.concatenate([self.cy, other.cy]),
            np.concatenate([self.level, other.level]),
            sp.vstack([self.u, other.u]).tocsr(),
            np.concatenate([self.low, other.low]),
        )


def grid_family(lv: _Levels) -> _Family:
    """The level-0 patches: a grid of side h0 over the box of the grown regions (every position that may see a piece
    lies in it), those that may see nothing left out (:meth:`planner.bounds.plane_patches.SidePieces.grid`: the sets
    :meth:`_Levels.sets` gives, by a scan line)."""
    got = lv.pieces.grid(lv.h0)
    if got is None:  # past the scan's grid cap: every centre asked of the trees
        box = live_box(lv.pieces.shapes(lv.h0)[0])
        assert box is not None
        nx_, ny_ = grid_shape(box, lv.h0)
        gx, gy = np.meshgrid(*(box[k] + (np.arange(m) + 0.5) * lv.h0 for k, m in ((0, nx_), (1, ny_))), indexing="ij")
        cx, cy = gx.ravel(), gy.ravel()
        u, low = lv.sets(cx, cy, 0)
        return _Family(cx, cy, np.zeros(cx.size, dtype=np.int64), u, low).keep(u.getnnz(axis=1) > 0)
    u, low, cx, cy = got
    return _Family(cx, cy, np.zeros(cx.size, dtype=np.int64), u, low)


def split(fam: _Family, rows: NDArray[np.int64], lv: _Levels) -> _Family:
    """``fam`` with the patches ``rows`` replaced by their four quarters (those that may see nothing left out)."""
    quarter = lv.h0 / 2.0 ** fam.level[rows] / 4.0
    cx = np.concatenate([fam.cx[rows] + dx * quarter for dx in (-1, -1, 1, 1)])
    cy = np.concatenate([fam.cy[rows] + dy * quarter for dy in (-1, 1, -1, 1)])
    level = np.tile(fam.level[rows] + 1, 4)
    parts = []
    for lev in np.unique(level).tolist():
        at = np.flatnonzero(level == lev)
        u, low = lv.sets(cx[at], cy[at], lev)
        parts.append(_Family(cx[at], cy[at], level[at], u, low))
    rest = np.ones(fam.cx.size, dtype=bool)
    rest[rows] = False
    out = fam.keep(rest)
    for p in parts:
        out = out.plus(p.keep(p.u.getnnz(axis=1) > 0))
    return out


def relaxed_links(
    u: sp.csr_matrix, low: NDArray[np.float64], lengths: NDArray[np.float64], share: float
) -> sp.csr_matrix:
    """The relaxed links (module docstring) among the rows of ``u``, symmetric, no diagonal: formed a block of rows
    against the rows from it on at a time (float32, with :data:`_SLACK_M` toward linking). The rows are taken in the
    order of their first piece, and each block's product keeps to the pieces its rows see and the later rows that see
    one of them (no other pair shares wall): a patch sees a run of the zone-side's ring, so a block sees a stretch of it
    (polygon C's inside: 5,208 patches, about a third of the work)."""
    n = u.shape[0]
    u = u.tocsr()
    u.sort_indices()
    has = np.diff(u.indptr) > 0
    first = np.full(n, -1, dtype=np.int64)
    first[has] = u.indices[u.indptr[:-1][has]]
    perm = np.argsort(first, kind="stable")
    ub = u[perm].astype(np.float32).toarray()
    w = ub * lengths.astype(np.float32)[None, :]
    need = (share * low[perm]).astype(np.float32)
    rows, cols = [], []
    for i in range(0, n, _BLOCK):
        block = min(_BLOCK, n - i)
        seen = np.flatnonzero(ub[i : i + block].any(axis=0))
        later = i + np.flatnonzero(ub[i:, seen].any(axis=1))
        shared = w[i : i + block, seen] @ ub[np.ix_(later, seen)].T
        ok = shared > 0
        ok &= shared + np.float32(_SLACK_M) >= np.minimum(need[i : i + block, None], need[None, later])
        ok &= later[None, :] > (i + np.arange(block))[:, None]
        r, c = np.nonzero(ok)
        rows.append(perm[r + i])
        cols.append(perm[later[c]])
    r, c = (np.concatenate(rows), np.concatenate(cols)) if rows else (np.zeros(0, int), np.zeros(0, int))
    upper = sp.csr_matrix((np.ones(r.size, dtype=bool), (r, c)), shape=(n, n))
    return (upper + upper.T).tocsr()


def distinct_rows(u: sp.csr_matrix, low: NDArray[np.float64]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """One row per distinct (U, low): the rows kept and, for every row, the index of its kept one."""
    u = u.tocsr()
    u.sort_indices()
    seen: dict[tuple[bytes, float], int] = {}
    first: list[int] = []
    inverse = np.empty(u.shape[0], dtype=np.int64)
    for i in range(u.shape[0]):
        k = (u.indices[u.indptr[i] : u.indptr[i + 1]].tobytes(), round(float(low[i]), 9))
        if k not in seen:
            seen[k] = len(first)
            first.append(i)
        inverse[i] = seen[k]
    return np.asarray(first, dtype=np.int64), inverse


def undominated_rows(
    u: sp.csr_matrix,
    low: NDArray[np.float64],
    centres: tuple[NDArray[np.float64], NDArray[np.float64], float] | None = None,
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """One row per distinct (U, low), then only the undominated (:func:`connected_cover`): the rows kept and, for every
    row, the index of its kept one among them (-1 where dominated). With ``centres`` (x, y and the side of a grid of
    patches) those a near patch dominates go first (:func:`near_dominated`), at no cost to the result."""
    first, inverse = distinct_rows(u, low)
    kept = np.ones(first.size, dtype=bool)
    if centres is not None:
        kept = ~near_dominated(u[first].tocsr(), low[first], centres[0][first], centres[1][first], centres[2])
    at = np.flatnonzero(kept)
    kept[at[dominated(u[first[at]].tocsr(), low[first[at]])]] = False
    return first[kept], np.where(kept[inverse], np.cumsum(kept)[inverse] - 1, -1)


def near_dominated(
    u: sp.csr_matrix, low: NDArray[np.float64], cx: NDArray[np.float64], cy: NDArray[np.float64], h: float
) -> NDArray[np.bool_]:
    """Mask of the patches of a grid (side ``h``) that a patch within :data:`_NEAR` cells dominates: P before Q in a
    strict order (larger U first, then smaller low, then index) with U(P) holding U(Q) and low(P) <= low(Q). All go at
    once: each Q's chain of dominators ends at a kept patch that dominates it (the relation is transitive), so
    :func:`planner.solve.presolve.dominated` on the rest keeps what it keeps on all."""
    n = u.shape[0]
    size = u.getnnz(axis=1)
    pos = np.empty(n, dtype=np.int64)
    pos[np.lexsort((np.arange(n), low, -size))] = np.arange(n)
    ix, iy = np.rint((cx - cx.min()) / h).astype(np.int64), np.rint((cy - cy.min()) / h).astype(np.int64)
    span = int(iy.max(initial=0)) + 2 * _NEAR + 1
    code = (ix + _NEAR) * span + iy + _NEAR
    at = np.full(int(code.max(initial=0)) + _NEAR * span + _NEAR + 1, -1, dtype=np.int64)
    at[code] = np.arange(n)
    out = np.zeros(n, dtype=bool)
    for dx in range(-_NEAR, _NEAR + 1):
        for dy in range(-_NEAR, _NEAR + 1):
            p = at[code + dx * span + dy]
            q = np.flatnonzero(p >= 0)
            p = p[q]
            ok = (pos[p] < pos[q]) & (low[p] <= low[q]) & (size[p] >= size[q])
            q, p = q[ok], p[ok]
            shared = np.asarray(u[q].multiply(u[p]).sum(axis=1)).ravel()
            out[q[shared == size[q]]] = True
    return out


def quick_bound(pieces: SidePieces, share: float, target: SupportsInt, box_patches: int = QUICK_PATCHES) -> Refined:
    """The connected cover over one grid of patches bounded without a search (:mod:`planner.bounds.patch_cover`):
    about ``box_patches`` patches over the box of the zone-side's regions (the ring walk's first side, whose grid it
    shares: :meth:`planner.bounds.plane_patches.SidePieces.grid`). Where it holds more than :data:`QUICK_NEAR`
    distinct patches that no near one dominates, or more than :data:`QUICK_FAMILY` undominated ones, the side grows once,
    to about :data:`QUICK_COARSE` of the former; where the coarser side still holds too many, no bound (0). Its ``steps`` is 0; ``proven`` says whether it reached ``target``: the plan then gives a cover
    over these patches of that size, so that is the cover's optimum."""
    box = live_box(pieces.outer)
    if box is None or not pieces.required.any():
        return Refined(0, 0, 0, 0.0, False)
    h = max(math.sqrt((box[2] - box[0]) * (box[3] - box[1]) / box_patches), MIN_PATCH_M)
    for last in (False, True):
        got = pieces.grid(h)
        if got is None:
            break
        first = distinct_rows(got[0], got[1])[0]
        first = first[~near_dominated(got[0][first].tocsr(), got[1][first], got[2][first], got[3][first], h)]
        near = first.size
        if near > QUICK_NEAR and not last:
            h *= math.sqrt(near / QUICK_COARSE)
            continue
        cells = np.rint(np.stack([got[2][first], got[3][first]], axis=1) / h).astype(np.int64)
        u, low = got[0][first].tocsr(), got[1][first]
        found = family_bound(u, low, cells, pieces.lengths, pieces.required, share, target, QUICK_FAMILY)
        if found is None:  # more than QUICK_FAMILY undominated patches
            if last:
                break
            h *= math.sqrt(near / QUICK_COARSE)
            continue
        return Refined(found[0], 0, found[1], h, found[0] >= int(target))
    return Refined(0, 0, 0, h, False)


def connected_cover(
    u: sp.csr_matrix,
    low: NDArray[np.float64],
    lengths: NDArray[np.float64],
    required: NDArray[np.bool_],
    share: float,
    work_s: float,
) -> tuple[int, bool, list[int]]:
    """The connected cover of the ``required`` pieces over the patches under the relaxed links: (its optimum, or its
    proven lower bound rounded up when not proven; proven; the rows chosen, with every row equal to one). One row per
    distinct (U, low), then only the undominated: Q goes for a kept P with U(P) holding U(Q) and low(P) <= low(Q)
    (:func:`planner.solve.presolve.dominated` with low as the cost). P then has every relaxed link Q has (more shared
    wall, a smaller need), so P stands in for Q in any connected cover; the links are formed among the kept rows
    only."""
    first, inverse = undominated_rows(u, low)
    ur, lr = u[first].tocsr(), low[first]
    n = first.size
    inst = CoverInstance(
        by_candidate=ur[:, np.flatnonzero(required)].tocsr(),
        cost=np.ones(n),
        groups=("side",) * n,
        target_length_m=lengths[required],
        relation=relaxed_links(ur, lr, lengths, share),
    )
    res = solve(inst, MilpOptions(overlap=SITE_SHARE.rule(share), work_limit=work_s))
    proven = res.status is Status.OPTIMAL
    chosen = np.flatnonzero(np.isin(inverse, np.asarray(res.selected, dtype=np.int64))).tolist() if proven else []
    value = int(round(res.objective)) if proven and res.objective is not None else math.ceil((res.bound or 0.0) - 1e-6)
    return value, proven, chosen


def refined_bound(
    pieces: SidePieces,
    share: float,
    h0: float,
    target: int,
    steps: int,
    work_s: float = STEP_WORK_S,
    quick: Refined | None = None,
) -> Refined:
    """The refined bound of one zone-side (module docstring), from patches of side ``h0``, at most ``steps``
    refinements, stopping once it reaches ``target`` (the plan's count there). The quick bound comes first (``quick``
    where it was found already for this target); with no steps it is all there is."""
    quick = quick_bound(pieces, share, target) if quick is None else quick
    if steps == 0 or quick.bound >= target:
        return quick
    lv = _Levels(pieces, h0)
    fam = grid_family(lv)
    best, taken, proven = quick.bound, 0, False
    while True:
        value, proven, chosen = connected_cover(fam.u, fam.low, pieces.lengths, pieces.required, share, work_s)
        best = max(best, value)
        rows = np.asarray([r for r in chosen if lv.side(int(fam.level[r]) + 1) >= MIN_PATCH_M], dtype=np.int64)
        if best >= target or not proven or taken >= steps or rows.size == 0:
            break
        fam = split(fam, rows, lv)
        taken += 1
    return Refined(best, taken, int(fam.cx.size), float(lv.side(int(fam.level.max()))), proven)
