"""The ring walks of the connected plane bound (:mod:`planner.bounds.plane_ring`, whose docstring gives the
relaxation): per zone-side and patch side, the ring graph over the undominated patches and its cheapest unit-cost walk
(:func:`side_ring_bound`), kept per run by :class:`RingWalks`, and the schedule that walks the zone-sides below their
counts level by level within the work budget (:func:`walked_sides`).

A walk searched farther than a target needs gives that target's part all the same (:func:`ring_of`), so walks done
ahead of the plan (:mod:`planner.bounds.ring_ahead`) serve the bound under any counts.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, replace
from functools import partial
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.bounds.arc_reach import short_arc_ring
from planner.bounds.connected_result import SideBound
from planner.bounds.outer import OuterRegions
from planner.bounds.plane_patches import FIRST_PATCHES, SidePieces, arc_links, patch_sides, undominated
from planner.bounds.plane_refine import Refined, quick_bound, refined_bound
from planner.bounds.walk_dual import Goal
from planner.coverage.regions import FrameSpace, coverage_regions, outer_tolerance_m, region_tolerance_m
from planner.coverage.threads import ordered_map
from planner.coverage.visibility import SightLimits
from planner.site.model import Site
from planner.solve.ring import arcs, cyclic_arcs
from planner.solve.ring_unit import UnitRing, unit_ring

#: the undominated patches kept per zone-side at most where the links among them are formed (pairwise)
MAX_FAMILY = 6_000
#: ... and where every patch sees one unbroken run of wall, so short that no links are formed (:func:`short_arc_ring`).
#: Only there does a finer side tighten the bound that no quick cover then raises (:func:`arcs_only`: polygon A's
#: outside, 13 stations over 3.89-m patches, 14 over 1.94-m ones, with 14,386 undominated); elsewhere the quick cover
#: over the first side is run and is the stronger (A's inside 9 against walks of 8 and 9, C's 12 against 9)
MAX_ARC_FAMILY = 60_000
#: relaxed links at most (formed pairwise in dense blocks, and walked once per station of the walk: past this, a large
#: outline's links take many seconds and gigabytes)
MAX_LINKS = 3_000_000
#: the quick cover over patches (:func:`planner.bounds.plane_refine.refined_bound` with no splits) runs by default only
#: where the plan is at most this many stations above the walks' bound (Baalbek 20 -> 21, polygon A 20 -> 22, C 24 -> 27
#: with its walks' dual); a process walking ahead begins the two largest zone-sides' covers before the counts are
#: known (:meth:`RingWalks.cover_ahead`), so that most of their 1-2 CPU-s is spent while the plan is still being made
QUICK_GAP = 5
#: a zone-side whose undominated family at one patch side is past its cap (MAX_FAMILY or MAX_ARC_FAMILY) / this is not formed at the next (half as
#: large) side: halving the side has multiplied the family by 3.4-3.7 on the bundled zone-sides, so that graph would
#: pass the cap after its grid and dominance were paid for (about a CPU-second on polygon A's and C's sides)
FAMILY_GROWTH = 3


def side_ring_bound(pieces: SidePieces, share: float, h: float, target: int) -> tuple[int | None, int]:
    """The ring walk over the undominated patches of side ``h`` of one zone-side, searched only as far as it can stay
    under ``target``: (the walk's cost, or ``target`` when no walk is cheaper; None when not formed; the family size).
    The patches grow the outer regions and shrink the inner ones by half their diagonal too."""
    graph, fam, _cap = side_graph(pieces, share, h)
    if graph is None:
        return None, fam
    # a walk of fewer than target stations has both branches from its anchor at most target - 2 long
    return ring_of(True, graph.unit_walk(limit=target - 1.5), target), fam  # every patch costs one station


def ring_of(formed: bool, walk: int | None, target: int) -> int | None:
    """The ring walk's part (:func:`side_ring_bound`) from a walk searched at least as far as ``target - 1.5`` (any
    farther search gives the same: every walk under ``target`` lies within that reach): None when not formed, else the
    walk's cost, ``target`` at most."""
    if not formed:
        return None
    return target if walk is None else min(target, walk)


def side_graph(pieces: SidePieces, share: float, h: float) -> tuple[UnitRing | None, int, int]:
    """The ring graph over the undominated patches of side ``h`` of one zone-side, the family size and its cap; None
    where not formed (too many undominated patches or links, or arcs that do not chain). Its :meth:`UnitRing.unit_walk`
    is the ring walk (every patch costs one station). Where every patch's arc is short the links are not formed
    (:func:`short_arc_ring`, the same walk); the cap is ``MAX_ARC_FAMILY`` where every patch sees one unbroken run,
    else ``MAX_FAMILY``."""
    lengths = pieces.lengths
    got = pieces.grid(h)  # the first side's grid, shared with the quick cover over patches
    sets = None if got is None else got[:2]
    if sets is None:
        return None, 0, MAX_FAMILY
    u, low = sets
    n = u.shape[1]
    start, end = cyclic_arcs(u)
    fam = undominated(start, end - start, low, n)
    s, sp_, lw = start[fam], (end - start)[fam], low[fam]
    runs = bool(np.all(sp_ + 1 == np.diff(u.indptr)[fam]))  # every patch sees one unbroken run
    cap = MAX_ARC_FAMILY if runs else MAX_FAMILY
    if fam.size > cap:
        return None, int(fam.size), cap
    if fam.size and 2 * int(sp_.max()) + 2 < n:  # short arcs: no links formed
        return short_arc_ring(s, sp_, lw, lengths, pieces.required, share), int(fam.size), cap
    cum = np.concatenate([[0.0], np.cumsum(np.tile(lengths, 3))])
    one_way = arc_links(s, sp_, lw, cum, n, share, most=MAX_LINKS)  # None: past MAX_LINKS already
    if one_way is None:
        return None, int(fam.size), MAX_FAMILY
    adj = (one_way + one_way.T).astype(bool).tocsr()
    if adj.nnz > MAX_LINKS:
        return None, int(fam.size), MAX_FAMILY
    r = np.repeat(np.arange(fam.size), sp_ + 1)
    c = (np.concatenate([np.arange(a, a + k + 1) for a, k in zip(s, sp_)]) % n) if fam.size else np.zeros(0, int)
    cover = sp.csr_matrix((np.ones(r.size, dtype=bool), (r, c)), shape=(fam.size, n))
    return unit_ring(cover, pieces.required, adj), int(fam.size), MAX_FAMILY


class _Ahead:
    """One zone-side's quick cover begun ahead: its live goal, its result (None until done, or where not run), the
    event set when it ends, and whether it was ended early (its result unused)."""

    def __init__(self) -> None:
        self.goal = Goal()
        self.result: Refined | None = None
        self.done = threading.Event()
        self.cancelled = False


@dataclass(frozen=True)
class FarleyShares:
    """The connected bound's first part, which the plan's counts do not enter: the zone-sides (keys ``2 zone + side``)
    with their shares of Farley's bound, and why the zone-sides cannot be summed ('' when they can)."""

    keys: tuple[int, ...]
    sides: tuple[SideBound, ...]
    clash: str


class RingWalks:
    """The ring walks of one run's zone-sides: each zone-side's regions drawn once (when it first walks) and each walk
    at a patch side kept once done, so that walks done ahead (:meth:`ahead`, searched all the way) serve a later
    :func:`walked_sides` under any counts (:func:`ring_of`)."""

    def __init__(
        self,
        site: Site,
        targets: Any,
        limits: SightLimits,
        share: float,
        required: NDArray[np.bool_],
        *,
        cache: dict[int, Any],
        spaces: dict[str, FrameSpace],
        outer_regions: OuterRegions,
    ) -> None:
        self.site, self.targets, self.limits, self.share = site, targets, limits, share
        self.required = np.asarray(required, dtype=bool)
        self.cache, self.spaces, self.outer_regions = cache, spaces, outer_regions
        self.key = targets.zone.astype(np.int64) * 2 + targets.side
        self._sides: dict[int, SidePieces] = {}
        self._levels: dict[int, list[float]] = {}
        self._graphs: dict[tuple[int, int], tuple[UnitRing | None, int]] = {}  # formed ahead, not walked yet
        self._done: dict[tuple[int, int], tuple[bool, int | None, int]] = {}  # walked all the way
        self._family: dict[tuple[int, int], tuple[int, int]] = {}  # each side formed: its family and that one's cap
        self._quick: dict[int, _Ahead | None] = {}  # quick covers begun ahead (None: taken by the caller, not ahead)
        self._lock = threading.Lock()
        self._ended = False  # no quick cover is begun ahead any more

    def draw(self, keys: list[int]) -> None:
        """The regions, inner and outer, of the zone-sides ``keys`` not drawn yet (one call for all their pieces)."""
        todo = [k for k in keys if k not in self._sides]
        pieces_of = {k: np.flatnonzero(self.key == k) for k in todo}
        drawn = [int(p) for k in todo for p in pieces_of[k]]
        if not drawn:
            return
        t, limits = self.targets, self.limits
        self.cache.update(
            coverage_regions(self.site, t, limits, [p for p in drawn if p not in self.cache], self.spaces)
        )
        outer = self.outer_regions.of(self.site, t, limits, drawn)
        grow_m = outer_tolerance_m(limits)
        shrink_m = region_tolerance_m(limits, self.site.parameters.min_standoff_m)
        lengths = t.s1_m - t.s0_m
        for k, ps in pieces_of.items():
            regs = [outer[int(p)] for p in ps], [self.cache[int(p)] for p in ps]
            self._sides[k] = SidePieces(*regs, lengths[ps], self.required[ps], grow_m, shrink_m)
            self._levels[k] = list(patch_sides(self._sides[k].outer))

    def cover_ahead(self, keys: list[int]) -> threading.Thread:
        """Begin the quick covers over patches of the drawn zone-sides ``keys`` on a thread, in turn, before the plan's
        counts are known (:class:`planner.bounds.walk_dual.Goal`): a process walking ahead runs them once its walks
        are done, so that the covers the counts then ask for are ready or under way. Zone-sides whose walk formed and
        whose patches all see one unbroken run are left out (there the cover is not run: :func:`arcs_only`)."""

        def run() -> None:
            for k in keys:
                with self._lock:
                    if self._ended or k in self._quick or k not in self._sides or not self._levels[k]:
                        continue
                    slot = self._quick[k] = _Ahead()
                try:  # where the walk formed and every patch sees one run, the cover is not asked for
                    formed = self._done.get((k, 0), (False, None, 0))[0]
                    if not (formed and arcs_only(self._sides[k], self._levels[k][0])):
                        slot.result = quick_bound(self._sides[k], self.share, slot.goal)
                finally:
                    slot.done.set()

        thread = threading.Thread(target=run, name="quick covers ahead", daemon=True)
        thread.start()
        return thread

    def quick(self, key: int, target: int) -> Refined | None:
        """The quick cover of zone-side ``key`` begun ahead (:meth:`cover_ahead`), told its ``target`` and awaited:
        the same as :func:`planner.bounds.plane_refine.quick_bound` for that target wherever the target is a plan's
        count there (at least every valid bound: a run past the point where the target stops it is capped at it).
        None where none was begun (the caller makes it; none is begun after this)."""
        with self._lock:
            slot = self._quick.setdefault(key, None)
        if slot is None:
            return None
        slot.goal.value = int(target)
        slot.done.wait()
        got = slot.result
        if got is None or slot.cancelled:
            return None
        return replace(got, bound=min(got.bound, int(target)), proven=got.bound >= int(target))

    def end_covers_ahead(self, needed: list[int]) -> None:
        """Begin no more quick covers ahead, and end those under way that the zone-sides ``needed`` do not include at
        their next round (goal 0; their results are then not used)."""
        with self._lock:
            self._ended = True
            for k, slot in self._quick.items():
                if slot is not None and k not in needed:
                    slot.cancelled = True
                    slot.goal.value = 0

    def side(self, key: int) -> SidePieces:
        """The regions of zone-side ``key`` (drawn now where they are not yet)."""
        self.draw([key])
        return self._sides[key]

    def levels(self, key: int) -> list[float]:
        """The patch sides zone-side ``key`` is walked at, in turn (:func:`patch_sides`)."""
        self.draw([key])
        return self._levels[key]

    def prepare(self, key: int, level: int) -> bool:
        """Form the ring graph of zone-side ``key`` at its ``level``-th patch side, kept for its walk; whether it
        formed."""
        done = self._done.get((key, level))
        if done is not None:
            return done[0]
        if (key, level) not in self._graphs:
            self._graphs[key, level] = self._formed(key, level)
        return self._graphs[key, level][0] is not None

    def _formed(self, key: int, level: int) -> tuple[UnitRing | None, int]:
        """:func:`side_graph` of zone-side ``key`` at its ``level``-th patch side, not formed (None, 0) where the
        family one level coarser was past its cap / ``FAMILY_GROWTH`` (:data:`FAMILY_GROWTH`)."""
        fam, cap = self._family.get((key, level - 1), (0, MAX_FAMILY))
        if fam * FAMILY_GROWTH > cap:
            return None, 0
        graph, fam, cap = side_graph(self.side(key), self.share, self.levels(key)[level])
        self._family[key, level] = fam, cap
        return graph, fam

    def ahead(self, key: int, level: int) -> None:
        """Walk zone-side ``key`` at its ``level``-th patch side all the way (for any counts later), on the graph
        :meth:`prepare` formed (formed now where it did not); the graph is then let go."""
        if (key, level) in self._done:
            return
        self.prepare(key, level)
        graph, fam = self._graphs.pop((key, level))
        self._done[key, level] = (graph is not None, None if graph is None else graph.unit_walk(limit=np.inf), fam)

    def walk(self, key: int, level: int, target: int) -> tuple[int | None, int]:
        """:func:`side_ring_bound` of zone-side ``key`` at its ``level``-th patch side: from the walk done ahead where
        there is one, else from the graph formed ahead, else formed now; the walk searched only as far as ``target``
        needs where not done ahead."""
        done = self._done.get((key, level))
        if done is not None:
            return ring_of(done[0], done[1], target), done[2]
        if (key, level) in self._graphs:
            graph, fam = self._graphs.pop((key, level))
            if graph is None:
                return None, fam
            return ring_of(True, graph.unit_walk(limit=target - 1.5), target), fam
        graph, fam = self._formed(key, level)
        if graph is None:
            return None, fam
        # a walk of fewer than target stations has both branches from its anchor at most target - 2 long
        return ring_of(True, graph.unit_walk(limit=target - 1.5), target), fam


def walked_sides(
    head: FarleyShares, walks: RingWalks, counts: dict[int, int], work_patches: int, refine_steps: int
) -> tuple[SideBound, ...]:
    """The zone-sides' parts: Farley's shares of ``head`` raised by the ring walks (level by level across the
    zone-sides below their counts, within ``work_patches``) and, with ``refine_steps``, the refined cover."""
    keys, sides = list(head.keys), list(head.sides)
    # only a zone-side below its count walks rings (or is refined): its pieces' regions, inner and outer, drawn now
    walk = [walks.share > 0 and sides[i].value < counts.get(k, 0) for i, k in enumerate(keys)]
    walks.draw([k for k, w_ in zip(keys, walk) if w_])
    levels = [walks.levels(k) if w_ else [] for k, w_ in zip(keys, walk)]
    spent, open_ = 0, [True] * len(keys)
    for level in range(max((len(x) for x in levels), default=0)):
        run = []  # the zone-sides that walk at this level: decided before any walks (a walk changes only its side)
        for i, k in enumerate(keys):
            if not open_[i] or level >= len(levels[i]) or sides[i].value >= counts.get(k, 0):
                open_[i] = False
                continue
            cost = FIRST_PATCHES * 4**level
            if spent + cost > work_patches:
                open_[i] = False  # the budget: this side keeps what it has
                continue
            spent += cost
            run.append(i)
        walked = ordered_map(partial(_walk_level, walks, keys, counts, level), run)  # side by side
        for i, (ring, fam) in zip(run, walked):
            h = levels[i][level]
            if ring is None:
                open_[i] = False  # too many patches or undominated ones, or arcs that do not chain
            elif ring > (sides[i].ring or 0):
                sides[i] = SideBound(sides[i].zone_side, sides[i].farley, ring, h, fam)
    # the quick cover over patches (no search) where the plan is within QUICK_GAP of the walks' bound
    gap = sum(counts.get(k, 0) for k in keys) - sum(s.value for s in sides)
    cover = refine_steps > 0 or gap <= QUICK_GAP
    needed = [k for i, k in enumerate(keys) if cover and levels[i] and sides[i].value < counts.get(k, 0)]
    walks.end_covers_ahead(needed)  # covers begun ahead that no zone-side takes stop at their next round
    for i, k in enumerate(keys):
        if not (cover and levels[i] and sides[i].value < counts.get(k, 0)):  # levels: none for share 0
            continue
        if not refine_steps and sides[i].ring is not None and arcs_only(walks.side(k), levels[i][0]):
            continue
        quick = walks.quick(k, counts[k])
        refined = refined_bound(walks.side(k), walks.share, levels[i][0], counts[k], refine_steps, quick=quick)
        sides[i] = replace(sides[i], refined=refined)
    return tuple(sides)


def arcs_only(pieces: SidePieces, h: float) -> bool:
    """Whether every patch of side ``h`` (the ring walk's first, whose grid is kept) may see only a run of consecutive
    pieces: then the connected cover over those patches *is* the ring walk over them (the ring theorem,
    :mod:`planner.solve.ring`; the cover's links only add the float slack of
    :func:`planner.bounds.plane_refine.relaxed_links`). Where that walk was formed the quick cover is not run: at that side
    it cannot pass the walk, and at the coarser side it takes when the patches are many it seldom does (polygon A's
    outside: 3.89-m patches, walk 13; the cover over 4.34-m patches 12)."""
    got = pieces.grid(h)
    if got is None:
        return False
    start, _, exact = arcs(got[0])
    return bool(exact[start >= 0].all())


def _walk_level(
    walks: RingWalks, keys: list[int], counts: dict[int, int], level: int, i: int
) -> tuple[int | None, int]:
    """:meth:`RingWalks.walk` of zone-side ``i`` at ``level``."""
    return walks.walk(keys[i], level, counts.get(keys[i], 0))
