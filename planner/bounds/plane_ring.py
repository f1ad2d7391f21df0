"""A bound for connected plans over every position in the plane: the ring walk over patches.

The ring bound (:mod:`planner.solve.ring`) replaces each candidate's coverage by the smallest cyclic arc that holds it
and finds the cheapest walk of linked arcs round a zone-side: a lower bound over the candidate pool. Here the candidates
are replaced by *patches*, squares of side h that tile the plane, so that the bound holds for stations anywhere.

**Relaxation.** For a patch P let U(P) be the pieces whose outer region O_t (grown by its tolerance) meets P, and l(P)
the wall length of the pieces whose region R_t (shrunk by its tolerance) holds all of P. Every position p in P covers a
set C(p) with C(p) within U(P), so within the smallest arc A(P) that holds U(P), and covers at least l(P) of wall. Two
stations p, q may be registered when they share at least f min(L(p), L(q)) of wall, f the overlap share
(:class:`planner.coverage.overlap.OverlapRule`) and L their covered lengths; then |A(P) n A(Q)| >= |C(p) n C(q)| >= f
min(l(P), l(Q)) and that shared length is > 0. So a relaxed link "arcs share more than 0 and at least f min(l(P), l(Q))"
joins the patches of every registered pair, and a connected plan of k stations, each replaced by its patch, is a
connected set of at most k patches whose arcs cover the zone-side. Its cheapest walk (the ring theorem) is therefore a
lower bound on the number of stations of any connected plan, with stations anywhere. A patch m with A(m) holding A(p)
and l(m) <= l(p) does everything p does (its links are a superset), so only such undominated patches are kept.

**Sum over zone-sides.** In ``zone`` registration each zone-side is its own network. When no position can see pieces of
two zone-sides (their grown outer regions do not meet, checked), the stations split by the zone-side they see, and the
plan's count is at least the sum over zone-sides of the larger of the ring walk and the zone-side's share of Farley's
bound (its duals over the heaviest weight of its own regions).

The bound tightens as h shrinks (U(P) and l(P) tend to the coverage of a point): it is tried at the sides of
:func:`planner.bounds.plane_patches.patch_sides` in turn, level by level across the zone-sides, a zone-side dropping out
when it reaches the plan's count there or its walk cannot be formed, until the next level would pass the patch budget
(:data:`CONNECTED_WORK_PATCHES`).
"""

from __future__ import annotations

import itertools
import time
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.bounds.connected_result import ConnectedPlaneBound, SideBound
from planner.bounds.outer import OuterRegions
from planner.bounds.ring_walks import FarleyShares, RingWalks, walked_sides
from planner.coverage.arrangement import grown, grown_reach, outer_max_weight
from planner.coverage.matrix import CoverageProblem
from planner.coverage.regions import FrameSpace, outer_tolerance_m
from planner.coverage.visibility import SightLimits
from planner.site.model import Site

if TYPE_CHECKING:
    from planner.bounds.ring_ahead import WalksAhead

#: the work the default plan gives the connected plane bound, in patches: a patch side of a zone-side costs the patches
#: it lays (about FIRST_PATCHES, then 4x at each halving). A count, not a time: the same bound under any load
CONNECTED_WORK_PATCHES = 200_000
#: two zone-sides' regions are tested pair by pair while the pairs whose boxes meet are at most this many per region;
#: past it their unions are formed and tested once
_PAIRS_PER = 20
#: two zone-sides count as apart (:func:`_apart`) only when their stand areas keep this much more than the growth (m)
_APART_M = 1e-6


def farley_shares(
    site: Site,
    problem: CoverageProblem,
    limits: SightLimits,
    duals: NDArray[np.float64],
    outer_regions: OuterRegions,
) -> FarleyShares:
    """Each zone-side's share of Farley's bound (its duals over the heaviest weight of the outer regions of its pieces
    of positive dual) and the test that no position sees two zone-sides (:func:`_sides_meet`)."""
    t = problem.targets
    key = t.zone.astype(np.int64) * 2 + t.side
    seen = problem.by_target.getnnz(axis=1) > 0
    keys = [int(k) for k in np.unique(key[seen])]
    pieces_all = [np.flatnonzero(key == k) for k in keys]
    grow_m = outer_tolerance_m(limits)
    # Farley's share of each zone-side weighs the outer regions of its pieces of positive dual only
    pos_all = [np.flatnonzero(duals[ps] > 1e-9) for ps in pieces_all]
    weighed = [int(p) for ps, pos in zip(pieces_all, pos_all) for p in ps[pos]]
    outer = outer_regions.of(site, t, limits, weighed)
    grown_of = dict(zip(weighed, grown([outer[p] for p in weighed], grow_m)))  # once: Farley's and the sides' test
    sides = []
    for pieces, pos in zip(pieces_all, pos_all):
        y = duals[pieces]
        regs = [outer[int(p)] for p in pieces[pos]]
        w = outer_max_weight(regs, y[pos], grow_m, [grown_of[int(p)] for p in pieces[pos]]) if pos.size else 0.0
        sides.append(SideBound(_name(t, pieces[0]), float(y.sum()) / max(1.0, w), None, None, 0))
    clash = _sides_meet(site, t, limits, pieces_all, outer_regions, grow_m=grow_m, grown_of=grown_of)
    return FarleyShares(tuple(keys), tuple(sides), clash)


def connected_plane_bound(
    site: Site,
    problem: CoverageProblem,
    limits: SightLimits,
    share: float,
    duals: NDArray[np.float64],
    counts: dict[int, int],
    *,
    work_patches: int = CONNECTED_WORK_PATCHES,
    cache: dict[int, Any] | None = None,
    refine_steps: int = 0,
    spaces: dict[str, FrameSpace] | None = None,
    outer_regions: OuterRegions | None = None,
    ahead: WalksAhead | None = None,
) -> ConnectedPlaneBound:
    """The connected bound over the plane for ``zone`` registration (module docstring). ``counts``: the plan's stations
    per zone-side (key ``2 zone + side``). With ``refine_steps``, a zone-side still below its count then gets the
    connected cover over patches refined up to that many times (:func:`planner.bounds.plane_refine.refined_bound`).
    ``cache``/``spaces`` and ``outer_regions``: the regions R_t and O_t this run has drawn already (pricing's).
    ``ahead``: the walks started on a second core before the plan was known
    (:class:`planner.bounds.ring_ahead.WalksAhead`); it gives the same bound, and where it fails (or with
    ``refine_steps``) the walks are done here."""
    t0 = time.perf_counter()
    outer_regions = OuterRegions() if outer_regions is None else outer_regions
    head = farley_shares(site, problem, limits, duals, outer_regions)
    if head.clash:
        return ConnectedPlaneBound(None, (), time.perf_counter() - t0, head.clash)
    required = problem.by_target.getnnz(axis=1) > 0
    # the refined cover (CP-SAT) is not run in the forked process: with refine steps, the walks are done here
    sides = None if ahead is None or refine_steps else ahead.walked(head, counts, required, work_patches, 0)
    if sides is None:
        cache, spaces = ({} if cache is None else cache), ({} if spaces is None else spaces)
        walks = RingWalks(
            site, problem.targets, limits, share, required, cache=cache, spaces=spaces, outer_regions=outer_regions
        )
        sides = walked_sides(head, walks, counts, work_patches, refine_steps)
    return ConnectedPlaneBound(sum(s.value for s in sides), sides, time.perf_counter() - t0)


def _name(t: Any, piece: int) -> str:
    return f"{t.zone_ids[int(t.zone[piece])]}/{'inside' if t.side[piece] == 0 else 'outside'}"


def _sides_meet(
    site: Site,
    t: Any,
    limits: SightLimits,
    pieces_all: list[NDArray[np.int64]],
    outer_regions: OuterRegions,
    *,
    grow_m: float,
    grown_of: dict[int, Any],
) -> str:
    """Why the zone-sides cannot be summed ('' when they can): two of one frame whose outer regions grown by ``grow_m``
    meet (a position there could serve both), i.e. a region of one meets a region of the other. Two zone-sides are apart
    outright where the stand area of an inside one (which holds its regions) keeps more than the growth inside its zone's
    polygon and the other's stand area more than that outside it (:func:`_apart`); the others are asked pair by pair of
    grown regions whose boxes meet (an STR-tree), or of the two zone-sides' unions where such pairs are many
    (:data:`_PAIRS_PER`). ``grown_of``: the grown regions drawn already, per piece (those drawn here are added)."""
    by_frame: dict[int, list[tuple[str, NDArray[np.int64], int]]] = {}
    for pieces in pieces_all:
        code = int(t.zone[pieces[0]]) * 2 + int(t.side[pieces[0]])
        by_frame.setdefault(int(t.frame[pieces[0]]), []).append((_name(t, pieces[0]), pieces, code))
    reach = grown_reach(grow_m) + _APART_M
    for fi, items in by_frame.items():
        space = outer_regions.space(site, t.frames[fi], limits)
        stand = {code: (space.inside if code % 2 == 0 else space.outside)[code // 2] for _, _, code in items}
        pending = [
            (p, q)
            for p, q in itertools.combinations(items, 2)
            if not (_apart(site, stand, p[2], q[2], reach) or _apart(site, stand, q[2], p[2], reach))
        ]
        need = list(dict.fromkeys(int(x) for p, q in pending for x in (*p[1], *q[1]) if int(x) not in grown_of))
        outer = outer_regions.of(site, t, limits, need)
        grown_of.update(zip(need, grown([outer[x] for x in need], grow_m)))
        geoms = {
            name: np.asarray([g for g in (grown_of[int(x)] for x in pieces) if not g.is_empty], dtype=object)
            for name, pieces, _ in (item for pair in pending for item in pair)
        }
        trees: dict[str, Any] = {}
        unions: dict[str, Any] = {}
        for (p, _, _), (q, _, _) in pending:
            gp, gq = geoms[p], geoms[q]
            trees[p] = trees[p] if p in trees else shapely.STRtree(gp)
            near = trees[p].query(gq)  # pairs whose boxes meet
            if near.shape[1] <= _PAIRS_PER * (gp.size + gq.size):
                meet = bool(shapely.intersects(gp[near[1]], gq[near[0]]).any())
            else:
                for name, g in ((p, gp), (q, gq)):
                    if name not in unions:
                        unions[name] = shapely.union_all(g)
                meet = bool(unions[p].intersects(unions[q]))
            if meet:
                return f"not formed: {p} and {q} can be seen from one position (their outer coverage regions meet)"
    return ""


def _apart(site: Site, stand: dict[int, Any], mine: int, other: int, reach: float) -> bool:
    """Whether no grown region of zone-side ``mine`` (an inside one, ``2 zone + 0``) can meet one of ``other``: the
    stand area of ``mine`` lies in its zone's polygon farther than ``reach`` from its outline, and that of ``other``
    farther than ``reach`` from the polygon (a region grown by less than ``reach`` stays on its own side)."""
    if mine % 2 != 0:
        return False
    a, b = stand[mine], stand[other]
    if a.is_empty or b.is_empty:
        return True
    zone = site.zones[mine // 2].polygon
    inside = bool(shapely.covered_by(a, zone)) and float(shapely.distance(a, zone.boundary)) > reach
    return inside and float(shapely.distance(b, zone)) > reach
