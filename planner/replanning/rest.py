"""The problem of the rest of a plan after its edits (:func:`rest_problem`): the pool of the plan less the candidates
the edits forbid, its pairs less those an obstacle hides, the done stations fixed, and the wall pieces nothing can
see any more set aside as lost (:class:`Lost`), with their lengths.

What is forbidden: a candidate within a blocked station's radius (in that station's frame), inside an obstacle or
closer to it than the site's stand-off, inside a closed area, or inside a closed zone. An obstacle also hides: a
pair is kept only where the triangle from the candidate to the piece misses every obstacle polygon (conservative:
a piece is covered whole or not at all; the 0.1-m verification checks the plan on the site with the obstacles).
The done stations are exempt: they stood where they stood, and see what the edited site lets them see."""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import scipy.sparse as sp
import shapely
from numpy.typing import NDArray

from planner.coverage.matrix import CoverageProblem, build_coverage
from planner.io.edits import Edits
from planner.io.replan_data import ReplanData, relation_of
from planner.plan.problem import Problem
from planner.site.candidate import Candidate
from planner.site.features import SITE_FRAME, Obstacle
from planner.site.model import Site

#: the reasons a candidate is removed, in the order they are tried and reported
REASONS = ("blocked", "obstacle", "closed area", "closed zone")


@dataclass(frozen=True, kw_only=True)
class Lost:
    """Wall pieces that no station can see any more (indices into the targets) and their length, by zone and side."""

    pieces: tuple[int, ...]
    by_zone: dict[str, float]
    length_m: float

    def line(self) -> str:
        if not self.pieces:
            return "walls lost: none (every wall still needed is seen by some candidate)"
        zones = ", ".join(f"{z} {m:.1f} m" for z, m in self.by_zone.items())
        return f"walls lost (nothing can see them any more): {self.length_m:.1f} m: {zones}"

    def to_dict(self) -> dict[str, Any]:
        return {"length_m": round(self.length_m, 3), "by_zone": {k: round(v, 3) for k, v in self.by_zone.items()}}


@dataclass(frozen=True, kw_only=True, eq=False)
class RestProblem:
    """The coverage of the re-plan (rows: the candidates left, then the done stations not in the pool; columns: every
    wall piece), the rows of the done stations (``done_rows``, in the edits' order), the candidates the edits
    removed (by reason), the lost pieces, the registration groups and links of the rows and their overlap
    relation (None: no registration rule)."""

    coverage: CoverageProblem
    done_rows: tuple[int, ...]
    plan_rows: dict[str, int]
    removed: dict[str, int]
    hidden_pairs: int
    lost: Lost
    groups: tuple[Hashable, ...]
    links: sp.csr_matrix | None
    relation: sp.csr_matrix | None


def edited_site(site: Site, edits: Edits) -> Site:
    """``site`` with the obstacles the edits draw (as tall as the site's tallest wall: nothing is seen over them)."""
    tall = max((max(w.h_start_m, w.h_end_m) for w in site.walls), default=3.0)
    new = tuple(
        Obstacle(name=a.entry + (f" ({a.note})" if a.note else ""), vertices=a.polygon, height_m=tall)
        for a in edits.areas
        if a.kind == "obstacle"
    )
    return replace(site, obstacles=site.obstacles + new) if new else site


def forbidden(site: Site, edits: Edits, cands: Sequence[Candidate], frames: dict[str, str]) -> list[str]:
    """Why each candidate may not be used after the edits ('' where it may); ``frames``: the frame of each planned
    station, by id."""
    n = len(cands)
    out = [""] * n
    if n == 0:
        return out
    xy = np.array([c.xy for c in cands], dtype=float).reshape(-1, 2)
    frame = np.array([c.frame for c in cands], dtype=object)

    def mark(mask: NDArray[np.bool_], why: str) -> None:
        for k in np.flatnonzero(mask):
            out[k] = out[k] or why

    for e in edits.blocked:
        f = frames.get(e.station.id, SITE_FRAME)
        d = np.hypot(xy[:, 0] - e.station.xy[0], xy[:, 1] - e.station.xy[1])
        mark((frame == f) & (d <= e.radius_m), "blocked")
    site_frame = frame == SITE_FRAME
    standoff = site.parameters.min_standoff_m
    for a in edits.areas:
        poly = shapely.Polygon(a.polygon)
        inside = shapely.intersects_xy(poly, xy[:, 0], xy[:, 1])
        if a.kind == "obstacle" and standoff > 0:
            inside |= shapely.distance(poly, shapely.points(xy)) < standoff
        mark(site_frame & inside, "obstacle" if a.kind == "obstacle" else "closed area")
    for zid in edits.closed_zones:
        zone = site.zone(zid)
        mark((frame == zone.frame) & shapely.intersects_xy(zone.polygon, xy[:, 0], xy[:, 1]), "closed zone")
    return out


def hidden(coverage: CoverageProblem, obstacles: Sequence[Sequence[tuple[float, float]]]) -> NDArray[np.bool_]:
    """Which pairs of ``coverage`` (in its CSR order) an obstacle hides: the triangle from the candidate to the
    piece meets the obstacle's polygon (site frame only)."""
    by = coverage.by_candidate
    out = np.zeros(by.nnz, dtype=bool)
    if not obstacles or by.nnz == 0:
        return out
    t = coverage.targets
    rows = np.repeat(np.arange(by.shape[0]), np.diff(by.indptr))
    cols = by.indices
    site_f = np.array([c.frame == SITE_FRAME for c in coverage.candidates])
    xy = np.array([c.xy for c in coverage.candidates], dtype=float).reshape(-1, 2)
    p, a, b = xy[rows], t.a[cols], t.b[cols]
    lo, hi = np.minimum(np.minimum(p, a), b), np.maximum(np.maximum(p, a), b)
    for ob in obstacles:
        poly = shapely.Polygon(ob)
        x0, y0, x1, y1 = poly.bounds
        near = site_f[rows] & (lo[:, 0] <= x1) & (hi[:, 0] >= x0) & (lo[:, 1] <= y1) & (hi[:, 1] >= y0) & ~out
        k = np.flatnonzero(near)
        if k.size:
            tri = shapely.polygons(np.stack([p[k], a[k], b[k], p[k]], axis=1))
            out[k] = shapely.intersects(tri, poly)
    return out


def rest_problem(
    problem: Problem, data: ReplanData, edits: Edits, done: Sequence[Candidate], planned: Sequence[Candidate]
) -> RestProblem:
    """The problem of the rest (see the module text) over ``data`` (the plan's pool); ``problem``: the edited site's
    (its sight hides behind the obstacles); ``done``: the done stations where they stood (in the edits' order);
    ``planned``: the plan's stations in plan.json order (rows ``data.plan_rows``)."""
    site, pool = problem.site, data.coverage
    stored = {pool.candidates[r].id: r for r in data.plan_rows}  # the plan's stations, by id
    plan_row = {s.id: stored[s.id] for s in planned if s.id in stored}
    done_ids = {s.id for s in done}
    moved = [s for s in done if plan_row.get(s.id) is None or pool.candidates[plan_row[s.id]].xy != s.xy]
    moved_ids = {s.id for s in moved}
    why = forbidden(site, edits, pool.candidates, {s.id: s.frame for s in planned})
    exempt = {plan_row[i] for i in done_ids - moved_ids if i in plan_row}
    dropped_moved = {plan_row[i] for i in moved_ids if i in plan_row}  # the planned position of a moved station
    keep = np.array(
        [(not why[k] or k in exempt) and k not in dropped_moved for k in range(len(pool.candidates))], dtype=bool
    )
    removed = {r: sum(1 for k, w in enumerate(why) if w == r and k not in exempt) for r in REASONS}
    rows = np.flatnonzero(keep)
    by = pool.by_candidate[rows]
    slant, inc = pool.slant_m[rows], pool.incidence_deg[rows]
    cands = [pool.candidates[k] for k in rows]
    obstacles = [a.polygon for a in edits.areas if a.kind == "obstacle"]
    kept_cov = _coverage(cands, pool, by, slant, inc)
    hide = hidden(kept_cov, obstacles)
    changed = np.unique(np.repeat(np.arange(by.shape[0]), np.diff(by.indptr))[hide])
    if hide.any():
        kept_cov = _coverage(cands, pool, *(_without(m, hide) for m in (by, slant, inc)))
    if moved:  # where they really stood, seen on the edited site
        more = build_coverage(site, moved, pool.targets, problem.limits)
        kept_cov = _coverage(
            cands + list(more.candidates),
            pool,
            sp.vstack([kept_cov.by_candidate, more.by_candidate]),
            sp.vstack([kept_cov.slant_m, more.slant_m]),
            sp.vstack([kept_cov.incidence_deg, more.incidence_deg]),
        )
    new_row = {int(r): k for k, r in enumerate(rows)}
    row_of = {s.id: new_row[plan_row[s.id]] for s in done if s.id not in moved_ids}
    row_of.update({s.id: len(rows) + k for k, s in enumerate(moved)})
    done_rows = tuple(row_of[s.id] for s in done)
    groups, links, relation = _relation(problem, data, rows, kept_cov, moved, changed)
    return RestProblem(
        coverage=kept_cov,
        done_rows=done_rows,
        plan_rows={i: new_row[r] for i, r in plan_row.items() if r in new_row},
        removed=removed,
        hidden_pairs=int(hide.sum()),
        lost=_lost(kept_cov),
        groups=groups,
        links=links,
        relation=relation,
    )


def _coverage(cands: Sequence[Candidate], like: CoverageProblem, by: Any, slant: Any, inc: Any) -> CoverageProblem:
    by = sp.csr_matrix(by, dtype=bool)
    return CoverageProblem(
        candidates=tuple(cands),
        targets=like.targets,
        by_candidate=by,
        by_target=by.T.tocsr(),
        slant_m=sp.csr_matrix(slant),
        incidence_deg=sp.csr_matrix(inc),
        excluded={},
        limits=like.limits,
    )


def _without(m: sp.csr_matrix, drop: NDArray[np.bool_]) -> sp.csr_matrix:
    """``m`` (on the coverage's pattern) without the pairs ``drop`` marks."""
    coo = sp.csr_matrix(m).tocoo()
    keep = ~drop
    return sp.csr_matrix((coo.data[keep], (coo.row[keep], coo.col[keep])), shape=m.shape)


def _lost(cov: CoverageProblem) -> Lost:
    """The pieces no row sees, with their lengths summed by zone/side."""
    pieces = cov.uncoverable()
    t = cov.targets
    by_zone: dict[str, float] = {}
    for k in pieces:
        key = f"{t.zone_ids[int(t.zone[k])]}/{'inside' if int(t.side[k]) == 0 else 'outside'}"
        by_zone[key] = by_zone.get(key, 0.0) + float(t.s1_m[k] - t.s0_m[k])
    return Lost(pieces=tuple(int(k) for k in pieces), by_zone=by_zone, length_m=sum(by_zone.values()))


def _relation(
    problem: Problem,
    data: ReplanData,
    rows: NDArray[np.int64],
    cov: CoverageProblem,
    moved: Sequence[Candidate],
    changed: NDArray[np.int64],
) -> tuple[tuple[Hashable, ...], sp.csr_matrix | None, sp.csr_matrix | None]:
    """Registration groups, links and the overlap relation of ``cov``'s rows: the groups and links of the pool as
    stored where no row changed, made again for all of them where an obstacle hid pairs or a done station moved (a
    link through an opening may join a changed row to any other); the relation made over the rows
    (:func:`planner.io.replan_data.relation_of`: pairwise, so the same as the whole pool's restricted to them)."""
    if moved or changed.size:
        groups, links = problem.registration.groups(cov.candidates)
        return tuple(groups), links, relation_of(problem, cov, groups, links)
    groups = tuple(data.groups[int(r)] for r in rows)
    links = None if data.links is None else data.links[rows][:, rows].tocsr()
    return groups, links, relation_of(problem, cov, groups, links)
