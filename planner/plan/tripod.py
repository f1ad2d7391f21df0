"""Where a plan's stations stand (:func:`placed_stations`) and how far each may move: the largest tripod disc that
keeps what the plan relies on it for (their registration is checked by
:meth:`planner.coverage.relation.Registration.check`).

For station j the plan relies on j for the targets it answers for (each covered target answers to its nearest
chosen station) and for the targets it shares with its registration partners (the overlap links), so that every
station may move within its disc at the same time. For every end point e of such a piece (top heights h_e) and
every point q of the disc {p + u : |u| <= r}:

- range:     |q - e| <= R_e = sqrt(S_max^2 - (h_e - IH)^2)          (and to the foot)
- incidence: |q - e| cos(theta_max) <= (q - e) . n                  (horizontal incidence)

Their worst cases over the disc, |p - e| + r <= R_e and (|p - e| + r) cos(theta_max) + r <= (p - e) . n. By default
the disc is centred on the planned station p0, so every disc contains its station and r has a closed form:
r = min_e min(R_e - |p0 - e|, ((p0 - e) . n - |p0 - e| cos theta_max) / (1 + cos theta_max)). With ``recentre``
the centre p is free (the station then moves to it): the constraints are second-order cone constraints in (p, r)
and cvxpy (Clarabel) maximises r. Sight lines, the stand-off and the incidence-dependent view error are not in
that model: the disc is then checked on its centre and ``RIM_POINTS`` points of its rim with the full coverage
test on the relied pieces only, and shrunk about the planned station (so it keeps containing it) until nothing is
lost; below ``MIN_RADIUS_M`` the radius is 0.

Each disc also carries the station's instrument-height tolerance (3.32): the radius of the tolerance circle when
the tripod stands between IH and IH + span, for the tallest relied wall top h at the slant range limit SD.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from planner.coverage.matrix import CoverageProblem, build_coverage, station_places
from planner.coverage.targets import Targets
from planner.coverage.visibility import SightLimits
from planner.site.candidate import Candidate
from planner.site.model import ScanSide, Site

if TYPE_CHECKING:
    from planner.plan.options import PlanOptions

RIM_POINTS = 16
MAX_RADIUS_M = 25.0
#: resolution of the disc radius: a smaller disc is reported as 0 (the station must stand where planned)
MIN_RADIUS_M = 0.05


@dataclass(frozen=True)
class TripodDisc:
    """Where station ``station`` may stand: a disc of ``radius_m`` around ``centre`` (which contains the
    planned station), the number of pieces it was kept for, and its height tolerance (3.32)."""

    station: str
    radius_m: float
    centre: tuple[float, float]
    relied_targets: int
    height_tolerance_m: float = float("nan")


def relied_targets(
    problem: CoverageProblem, selected: Sequence[int], partners: dict[int, list[int]] | None = None
) -> dict[int, np.ndarray]:
    """Per chosen candidate: the targets it answers for, plus those it shares with its registration partners.
    Every covered target answers to one chosen station, the nearest (smallest slant range) of those that see it,
    so that all stations may move at once: each keeps its own targets, and the shared ones keep the overlap links."""
    sel = list(selected)
    coo = problem.slant_m[sel].tocoo()
    order = np.lexsort((coo.row, coo.data, coo.col))  # by target, then slant range, then station
    col = coo.col[order]
    first = order[np.r_[True, col[1:] != col[:-1]]] if col.size else order  # each target's nearest station
    owned = np.argsort(coo.row[first], kind="stable")  # those targets grouped by station, in target order
    ends = np.searchsorted(coo.row[first][owned], np.arange(len(sel) + 1))
    targets = coo.col[first][owned].astype(np.int64)
    shared = _shared_with_partners(problem, sel, partners or {})
    owner: dict[int, np.ndarray] = {}
    for k, j in enumerate(sel):
        own = targets[ends[k] : ends[k + 1]]
        if shared is not None:
            own = np.union1d(own, shared.indices[shared.indptr[k] : shared.indptr[k + 1]]).astype(np.int64)
        owner[j] = own
    return owner


def _shared_with_partners(
    problem: CoverageProblem, sel: list[int], partners: dict[int, list[int]]
) -> sp.csr_matrix | None:
    """Row k: the targets the k-th station of ``sel`` sees together with one of its registration partners at least
    (one sparse product; None without partners)."""
    pairs = [(k, p) for k, j in enumerate(sel) for p in partners.get(j, [])]
    if not pairs:
        return None
    r, c = np.array(pairs, dtype=np.int64).T
    by = problem.by_candidate.tocsr().astype(bool).astype(np.int32)
    pick = sp.csr_matrix((np.ones(r.size, dtype=np.int32), (r, c)), shape=(len(sel), by.shape[0]))
    shared = (pick @ by).multiply(by[sel]).tocsr()
    shared.eliminate_zeros()
    shared.sort_indices()
    return shared


def _centred_radius(
    p0: np.ndarray, ends: np.ndarray, normals: np.ndarray, reach: np.ndarray, theta_max_deg: float
) -> float:
    """Largest r of the disc centred on p0 (closed form of the module docstring's constraints)."""
    if len(ends) == 0:
        return MAX_RADIUS_M
    c = math.cos(math.radians(theta_max_deg))
    v = p0[None, :] - ends
    dist = np.hypot(v[:, 0], v[:, 1])
    r_range = reach - dist
    r_inc = (np.einsum("ij,ij->i", v, normals) - dist * c) / (1.0 + c)
    return float(min(MAX_RADIUS_M, max(0.0, min(r_range.min(), r_inc.min()))))


def _socp_disc(
    p0: np.ndarray, ends: np.ndarray, normals: np.ndarray, reach: np.ndarray, theta_max_deg: float
) -> tuple[np.ndarray, float]:
    # on import, cvxpy logs that it does not know the installed ortools (its GLOP/PDLP interfaces, unused here)
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
    # (p - e) . n per end, as an affine map of p; not cp.sum(..., axis=1), whose shape check sums an uninitialised
    # np.empty array (numpy then warns of an invalid value in reduce)
    along = normals @ p - np.einsum("ij,ij->i", ends, normals)
    cons = [r >= 0, r <= MAX_RADIUS_M, dist + r <= reach, c * (dist + r) + r <= along]
    prob = cp.Problem(cp.Maximize(r), cons)
    try:
        prob.solve(solver=cp.CLARABEL)
    except cp.error.SolverError:
        return p0, 0.0
    if prob.status not in ("optimal", "optimal_inaccurate") or r.value is None:
        return p0, 0.0
    return np.asarray(p.value, dtype=float), max(float(r.value), 0.0)


def tripod_discs(
    site: Site,
    problem: CoverageProblem,
    selected: Sequence[int],
    limits: SightLimits,
    partners: dict[int, list[int]] | None = None,
    recentre: bool = False,
) -> list[TripodDisc]:
    """The largest safe disc of every chosen station (module docstring): centred on the station, or, with
    ``recentre``, anywhere (the station then moves to its centre; the disc need not hold the planned position)."""
    from planner.instrument.accuracy import instrument_height_tolerance_m

    t: Targets = problem.targets
    relied = relied_targets(problem, selected, partners)
    ih = limits.instrument_height_m
    span = site.parameters.instrument_height_span_m
    first: list[tuple[int, np.ndarray, np.ndarray, np.ndarray, float]] = []
    for j in selected:
        cand = problem.candidates[j]
        ts = relied[j]
        p0 = np.array(cand.xy, dtype=float)
        ends = np.vstack([t.a[ts], t.b[ts]]) if ts.size else np.zeros((0, 2))
        normals = np.vstack([t.normal[ts], t.normal[ts]]) if ts.size else np.zeros((0, 2))
        dz = np.maximum(np.abs(np.concatenate([t.ha_m[ts], t.hb_m[ts]]) - ih), ih) if ts.size else np.zeros(0)
        reach = np.sqrt(np.maximum(limits.effective_range_m**2 - dz**2, 0.0))
        if recentre:
            centre, radius = _socp_disc(p0, ends, normals, reach, limits.theta_max_deg)
        else:
            centre, radius = p0, _centred_radius(p0, ends, normals, reach, limits.theta_max_deg)
        first.append((j, ts, p0, centre, radius))
    safe = _safe_at_first(site, problem.candidates, t, first, limits)
    out = []
    for (j, ts, p0, centre, radius), ok in zip(first, safe):
        cand = problem.candidates[j]
        heights = np.concatenate([t.ha_m[ts], t.hb_m[ts]]) if ts.size else np.zeros(0)
        if not ok:  # halved until safe (its first disc is tried again there, and fails again)
            centre, radius = _shrink_until_safe(site, cand, p0, centre, radius, take_targets(t, ts), limits)
        tol = float("nan")
        if heights.size and limits.effective_range_m > abs(float(heights.max()) - ih) + span:
            tol = abs(instrument_height_tolerance_m(float(heights.max()), limits.effective_range_m, ih, ih + span))
        out.append(TripodDisc(cand.id, radius, (float(centre[0]), float(centre[1])), int(ts.size), tol))
    return out


def take_targets(t: Targets, idx: np.ndarray) -> Targets:
    """The pieces ``idx`` of ``t``, in that order, as a Targets of their own (same frames and zone ids; the arrays
    read-only, as every Targets'): the rim test and a tile's coverage are built on these only."""
    arrays = ("zone", "side", "wall", "s0_m", "s1_m", "a", "b", "ha_m", "hb_m", "normal", "frame")
    return replace(t, **{name: getattr(t, name)[idx] for name in arrays})


def _probe_xy(p0: np.ndarray, centre: np.ndarray, radius: float) -> np.ndarray:
    """The disc's centre, the planned station and ``RIM_POINTS`` points of the rim: (RIM_POINTS + 2, 2)."""
    angles = np.linspace(0.0, 2.0 * math.pi, RIM_POINTS, endpoint=False)
    rim = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    return np.vstack([centre, p0, centre + radius * rim])


def _probes(cand: Candidate, p0: np.ndarray, centre: np.ndarray, radius: float) -> list[Candidate]:
    """The points of :func:`_probe_xy` as candidates to check."""
    pts = _probe_xy(p0, centre, radius)
    return [replace(cand, id=f"{cand.id}#{k}", x=float(x), y=float(y)) for k, (x, y) in enumerate(pts)]


def _misplaced(site: Site, cands: Sequence[Candidate], xy: np.ndarray) -> np.ndarray:
    """For each point ``xy[i]`` (of candidate ``cands[i]``'s zone-side), True where a station of that zone-side
    cannot stand there (:func:`planner.candidates.final_step.misplacement`'s rule, for all the points in one
    classification)."""
    places = station_places(site, xy, [c.frame for c in cands])
    zone_of: dict[str, int] = {}
    for i, z in enumerate(site.zones):
        zone_of.setdefault(z.id, i)  # the first zone of an id, as misplacement takes it
    zi = np.array([zone_of[c.zone] for c in cands], dtype=np.int64).reshape(-1)
    inside = places.inside[np.arange(len(cands)), zi] if len(cands) else np.zeros(0, dtype=bool)
    wants = np.array([c.side is ScanSide.INSIDE for c in cands], dtype=bool).reshape(-1)
    bad: np.ndarray = np.array([bool(r) for r in places.reason], dtype=bool).reshape(-1) | (inside != wants)
    return bad


def _safe_at_first(
    site: Site,
    candidates: Sequence[Candidate],
    t: Targets,
    first: list[tuple[int, np.ndarray, np.ndarray, np.ndarray, float]],
    limits: SightLimits,
) -> list[bool]:
    """Whether each station's first disc ``(j, relied pieces, p0, centre, radius)`` is safe, as
    :func:`_shrink_until_safe` tests it, with one classification of the probe points and one coverage build for the
    probes of every station over the pieces any relies on (a pair's coverage does not depend on the other pairs
    built with it); a disc below ``MIN_RADIUS_M`` is not safe here (it is left to :func:`_shrink_until_safe`)."""
    safe = [False] * len(first)
    n = RIM_POINTS + 2
    tried = [k for k, (_, _, _, _, radius) in enumerate(first) if radius >= MIN_RADIUS_M]
    if not tried:
        return safe
    xy = np.vstack([_probe_xy(first[k][2], first[k][3], first[k][4]) for k in tried])
    owners = [candidates[first[k][0]] for k in tried for _ in range(n)]
    bad = np.asarray(_misplaced(site, owners, xy).reshape(len(tried), n).any(axis=1), dtype=bool).tolist()
    probes: list[Candidate] = []
    rows: list[tuple[int, int, np.ndarray]] = []  # (position in first, first probe row, relied pieces)
    for k, misplaced in zip(tried, bad):
        j, ts, p0, centre, radius = first[k]
        if misplaced:
            continue
        if not ts.size:
            safe[k] = True
            continue
        rows.append((k, len(probes), ts))
        probes += _probes(candidates[j], p0, centre, radius)
    if rows:
        pieces = np.unique(np.concatenate([ts for _, _, ts in rows]))
        cover = build_coverage(site, probes, take_targets(t, pieces), limits).by_candidate.tocsr().astype(bool)
        # every probe of a station must see each of its relied pieces: (probe, piece) pairs asked, then counted
        counts = np.array([ts.size for _, _, ts in rows], dtype=np.int64)
        probe = (np.array([r0 for _, r0, _ in rows], dtype=np.int64)[:, None] + np.arange(n)).ravel()
        piece = np.searchsorted(pieces, np.concatenate([ts for _, _, ts in rows]))
        first_piece = np.r_[0, np.cumsum(counts)[:-1]]
        ask_row = np.repeat(probe, np.repeat(counts, n))
        ask_col = np.concatenate([piece[a : a + c] for a, c in zip(first_piece, counts) for _ in range(n)])
        asked = sp.csr_matrix((np.ones(ask_row.size, dtype=bool), (ask_row, ask_col)), shape=cover.shape, dtype=bool)
        got = np.asarray(asked.multiply(cover).sum(axis=1)).ravel()[probe].reshape(len(rows), n)
        for (k, _, _), ok in zip(rows, np.all(got == counts[:, None], axis=1).tolist()):
            safe[k] = ok
    return safe


def _shrink_until_safe(
    site: Site, cand: Candidate, p0: np.ndarray, centre: np.ndarray, radius: float, t: Targets, limits: SightLimits
) -> tuple[np.ndarray, float]:
    """(centre, radius) of the disc checked on its centre and rim, halved about the planned station p0 until it
    is safe; (p0, 0) when no disc of at least ``MIN_RADIUS_M`` is."""
    while radius >= MIN_RADIUS_M:
        probes = _probes(cand, p0, centre, radius)
        ok = not _misplaced(site, probes, np.array([(p.x, p.y) for p in probes])).any()  # one classification
        if ok and len(t):
            sub = build_coverage(site, probes, t, limits).by_candidate
            ok = bool(np.all(np.diff(sub.tocsr().indptr) == len(t)))
        if ok:
            return centre, radius
        centre, radius = p0 + (centre - p0) / 2.0, radius / 2.0
    return p0, 0.0


def placed_stations(
    site: Site,
    problem: CoverageProblem,
    selected: tuple[int, ...],
    options: PlanOptions,
    partners: dict[int, list[int]],
) -> tuple[list[Candidate], tuple[TripodDisc, ...]]:
    """The chosen stations and, with ``options.tripod`` or ``options.recentre``, their tripod discs (relied
    pieces only, checked on centre and rim); ``recentre`` moves each station to its disc's centre."""
    stations = [problem.candidates[i] for i in selected]
    if not (options.tripod or options.recentre):
        return stations, ()
    tripods = tuple(tripod_discs(site, problem, selected, problem.limits, partners, options.recentre))
    if options.recentre:
        stations = [replace(s, x=d.centre[0], y=d.centre[1]) for s, d in zip(stations, tripods)]
    return stations, tripods
