"""Geometric column generation: grow the candidate pool until the cover LP's bound holds for every
position in the plane (at the chosen wall discretisation), or say that it holds over the pool only.

Each round solves the cover LP on the pool, takes the pieces with a positive dual, builds (once) their
coverage regions and looks for the heaviest faces of their arrangement, frame by frame. A face heavier
than the station cost (1) is a position that prices out: its point is tested with the coverage test
itself and added as a candidate when its true covered pieces price out too. When no face is heavier
than 1, the LP value is a lower bound over the plane: no position anywhere could lower it.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import scipy.sparse as sp
import shapely

from planner.candidates.closed_form import SIDE_TAG
from planner.candidates.model import Candidate, CandidateKind
from planner.coverage.matrix import CoverageProblem, build_coverage
from planner.coverage.regions import FrameSpace, coverage_regions, region_tolerance_m
from planner.coverage.visibility import SightLimits
from planner.site.model import ScanSide, Site
from planner.solve.pricing import cover_lp, heaviest_faces
from planner.solve.result import SolveResult, Status

#: a face or column prices out when its dual weight exceeds the cost by more than this
PRICE_EPS = 1e-7


@dataclass(frozen=True)
class PricingReport:
    """What pricing established.

    ``lp_bound`` is the cover LP over the final pool. ``plane_lp_bound`` holds over every position in the
    plane: Farley's bound ``sum(y) / max(1, w*)``, where ``y`` are the LP duals and ``w*`` the heaviest
    arrangement face (any position's dual weight), scales the duals to a feasible dual of the plane's LP;
    the best over all rounds is kept. ``scope`` is ``plane`` when the pool's integer bound is proven over
    the plane (no face prices out, or Farley's bound rounds up to the same integer), else ``pool``.
    """

    scope: str
    lp_bound: float
    plane_lp_bound: float
    rounds: int
    columns_added: int
    time_s: float
    tolerance_m: float
    note: str = ""
    history: tuple[float, ...] = field(default_factory=tuple)
    plane_history: tuple[float, ...] = field(default_factory=tuple)

    @property
    def integer_bound(self) -> int:
        """ceil of the pool's LP bound: no cover from the pool has fewer stations."""
        return math.ceil(self.lp_bound - 1e-6)

    @property
    def plane_bound(self) -> int:
        """ceil of the plane LP bound: no cover from any positions has fewer stations."""
        return math.ceil(self.plane_lp_bound - 1e-6)

    def to_dict(self) -> dict[str, Any]:
        return {"scope": self.scope, "lp_bound": self.lp_bound, "integer_bound": self.integer_bound,
                "plane_lp_bound": self.plane_lp_bound, "plane_bound": self.plane_bound,
                "rounds": self.rounds, "columns_added": self.columns_added, "time_s": self.time_s,
                "tolerance_m": self.tolerance_m, "note": self.note, "lp_history": list(self.history),
                "plane_lp_history": list(self.plane_history)}

    def summary(self) -> str:
        head = (f"pricing: LP bound {self.lp_bound:.3f} over the pool; over every position in the plane "
                f"LP >= {self.plane_lp_bound:.3f} (>= {self.plane_bound} stations)")
        state = "converged" if self.scope == "plane" else "not converged"
        return (f"{head}; {state}, {self.rounds} rounds, {self.columns_added} columns added, {self.time_s:.1f} s"
                + (f"; {self.note}" if self.note else ""))


def merge_problems(p: CoverageProblem, q: CoverageProblem) -> CoverageProblem:
    """``p`` with the candidates of ``q`` appended (same targets and limits)."""
    by_c = sp.vstack([p.by_candidate, q.by_candidate]).tocsr()
    off = len(p.candidates)
    return CoverageProblem(
        candidates=p.candidates + q.candidates, targets=p.targets, by_candidate=by_c, by_target=by_c.T.tocsr(),
        slant_m=sp.vstack([p.slant_m, q.slant_m]).tocsr(), incidence_deg=sp.vstack([p.incidence_deg, q.incidence_deg]).tocsr(),
        excluded={**p.excluded, **{k + off: v for k, v in q.excluded.items()}}, limits=p.limits)


def _owner(problem: CoverageProblem, row: int) -> tuple[str, ScanSide]:
    """The zone-side whose pieces a priced column covers most of (its registration group)."""
    t = problem.targets
    cols = problem.by_candidate.indices[problem.by_candidate.indptr[row]:problem.by_candidate.indptr[row + 1]]
    keys, counts = np.unique(t.zone[cols].astype(np.int64) * 2 + t.side[cols], return_counts=True)
    k = int(keys[np.argmax(counts)])
    return t.zone_ids[k // 2], (ScanSide.INSIDE if k % 2 == 0 else ScanSide.OUTSIDE)


def price_plane(site: Site, problem: CoverageProblem, limits: SightLimits, *, max_rounds: int = 400,
                per_round: int = 100, time_limit_s: float = 120.0,
                cache: dict[int, shapely.Geometry] | None = None,
                spaces: dict[str, FrameSpace] | None = None) -> tuple[CoverageProblem, PricingReport]:
    """Add priced columns to ``problem`` until none prices out (scope ``plane``) or a limit stops it."""
    start = time.perf_counter()
    tol = region_tolerance_m(limits, site.parameters.min_standoff_m)
    cache = {} if cache is None else cache
    spaces = {} if spaces is None else spaces
    t = problem.targets
    added, history, plane_history, note, scope = 0, [], [], "", "pool"
    farley = 0.0
    rounds = 0
    while True:
        lp = cover_lp(problem.by_target)
        history.append(lp.value)
        if rounds >= max_rounds or time.perf_counter() - start > time_limit_s:
            note = f"stopped after {rounds} rounds / {time.perf_counter() - start:.0f} s before pricing converged"
            break
        rounds += 1
        pos = np.flatnonzero(lp.y > 1e-9)
        missing = [int(k) for k in pos if int(k) not in cache]
        cache.update(coverage_regions(site, t, limits, missing, spaces))
        faces, heaviest = [], 0.0
        for fi in range(len(t.frames)):
            here = pos[t.frame[pos] == fi]
            if here.size:
                found, top = heaviest_faces([cache[int(k)] for k in here], lp.y[here], 1.0 + PRICE_EPS, per_round)
                faces += [(fi, f) for f in found]
                heaviest = max(heaviest, top)
        # Farley's bound: y / max(1, heaviest) is dual feasible for every position, so it bounds the plane's LP
        farley = max(farley, float(lp.y.sum()) / max(1.0, heaviest))
        plane_history.append(farley)
        if not faces or math.ceil(farley - 1e-6) >= math.ceil(lp.value - 1e-6):
            scope = "plane"
            farley = max(farley, lp.value) if not faces else farley
            break
        new = [Candidate(f"PR{rounds}.{k}", "", ScanSide.INSIDE, t.frames[fi], f.x, f.y, CandidateKind.PRICED)
               for k, (fi, f) in enumerate(faces, 1)]
        sub = build_coverage(site, new, t, limits)
        gain = np.asarray(sub.by_candidate.astype(np.float64) @ lp.y).ravel()
        good = np.flatnonzero(gain > 1.0 + PRICE_EPS)
        if good.size == 0:
            note = (f"{len(faces)} faces price out by their regions but none by the coverage test "
                    f"(within the {tol:.4f} m tolerance)")
            break
        keep = sub.by_candidate[good]
        owners = [_owner(sub, int(g)) for g in good]
        cands = tuple(Candidate(f"{z}-{SIDE_TAG[s]}-{new[g].id}", z, s, new[g].frame, new[g].x, new[g].y, CandidateKind.PRICED)
                      for g, (z, s) in zip(good, owners))
        piece = CoverageProblem(cands, t, keep, keep.T.tocsr(), sub.slant_m[good], sub.incidence_deg[good], {}, sub.limits)
        problem = merge_problems(problem, piece)
        added += len(cands)
    report = PricingReport(scope, history[-1], farley, rounds, added, time.perf_counter() - start, tol,
                           note, tuple(history), tuple(plane_history))
    return problem, report


def with_plane_bound(result: SolveResult, pricing: PricingReport) -> SolveResult:
    """The MILP result with what pricing adds: ``info['bound_scope']`` is ``plane`` when the plan meets the
    LP bound that holds over the plane (optimal over every position), else ``pool`` (the MILP's bound holds
    over the pool; ``info['plane_bound']``, the ceil of Farley's bound, bounds every cover from any positions
    even when pricing stopped early)."""
    info = dict(result.info)
    info["pricing"] = pricing.to_dict()
    plane = pricing.plane_bound
    info["plane_bound"] = plane
    proven = result.objective is not None and result.objective <= plane + 1e-9
    info["bound_scope"] = "plane" if proven else "pool"
    if proven:
        return replace(result, status=Status.OPTIMAL, bound=float(plane), info=info)
    return replace(result, info=info)
