"""Geometric column generation: grow the candidate pool until the cover LP's bound holds for every position in the plane
(at the chosen wall discretisation), or say that it holds over the pool only.

Each round solves the cover LP on the pool, takes the pieces with a positive dual, builds (once) their coverage regions
and looks for the heaviest points of their closed arrangement, frame by frame. A point heavier than the station cost (1)
prices out: it is tested with the coverage test itself and added as a candidate when its true covered pieces price out
too. The bound over the plane is Farley's, ``sum(y) / max(1, w*)`` for the last LP's duals ``y``, with ``w*`` the
heaviest weight of any position over the regions *grown* by the tolerance
(:func:`planner.coverage.arrangement.outer_max_weight`): ``y / max(1, w*)`` is dual feasible for every position, so the
bound holds for every cover from any positions.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import shapely

from planner.bounds.outer import OuterRegions
from planner.candidates.closed_form import SIDE_TAG
from planner.coverage.arrangement import heaviest_points, outer_max_weight
from planner.coverage.matrix import CoverageProblem, build_coverage, merge_problems
from planner.coverage.regions import FrameSpace, coverage_regions, outer_tolerance_m, region_tolerance_m
from planner.coverage.visibility import SightLimits
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Site
from planner.solve.pricing import WarmCoverLp
from planner.solve.result import SolveResult, Status

#: a face or column prices out when its dual weight exceeds the cost by more than this
PRICE_EPS = 1e-7
#: after convergence, points within this of the cost (reduced cost ~0) join the pool as alternatives
TIE_EPS = 1e-6
#: pricing's work limit: the (point, region) pairs found in weighing the points of the rounds' arrangements, summed (a
#: count that follows the cost of a round, whose bulk is that weighing). No round starts once it is reached
PRICING_WORK = 16_000_000


#: what a plane certificate assumes (plan.json ``certificate.assumes``, the summary)
ASSUMES = (
    "walls cut into pieces of the target spacing, each covered only when one station sees all of it; "
    "coverage regions exact to within the tolerance"
)


@dataclass(frozen=True)
class PricingReport:
    """What pricing established: ``lp_bound``, the cover LP over the final pool; ``plane_lp_bound``, Farley's bound over
    the plane (module docstring) with ``w*`` in ``heaviest_weight``; ``converged``: no point of the arrangement priced
    out; ``work``: the (point, region) pairs its rounds weighed (:data:`PRICING_WORK`); ``wall_cap_hit``: the user's
    wall-clock cap, not the round or work limit, stopped it (then the bound may depend on the machine's load)."""

    converged: bool
    lp_bound: float
    plane_lp_bound: float
    rounds: int
    columns_added: int
    time_s: float
    tolerance_m: float
    note: str = ""
    history: tuple[float, ...] = field(default_factory=tuple)
    plane_history: tuple[float, ...] = field(default_factory=tuple)
    heaviest_weight: float = 0.0
    duals: tuple[float, ...] = field(default_factory=tuple, repr=False)  # the last LP's y, per piece
    wall_cap_hit: bool = False
    work: int = 0

    @property
    def integer_bound(self) -> int:
        """ceil of the pool's LP bound: no cover from the pool has fewer stations."""
        return math.ceil(self.lp_bound - 1e-6)

    @property
    def plane_bound(self) -> int:
        """ceil of the plane LP bound: no cover from any positions has fewer stations."""
        return math.ceil(self.plane_lp_bound - 1e-6)

    def to_dict(self) -> dict[str, Any]:
        return {
            "converged": self.converged,
            "pool_lp_bound": self.lp_bound,
            "pool_integer_bound": self.integer_bound,
            "plane_lp_bound": self.plane_lp_bound,
            "plane_bound": self.plane_bound,
            "heaviest_weight": self.heaviest_weight,
            "rounds": self.rounds,
            "columns_added": self.columns_added,
            "time_s": self.time_s,
            "tolerance_m": self.tolerance_m,
            "note": self.note,
            "wall_cap_hit": self.wall_cap_hit,
            "work": self.work,
            "pool_lp_history": list(self.history),
            "plane_lp_history": list(self.plane_history),
        }

    def summary(self) -> str:
        head = (
            f"pricing: cover LP {self.lp_bound:.3f} over the pool; over every position in the plane "
            f"LP >= {self.plane_lp_bound:.3f} (>= {self.plane_bound} stations; heaviest position weight "
            f"{self.heaviest_weight:.4f} over outer regions grown by {self.tolerance_m * 1000:.3f} mm)"
        )
        state = "converged" if self.converged else "not converged"
        return f"{head}; {state}, {self.rounds} rounds, {self.columns_added} columns added, {self.time_s:.1f} s" + (
            f"; {self.note}" if self.note else ""
        )


def _owner(problem: CoverageProblem, row: int) -> tuple[str, ScanSide]:
    """The zone-side whose pieces a priced column covers most of (its registration group)."""
    t = problem.targets
    cols = problem.by_candidate.indices[problem.by_candidate.indptr[row] : problem.by_candidate.indptr[row + 1]]
    keys, counts = np.unique(t.zone[cols].astype(np.int64) * 2 + t.side[cols], return_counts=True)
    k = int(keys[np.argmax(counts)])
    return t.zone_ids[k // 2], (ScanSide.INSIDE if k % 2 == 0 else ScanSide.OUTSIDE)


def _heaviest(
    cache: dict[int, shapely.Geometry],
    t: Any,
    pos: np.ndarray,
    y: np.ndarray,
    per_round: int,
    threshold: float = 1.0 + PRICE_EPS,
    work: list[int] | None = None,
) -> list[tuple[int, Any]]:
    """Points of the closed arrangements (one per frame) of the regions of the pieces ``pos`` weighing more than
    ``threshold`` (by default: those that price out); ``work`` gets the pairs weighed appended."""
    return [
        (fi, f)
        for fi, here in _frames(t, pos)
        for f in heaviest_points([cache[int(k)] for k in here], y[here], threshold, per_round, work)
    ]


def _frames(t: Any, pos: np.ndarray):
    """The pieces ``pos`` frame by frame: (frame index, its pieces), frames with none left out."""
    for fi in range(len(t.frames)):
        here = pos[t.frame[pos] == fi]
        if here.size:
            yield fi, here


def _outer(site: Site, t: Any, limits: SightLimits, pos: np.ndarray, y: np.ndarray, regions: OuterRegions) -> float:
    """``w*``: the arrangement of the outer regions O_t grown by :func:`outer_tolerance_m`, per frame."""
    outer = regions.of(site, t, limits, pos)
    grow = outer_tolerance_m(limits)
    return max([0.0, *(outer_max_weight([outer[int(k)] for k in here], y[here], grow) for _, here in _frames(t, pos))])


def _add_points(
    site: Site,
    t: Any,
    model: WarmCoverLp,
    points: list[tuple[int, Any]],
    y: np.ndarray,
    limits: SightLimits,
    tag: str,
    threshold: float,
) -> tuple[CoverageProblem | None, int]:
    """Those ``points`` (frame index, sample) whose coverage of the targets ``t`` by the coverage test weighs more than
    ``threshold``, as priced candidates owned by the zone-side they see most of (None where none does); also added to
    ``model``. The pool takes them at the end (:func:`_merged`)."""
    new = [
        Candidate(f"{tag}.{k}", "", ScanSide.INSIDE, t.frames[fi], f.x, f.y, CandidateKind.PRICED)
        for k, (fi, f) in enumerate(points, 1)
    ]
    if not new:
        return None, 0
    sub = build_coverage(site, new, t, limits)
    gain = np.asarray(sub.by_candidate.astype(np.float64) @ y).ravel()
    good = np.flatnonzero(gain > threshold)
    if good.size == 0:
        return None, 0
    keep = sub.by_candidate[good]
    owners = [_owner(sub, int(g)) for g in good]
    cands = tuple(
        Candidate(f"{z}-{SIDE_TAG[s]}-{new[g].id}", z, s, new[g].frame, new[g].x, new[g].y, CandidateKind.PRICED)
        for g, (z, s) in zip(good, owners)
    )
    piece = CoverageProblem(
        candidates=cands,
        targets=t,
        by_candidate=keep,
        by_target=keep.T.tocsr(),
        slant_m=sub.slant_m[good],
        incidence_deg=sub.incidence_deg[good],
        excluded={},
        limits=sub.limits,
    )
    model.add_columns(keep)
    return piece, len(cands)


def _merged(problem: CoverageProblem, pieces: list[CoverageProblem]) -> CoverageProblem:
    """``problem`` with the priced ``pieces`` appended in their order: the pieces merged among themselves first and the
    pool once (the same problem as merging each round, without copying the whole pool every round)."""
    if not pieces:
        return problem
    new = pieces[0]
    for piece in pieces[1:]:
        new = merge_problems(new, piece)
    return merge_problems(problem, new)


def price_plane(
    site: Site,
    problem: CoverageProblem,
    limits: SightLimits,
    *,
    max_rounds: int = 400,
    per_round: int = 100,
    time_limit_s: float | None = None,
    max_work: int | None = PRICING_WORK,
    ties: int = 1000,
    cache: dict[int, shapely.Geometry] | None = None,
    spaces: dict[str, FrameSpace] | None = None,
    outer: OuterRegions | None = None,
) -> tuple[CoverageProblem, PricingReport]:
    """Add priced columns to ``problem`` until none prices out or a limit stops it; then bound the plane (module
    docstring). Limits: ``max_rounds`` rounds and ``max_work`` (point, region) pairs weighed, counts (the same columns
    under any load), and only where the user sets one a wall-clock cap ``time_limit_s``. ``cache``/``spaces`` and
    ``outer``: the regions R_t and O_t already drawn in this run (filled in here for the next user)."""
    start = time.perf_counter()
    tol = region_tolerance_m(limits, site.parameters.min_standoff_m)
    cache = {} if cache is None else cache
    spaces = {} if spaces is None else spaces
    t = problem.targets
    added, history, note = 0, [], ""
    pieces: list[CoverageProblem] = []  # the priced candidates of each round, appended to the pool at the end
    rounds, converged, capped = 0, False, False
    work: list[int] = []  # (point, region) pairs weighed, per weighing
    outer = OuterRegions() if outer is None else outer
    model = WarmCoverLp(problem.by_target)
    while True:
        lp = model.solve()
        history.append(lp.value)
        pos = np.flatnonzero(lp.y > 1e-9)
        missing = [int(k) for k in pos if int(k) not in cache]
        cache.update(coverage_regions(site, t, limits, missing, spaces))
        capped = time_limit_s is not None and time.perf_counter() - start > time_limit_s
        spent = max_work is not None and sum(work) >= max_work
        if rounds >= max_rounds or capped or spent:
            note = _stopped(rounds, start, time_limit_s if capped else None, max_work if spent else None, max_rounds)
            break
        rounds += 1
        faces = _heaviest(cache, t, pos, lp.y, per_round, work=work)
        if not faces:
            converged = True
            break
        piece, n = _add_points(site, t, model, faces, lp.y, limits, f"PR{rounds}", 1.0 + PRICE_EPS)
        if piece is None:
            note = (
                f"{len(faces)} arrangement points price out by their regions but none by the coverage test "
                f"(within the {tol:.4f} m tolerance)"
            )
            break
        added += n
        pieces.append(piece)
    if converged and ties:  # the optimal LP's alternatives: positions as good as its columns (reduced cost 0)
        points = _heaviest(cache, t, pos, lp.y, ties, 1.0 - TIE_EPS)
        piece, n = _add_points(site, t, model, points, lp.y, limits, "PT", 1.0 - TIE_EPS)
        added += n
        pieces += [] if piece is None else [piece]
    problem = _merged(problem, pieces)
    model.close()
    w_star = _outer(site, t, limits, pos, lp.y, outer)
    farley = float(lp.y.sum()) / max(1.0, w_star)
    report = PricingReport(
        converged,
        history[-1],
        farley,
        rounds,
        added,
        time.perf_counter() - start,
        outer_tolerance_m(limits),
        note,
        tuple(history),
        (farley,),
        w_star,
        tuple(map(float, lp.y)),
        capped,
        sum(work),
    )
    return problem, report


def _stopped(rounds: int, start: float, cap_s: float | None, work: int | None, max_rounds: int) -> str:
    """Why pricing stopped before it converged: the cap ``cap_s`` or work limit ``work`` reached (or None), else its
    rounds."""
    why = (
        f"the wall-clock cap of {cap_s:g} s; may depend on the load"
        if cap_s is not None
        else f"its work limit of {work:,} weighed pairs"
        if work is not None
        else f"its {max_rounds} rounds"
    )
    return f"stopped after {rounds} rounds / {time.perf_counter() - start:.0f} s before pricing converged ({why})"


def with_plane_bound(result: SolveResult, pricing: PricingReport) -> SolveResult:
    """The MILP result with ``info['pool_bound']`` (the MILP's own), ``info['plane_bound']`` (Farley's, rounded up) and
    ``info['bound_scope']``: ``plane`` when the plan meets the plane bound (``bound`` becomes it), else ``pool``."""
    info = dict(result.info)
    info["pricing"] = pricing.to_dict()
    plane = pricing.plane_bound
    info["pool_bound"] = result.bound
    info["plane_bound"] = plane
    info["certificate"] = {
        "assumes": ASSUMES,
        "tolerance_m": pricing.tolerance_m,
        "plane_bound_from": "Farley's bound on the cover LP's duals over the closed arrangement of "
        "the coverage regions grown by the tolerance (a plain cover; "
        "registration not used)",
    }
    proven = result.objective is not None and result.objective <= plane + 1e-9
    info["bound_scope"] = "plane" if proven else "pool"
    if proven:
        return replace(result, status=Status.OPTIMAL, bound=float(plane or 0), info=info)
    return replace(result, info=info)
