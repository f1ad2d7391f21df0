"""Study: is there a smaller connected plan than the default's, with stations on a dense grid of each zone-side?

    python scripts/studies/dense_pool.py instances/polygon_a.json --step 2 --work 100 [--side inside] [--out plan.json]

For every zone-side (or the one asked), the points of a square grid of ``--step`` m over where its stations can stand
(inside: the zone less a 0.5-m band; outside: a ring of ``--ring`` m round it less the same band), together with the
default pool's candidates of that side (its corner rays reach slivers no grid hits: the 23-deg tip of polygon_c), become
candidates; their coverage of the side's pieces is built with the run's own sight
(:meth:`planner.coverage.sight.Sight.coverage`), candidates seeing the same pieces are merged (they are the same for the
cover and for the overlap relation), and the connected set cover is solved by the planner's MILP (presolve, cut loop,
ring bound, local search) with ``--work`` deterministic seconds and no stall rule. Each side prints its plan, its bound
over these candidates, and the solver's reason for any gap; the plan of the sides planned is then verified the
planner's way (pieces covered at 0.1 m, :func:`planner.plan.verify.verify_stations`; each registration group connected
under the overlap rule, :meth:`planner.coverage.relation.Registration.check`) and, with ``--out``, written as a plan
file that ``planner verify SITE PLAN`` reads.

What it measured (issue 57, the default overlap rule; one run each on 2 cores shared by about 5 sessions):

| site / side | default plan | grid 3 m (``planner plan --grid-spacing 3``) | grid 2 m, this script (C inside: + pool) | grid 1 m, this script |
|---|---|---|---|---|
| polygon_a inside | 10 | 10 | 10, optimal over the grid (work 60) | 10, bound 9 (work 200; 93,000 distinct rows, 370 s) |
| polygon_a outside | 15 | 15 | 15, optimal (work 100) | - |
| polygon_c inside | 13 | - | 13, bound 12 (work 300, 427 CPU-s; seed 1, work 700, 939 CPU-s: the same) | - |
| polygon_c outside | 16 | - | 16, optimal (work 100) | - |

No plan of 24 for polygon_a or 28 for polygon_c was found on grids 5 to 25 times denser (per area) than the default's.
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace

import numpy as np
import scipy.sparse as sp
import shapely

from planner.coverage.targets import SIDE_CODE
from planner.engine import problem_of
from planner.plan.problem import Problem
from planner.plan.run import build_problem
from planner.plan.verify import verify_stations
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Zone
from planner.solve.instance import CoverInstance
from planner.solve.milp import solve

#: no grid point closer to a wall than this, m (the pool's own stand-off)
BAND_M = 0.5


def stand_region(zone: Zone, side: ScanSide, ring_m: float) -> shapely.Geometry:
    """Where a station of this zone-side may stand: the zone (inside) or a ring round it (outside), off the walls."""
    if side is ScanSide.INSIDE:
        return zone.polygon.buffer(-BAND_M)
    return zone.polygon.buffer(ring_m).difference(zone.polygon.buffer(BAND_M))


def grid_candidates(zone: Zone, side: ScanSide, step_m: float, ring_m: float) -> list[Candidate]:
    """The points of a square grid of ``step_m`` (axes of the site's frame) in the stand region, as candidates."""
    region = stand_region(zone, side, ring_m)
    x0, y0, x1, y1 = region.bounds
    gx, gy = np.meshgrid(np.arange(np.floor(x0), x1, step_m), np.arange(np.floor(y0), y1, step_m))
    pts = np.c_[gx.ravel(), gy.ravel()]
    pts = pts[shapely.contains_xy(region, pts[:, 0], pts[:, 1])]
    tag = "in" if side is ScanSide.INSIDE else "out"
    return [
        Candidate(f"{zone.id}-{tag}-D{k}", zone.id, side, zone.frame, float(x), float(y), CandidateKind.GRID)
        for k, (x, y) in enumerate(pts, 1)
    ]


def distinct_rows(by: sp.csr_matrix) -> list[int]:
    """The first row of each distinct non-empty row pattern."""
    seen: set[bytes] = set()
    keep = []
    for i in range(by.shape[0]):
        row = np.sort(by.indices[by.indptr[i] : by.indptr[i + 1]])
        key = row.tobytes()
        if row.size and key not in seen:
            seen.add(key)
            keep.append(i)
    return keep


def plan_side(
    problem: Problem, zone: Zone, side: ScanSide, pool: list[Candidate], args: argparse.Namespace
) -> list[Candidate]:
    """The connected cover of one zone-side's pieces over its dense grid and the default pool's candidates of the
    side (corner rays in a sliver no grid hits), printed with its bound."""
    start = time.process_time()
    own = [c for c in pool if c.zone == zone.id and c.side is side]
    cands = grid_candidates(zone, side, args.step, args.ring) + own
    cov = problem.sight.coverage(cands, problem.targets)
    by = cov.by_candidate.tocsr()
    keep = distinct_rows(by)
    by = by[keep]
    t = problem.targets
    cols = np.flatnonzero((np.asarray(t.zone_ids)[t.zone] == zone.id) & (np.asarray(t.side) == SIDE_CODE[side]))
    unseen = cols[by[:, cols].getnnz(axis=0) == 0]
    if unseen.size:
        raise SystemExit(
            f"{zone.id}/{side.value}: {unseen.size} piece(s) seen by no candidate, e.g. {t.label(unseen[0])}"
        )
    inst = CoverInstance(
        by_candidate=by[:, cols].astype(bool).tocsr(),
        cost=np.ones(len(keep)),
        groups=tuple([0] * len(keep)),
        target_length_m=np.asarray(t.s1_m - t.s0_m, dtype=float)[cols],
        xy=np.array([cands[i].xy for i in keep]),
    )
    options = replace(problem.options.milp, work_limit=args.work, stall_work=None, time_limit_s=None, seed=args.seed)
    result = solve(inst, options)
    chosen = [cands[keep[i]] for i in result.selected]
    print(
        f"{zone.id}/{side.value}: {len(cands) - len(own):,} grid points + {len(own):,} of the pool, {len(keep):,} distinct, {len(cols):,} pieces; "
        f"{len(chosen)} stations, bound {result.bound:.2f} over the grid ({result.status.value}); "
        f"{time.process_time() - start:.0f} CPU-s"
    )
    if "gap_reason" in result.info:
        print(f"  {result.info['gap_reason']}")
    return chosen


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("site")
    ap.add_argument("--step", type=float, default=2.0, help="grid step, m")
    ap.add_argument("--ring", type=float, default=95.0, help="outside: how far round the zone, m")
    ap.add_argument("--work", type=float, default=100.0, help="MILP work limit per side, deterministic s")
    ap.add_argument("--seed", type=int, default=0, help="the MILP's seed")
    ap.add_argument("--side", choices=("inside", "outside"), help="one side only")
    ap.add_argument("--out", help="write the plan here (planner verify SITE PLAN)")
    args = ap.parse_args()
    problem = problem_of(args.site)
    pool = list(build_problem(problem).candidates)
    stations: list[Candidate] = []
    for zone in problem.site.zones:
        for side in zone.scan_side.sides:
            if args.side is None or side.value == args.side:
                stations += plan_side(problem, zone, side, pool, args)
    cov = problem.sight.coverage(stations, problem.targets)
    components, _ = problem.registration.check(cov, range(len(stations)))
    report = verify_stations(problem.sight, stations)
    covered = [f"{z.zone}/{z.side} {z.percent:.3f} %" for z in report.zones]
    print(f"{len(stations)} stations; components per group {components}; verified: {', '.join(covered)}")
    if args.out:
        rows = [{"id": s.id, "zone": s.zone, "side": s.side.value, "x": s.x, "y": s.y} for s in stations]
        with open(args.out, "w") as f:
            json.dump({"stations": rows}, f, indent=1)


if __name__ == "__main__":
    main()
