"""The plane bound over walls and floors (and ceilings) together.

The cover LP's rows are the wall pieces and the patches the pool sees; its columns the pool's candidates. For any duals
y >= 0 of those rows, let w* bound the weight sum_{r: p covers r} y_r of every position p of the plane. Then y / max(1,
w*) is feasible for the LP over *all* positions, so Farley's sum(y) / max(1, w*) bounds every cover from any positions
(walls and those patches), as pricing's bound does for walls (:mod:`planner.bounds.plane`).

w* is the heaviest weight over the arrangement of the *outer* regions, frame by frame: each wall piece's O_t
(:class:`planner.bounds.outer.OuterRegions`) and each patch's outer region
(:func:`planner.candidates.surface_regions.patch_regions` with ``outer``: range discs circumscribed, the blind disc
inscribed, shadows exact within the reach), all grown by the walls' outer tolerance
(:func:`planner.coverage.arrangement.outer_max_weight`: every covering position lies in its grown region, and the
heaviest face of the grown arrangement weighs at least any position's weight).

Before that, a few rounds of column generation make the duals good: the heaviest points of the arrangement of the
*inner* regions (walls' R_t, patches' inner regions) are tested with the sight tests themselves, and those whose real
coverage prices out join the LP (not the pool: the plan is solved already). When none prices out the LP over the plane
is reached, to the regions' tolerance. A plan with ``k`` views of every piece and patch bounds k times that LP.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
import shapely

from planner.bounds.outer import OuterRegions
from planner.candidates.surface_regions import patch_regions
from planner.coverage.arrangement import grown, heaviest_points, outer_max_weight
from planner.coverage.matrix import CoverageProblem, build_coverage
from planner.coverage.regions import FrameSpace, coverage_regions, outer_tolerance_m
from planner.coverage.surface_sight import SurfaceLimits, standing_zone, surface_sight
from planner.coverage.surfaces import SurfaceTargets
from planner.coverage.visibility import SightLimits
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Site
from planner.solve.pricing import WarmCoverLp

#: a point prices out when its weight exceeds the station cost by more than this
PRICE_EPS = 1e-7
#: the bound is formed only where the LP has at most this many rows (wall pieces and seen patches)
MAX_ROWS = 3_000
#: column generation: rounds, points tested per round, and (point, region) pairs weighed in all; only where the LP has
#: at most MAX_PRICED_ROWS rows (a small room's walls and floor; beyond, Farley's bound on the pool's own duals)
MAX_ROUNDS = 10
PER_ROUND = 60
MAX_WORK = 600_000
MAX_PRICED_ROWS = 400
#: the grid the grown outer regions are put on before their arrangement is formed (m)
SNAP_M = 1e-9
#: the rounding slack of the bound (as for walls)
ROUND_TOL = 1e-6


@dataclass(frozen=True)
class SurfacePlaneBound:
    """What the bound over walls and surfaces established. ``lp_bound``: the cover LP over the pool and the priced
    positions; ``plane_lp_bound``: Farley's bound over the plane (None: not formed, ``note`` says why);
    ``heaviest_weight``: w*; ``priced``: positions outside the pool whose real coverage priced out; ``converged``: none
    was left; ``scope``: what it covers, e.g. ``plane, walls and floors``."""

    scope: str
    lp_bound: float | None = None
    plane_lp_bound: float | None = None
    heaviest_weight: float = 0.0
    rounds: int = 0
    priced: int = 0
    converged: bool = False
    tolerance_m: float = 0.0
    rows: int = 0
    time_s: float = 0.0
    note: str = ""
    work: int = 0
    history: tuple[float, ...] = field(default_factory=tuple)
    duals: tuple[float, ...] = field(default_factory=tuple, repr=False)  # the last LP's y: wall pieces, then patches

    def bound(self, k: int = 1) -> int | None:
        """ceil(k L - tolerance): no plan covering every piece and patch ``k`` times from any positions has fewer."""
        return None if self.plane_lp_bound is None else math.ceil(k * self.plane_lp_bound - ROUND_TOL)

    def to_dict(self) -> dict[str, Any]:
        return {
            "scope": self.scope,
            "pool_lp_bound": self.lp_bound,
            "plane_lp_bound": self.plane_lp_bound,
            "heaviest_weight": self.heaviest_weight,
            "rounds": self.rounds,
            "priced_positions": self.priced,
            "converged": self.converged,
            "tolerance_m": self.tolerance_m,
            "rows": self.rows,
            "time_s": self.time_s,
            "note": self.note,
            "work": self.work,
            "lp_history": list(self.history),
        }

    def summary(self) -> str:
        """One line for the log."""
        if self.plane_lp_bound is None:
            return f"plane bound over {self.scope.removeprefix('plane, ')}: not formed ({self.note})"
        state = "converged" if self.converged else "not converged"
        return (
            f"plane bound over {self.scope.removeprefix('plane, ')}: cover LP {self.lp_bound:.3f} over the pool and "
            f"{self.priced} priced positions; over every position LP >= {self.plane_lp_bound:.3f} (>= {self.bound()} "
            f"stations; heaviest weight {self.heaviest_weight:.4f}); {state}, {self.rounds} rounds, {self.time_s:.1f} s"
            + (f"; {self.note}" if self.note else "")
        )


@dataclass(frozen=True, eq=False)
class _Rows:
    """The LP's rows: the wall pieces (0..T-1), then the patches ``seen`` (T..), and the regions drawn for them."""

    site: Site
    walls: CoverageProblem
    patches: SurfaceTargets
    seen: np.ndarray
    limits: SightLimits
    surface_limits: SurfaceLimits
    spaces: dict[str, FrameSpace]
    region_cache: dict[int, Any]
    inner: dict[int, shapely.Geometry] = field(default_factory=dict)  # patch index -> inner region

    def frame_rows(self, pos: np.ndarray) -> dict[str, np.ndarray]:
        """The rows ``pos`` by frame name."""
        t = self.walls.targets
        n_t = len(t)
        names = np.empty(len(pos), dtype=object)
        wall = pos < n_t
        names[wall] = np.asarray(t.frames, dtype=object)[t.frame[pos[wall]]]
        names[~wall] = np.asarray(self.patches.frames, dtype=object)[self.patches.frame[self.seen[pos[~wall] - n_t]]]
        return {str(f): pos[names == f] for f in dict.fromkeys(names.tolist())}

    def regions(self, rows: np.ndarray, outer: OuterRegions | None = None) -> list[shapely.Geometry]:
        """The regions of ``rows``: inner (R_t, patches' inner), or the outer ones with ``outer``."""
        n_t = len(self.walls.targets)
        walls, pats = rows[rows < n_t], self.seen[rows[rows >= n_t] - n_t]
        if outer is not None:
            o = outer.of(self.site, self.walls.targets, self.limits, walls)
            p = patch_regions(self.site, self.patches, self.surface_limits, self.limits, pats, outer.spaces, True)
            return [*(o[int(w)] for w in walls), *(p[int(q)] for q in pats)]
        missing = [int(w) for w in walls if int(w) not in self.region_cache]
        self.region_cache.update(coverage_regions(self.site, self.walls.targets, self.limits, missing, self.spaces))
        todo = [int(q) for q in pats if int(q) not in self.inner]
        self.inner.update(patch_regions(self.site, self.patches, self.surface_limits, self.limits, todo, self.spaces))
        return [*(self.region_cache[int(w)] for w in walls), *(self.inner[int(q)] for q in pats)]

    def columns(self, frame: str, xy: np.ndarray) -> sp.csr_matrix:
        """What positions ``xy`` of ``frame`` cover by the sight tests: wall pieces, then the seen patches."""
        cands = [
            Candidate(f"SP.{k}", "", ScanSide.INSIDE, frame, x, y, CandidateKind.PRICED)
            for k, (x, y) in enumerate(xy.tolist())
        ]
        walls = build_coverage(self.site, cands, self.walls.targets, self.limits)
        zone = standing_zone(self.site, xy, np.full(len(xy), frame, dtype=object))
        zone[np.asarray(list(walls.excluded), dtype=np.int64)] = -1
        rows = np.flatnonzero(zone >= 0)
        pats = sp.csr_matrix((len(xy), len(self.seen)), dtype=bool)
        if rows.size:
            sub = surface_sight(self.site, self.patches, xy[rows], zone[rows], self.surface_limits)[
                :, self.seen
            ].tocoo()
            pats = sp.csr_matrix((np.ones(sub.nnz, bool), (rows[sub.row], sub.col)), shape=pats.shape, dtype=bool)
        return sp.hstack([walls.by_candidate, pats], format="csr").astype(bool)


def _heaviest(regions: list[shapely.Geometry], y: np.ndarray, tol: float) -> float:
    """w* of one frame: :func:`planner.coverage.arrangement.outer_max_weight` over the regions grown by ``tol`` and
    put on a grid of :data:`SNAP_M` (the round ends of many discs about shared corners otherwise lose faces to the
    polygoniser, and it falls back to the sum of the weights); where that still falls back, a grid 10 times coarser.
    Snapping moves a vertex by less than the grown regions' margin (1 um), so each result is an upper bound on every
    position's weight, and so is the smaller of the two."""
    grown_regions = grown(regions, tol)
    best = float(np.sum(y))
    for snap in (SNAP_M, 10 * SNAP_M):
        snapped = list(shapely.set_precision(np.asarray(grown_regions, dtype=object), snap))
        best = min(best, outer_max_weight(regions, y, tol, grown_regions=snapped))
        if best < float(np.sum(y)) - 1e-12:
            break
    return best


def _price(rows: _Rows, model: WarmCoverLp, y: np.ndarray, pos: np.ndarray, work: list[int]) -> tuple[int, int]:
    """One round: the heaviest points of each frame's inner arrangement, tested; the columns that price out added to
    ``model``. Returns how many points priced out by their regions, and how many by the sight tests (added)."""
    found = added = 0
    for frame, here in rows.frame_rows(pos).items():
        snapped = list(shapely.set_precision(np.asarray(rows.regions(here), dtype=object), SNAP_M))
        points = heaviest_points(snapped, y[here], 1.0 + PRICE_EPS, PER_ROUND, work)
        if not points:
            continue
        found += len(points)
        cols = rows.columns(frame, np.array([[p.x, p.y] for p in points], dtype=float))
        good = np.flatnonzero(np.asarray(cols.astype(np.float64) @ y).ravel() > 1.0 + PRICE_EPS)
        if good.size:
            model.add_columns(cols[good])
            added += int(good.size)
    return found, added


def surfaces_plane_bound(
    site: Site,
    walls: CoverageProblem,
    patches: SurfaceTargets,
    seen: np.ndarray,
    patch_columns: sp.csr_matrix,
    surface_limits: SurfaceLimits,
    *,
    scope: str,
    spaces: dict[str, FrameSpace] | None = None,
    region_cache: dict[int, Any] | None = None,
    outer: OuterRegions | None = None,
    max_rounds: int = MAX_ROUNDS,
    max_work: int = MAX_WORK,
) -> SurfacePlaneBound:
    """The plane bound for covering the wall pieces of ``walls`` and the patches ``seen`` (their columns for the pool:
    ``patch_columns``, candidates x seen): the module's LP, priced for at most ``max_rounds`` rounds and ``max_work``
    weighed pairs, and Farley's bound over the outer arrangement. ``spaces``/``region_cache``/``outer``: the regions
    drawn in this run (filled in here)."""
    start = time.perf_counter()
    n_rows = len(walls.targets) + len(seen)
    tol = outer_tolerance_m(walls.limits)
    if n_rows > MAX_ROWS:
        note = f"{n_rows:,} wall pieces and patches, more than the {MAX_ROWS:,} it is formed for"
        return SurfacePlaneBound(scope, note=note, rows=n_rows, tolerance_m=tol)
    outer = OuterRegions() if outer is None else outer
    rows = _Rows(
        site,
        walls,
        patches,
        np.asarray(seen, np.int64),
        walls.limits,
        surface_limits,
        {} if spaces is None else spaces,
        {} if region_cache is None else region_cache,
    )
    by_target = sp.vstack([walls.by_target, patch_columns.T.tocsr()]).tocsr()
    model = WarmCoverLp(by_target)
    work: list[int] = []
    history: list[float] = []
    rounds = priced = 0
    if n_rows > MAX_PRICED_ROWS:
        max_rounds = 0
    converged = False
    thin = 0
    try:
        while True:
            lp = model.solve()
            history.append(lp.value)
            pos = np.flatnonzero(lp.y > 1e-9)
            if rounds >= max_rounds or sum(work) >= max_work:
                break
            rounds += 1
            found, n = _price(rows, model, lp.y, pos, work)
            if n == 0:
                converged, thin = found == 0, found
                break
            priced += n
    finally:
        model.close()
    w_star = max(
        [0.0, *(_heaviest(rows.regions(here, outer), lp.y[here], tol) for here in rows.frame_rows(pos).values())]
    )
    note = (
        ""
        if converged
        else f"not priced ({n_rows:,} wall pieces and patches, more than {MAX_PRICED_ROWS}): the pool's duals"
        if n_rows > MAX_PRICED_ROWS
        else f"{thin} arrangement points price out by their regions but none by the sight tests"
        if thin
        else f"stopped after {rounds} rounds ({sum(work):,} weighed pairs) before it converged"
    )
    return SurfacePlaneBound(
        scope,
        lp_bound=float(lp.value),
        plane_lp_bound=float(lp.y.sum()) / max(1.0, w_star),
        heaviest_weight=w_star,
        rounds=rounds,
        priced=priced,
        converged=converged,
        tolerance_m=tol,
        rows=n_rows,
        time_s=time.perf_counter() - start,
        note=note,
        work=sum(work),
        history=tuple(history),
        duals=tuple(map(float, lp.y)),
    )
