"""How far each chosen station may move: the largest tripod disc that keeps what the plan relies on it for.

For station j the plan relies on j for the targets it answers for (each
covered target answers to its nearest chosen station) and for the targets it
shares with its registration partners (the overlap links), so that every
station may move within its disc at the same time. For every end point e of such a piece (top heights h_e) and
every point q of the disc {p + u : |u| <= r}:

- range:     |q - e| <= R_e = sqrt(S_max^2 - (h_e - IH)^2)          (and to the foot)
- incidence: |q - e| cos(theta_max) <= (q - e) . n                  (horizontal incidence)

Their worst cases over the disc, |p - e| + r <= R_e and
(|p - e| + r) cos(theta_max) + r <= (p - e) . n, are second-order cone
constraints in (p, r); cvxpy (Clarabel) maximises r. Sight lines are not
convex: the disc is then checked on its centre and 16 points of its rim with
the full coverage test and halved until nothing is lost.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from planner.candidates.model import Candidate
from planner.coverage.matrix import CoverageProblem, build_coverage
from planner.coverage.targets import Targets
from planner.coverage.visibility import SightLimits
from planner.site.model import Site

RIM_POINTS = 16
MAX_RADIUS_M = 25.0


@dataclass(frozen=True)
class TripodDisc:
    station: str
    radius_m: float
    centre: tuple[float, float]
    relied_targets: int


def relied_targets(problem: CoverageProblem, selected: Sequence[int], partners: dict[int, list[int]] | None = None) -> dict[int, np.ndarray]:
    """Per chosen candidate: the targets it answers for, plus those it shares with its registration partners.

    Every covered target answers to one chosen station, the nearest (smallest
    slant range) of those that see it, so that all stations may move at once:
    each keeps its own targets, and the shared ones keep the overlap links.
    """
    sel = list(selected)
    slant = problem.slant_m[sel].tocsc()
    owner: dict[int, np.ndarray] = {j: np.zeros(0, dtype=np.int64) for j in sel}
    best_row = np.full(slant.shape[1], -1)
    best_val = np.full(slant.shape[1], np.inf)
    coo = slant.tocoo()
    for r, t, v in sorted(zip(coo.row, coo.col, coo.data), key=lambda x: (x[1], x[2], x[0])):
        if best_row[t] < 0:
            best_row[t], best_val[t] = r, v
    for k, j in enumerate(sel):
        own = np.flatnonzero(best_row == k)
        keep = set(own.tolist())
        mine = problem.by_candidate[j].indices
        for p in (partners or {}).get(j, []):
            keep |= set(np.intersect1d(mine, problem.by_candidate[p].indices).tolist())
        owner[j] = np.array(sorted(keep), dtype=np.int64)
    return owner


def _socp_disc(p0: np.ndarray, ends: np.ndarray, normals: np.ndarray, reach: np.ndarray, theta_max_deg: float) -> tuple[np.ndarray, float]:
    # on import, cvxpy 1.8 logs that it does not know ortools 9.15 (for its GLOP/PDLP interfaces,
    # unused here); its logger is quiet while it loads
    logger = logging.getLogger("__cvxpy__")
    was = logger.disabled
    logger.disabled = True
    try:
        import cvxpy as cp
    finally:
        logger.disabled = was

    if len(ends) == 0:
        return p0, MAX_RADIUS_M
    p, r = cp.Variable(2), cp.Variable()
    c = math.cos(math.radians(theta_max_deg))
    dist = cp.norm(cp.reshape(p, (1, 2), order="C") - ends, axis=1)
    cons = [r >= 0, r <= MAX_RADIUS_M, dist + r <= reach,
            c * (dist + r) + r <= cp.sum(cp.multiply(cp.reshape(p, (1, 2), order="C") - ends, normals), axis=1)]
    prob = cp.Problem(cp.Maximize(r), cons)
    try:
        prob.solve(solver=cp.CLARABEL)
    except cp.error.SolverError:
        return p0, 0.0
    if prob.status not in ("optimal", "optimal_inaccurate") or r.value is None:
        return p0, 0.0
    return np.asarray(p.value, dtype=float), max(float(r.value), 0.0)


def tripod_discs(site: Site, problem: CoverageProblem, selected: Sequence[int], limits: SightLimits,
                 partners: dict[int, list[int]] | None = None) -> list[TripodDisc]:
    """The largest safe disc of every chosen station (see the module docstring)."""
    t: Targets = problem.targets
    relied = relied_targets(problem, selected, partners)
    out = []
    for j in selected:
        cand = problem.candidates[j]
        ts = relied[j]
        ends = np.vstack([t.a[ts], t.b[ts]]) if ts.size else np.zeros((0, 2))
        heights = np.concatenate([t.ha_m[ts], t.hb_m[ts]]) if ts.size else np.zeros(0)
        normals = np.vstack([t.normal[ts], t.normal[ts]]) if ts.size else np.zeros((0, 2))
        dz = np.maximum(np.abs(heights - limits.instrument_height_m), limits.instrument_height_m)
        reach = np.sqrt(np.maximum(limits.range_limit_m**2 - dz**2, 0.0))
        centre, radius = _socp_disc(np.array(cand.xy), ends, normals, reach, limits.theta_max_deg)
        radius = _shrink_until_safe(site, cand, centre, radius, t, ts, limits)
        if radius <= 0.0:
            centre = np.array(cand.xy)
        out.append(TripodDisc(cand.id, radius, (float(centre[0]), float(centre[1])), int(ts.size)))
    return out


def _shrink_until_safe(site: Site, cand: Candidate, centre: np.ndarray, radius: float, t: Targets, ts: np.ndarray,
                       limits: SightLimits) -> float:
    from planner.candidates.final_step import misplacement

    angles = np.linspace(0.0, 2.0 * math.pi, RIM_POINTS, endpoint=False)
    for _ in range(30):
        if radius < 1e-3:
            return 0.0
        pts = np.vstack([centre, centre + radius * np.stack([np.cos(angles), np.sin(angles)], axis=1)])
        probes = [replace(cand, id=f"{cand.id}#{k}", x=float(x), y=float(y)) for k, (x, y) in enumerate(pts)]
        ok = all(not misplacement(site, p, p.x, p.y) for p in probes)
        if ok and ts.size:
            sub = build_coverage(site, probes, t, limits).by_candidate[:, ts]
            ok = bool(np.all(np.diff(sub.tocsr().indptr) == ts.size))
        if ok:
            return radius
        radius /= 2.0
    return 0.0
