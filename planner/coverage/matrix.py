"""The coverage problem: which candidate sees which target, kept in both sparse views."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
import shapely
from numpy.typing import NDArray

from planner.core import progress
from planner.coverage.faces import keyed_parts, partner_stretches, trim_at_junctions
from planner.coverage.openings import opening_segments, solid_intervals, wall_gaps
from planner.coverage.targets import Targets
from planner.coverage.visibility import Blockers, SightLimits, geometric_pairs, sight_clear, wall_key
from planner.site.candidate import Candidate
from planner.site.model import SITE_FRAME, Site

#: Candidates per block of the coverage build (the unit of its progress reports)
PROGRESS_BLOCK = 1024
#: Memory a block of the coverage build may take for its pairs, and the worst case per pair (every candidate of the
#: block paired with every piece of the frame: geometry, sight test, kept arrays).
BLOCK_BUDGET_BYTES = 256 * 2**20
PAIR_WORST_BYTES = 96
#: Pairs per batch of the sight test: its hit arrays (pairs x blockers in their boxes) stay bounded.
SIGHT_BATCH = 65_536
#: A station closer than this to a wall line is "on the wall" and stands nowhere.
ON_WALL_M = 1e-6
#: the last sites' blockers and zone-side blockers, by site and frame (each entry keeps its site: ids are reused)
_BUILT: dict[tuple[int, str, str], tuple[Site, Any]] = {}
#: entries kept before the cache starts afresh
_BUILT_MAX = 64


def _once(kind: str, site: Site, frame: str, build: Any) -> Any:
    """``build(site, frame)``, made once per site and frame (a site is immutable; a plan builds the coverage of its
    pool, of the complete step, of the tripod discs and of the bounds, each over the same walls)."""
    key = (id(site), frame, kind)
    hit = _BUILT.get(key)
    if hit is None or hit[0] is not site:
        if len(_BUILT) >= _BUILT_MAX:
            _BUILT.clear()
        hit = _BUILT[key] = (site, build(site, frame))
    return hit[1]


def blockers_for(site: Site, frame: str) -> Blockers:
    """Walls of every zone in ``frame`` and, in the site frame, the obstacle edges (made once per site and frame)."""
    blockers: Blockers = _once("blockers", site, frame, _blockers_for)
    return blockers


def zone_side_blockers(site: Site, frame: str) -> ZoneSideBlockers:
    """The :class:`ZoneSideBlockers` of ``frame``, made once per site and frame."""
    views: ZoneSideBlockers = _once("zone-side", site, frame, ZoneSideBlockers)
    return views


def _blockers_for(site: Site, frame: str) -> Blockers:
    """Walls of every zone in ``frame`` and, in the site frame, the obstacle edges."""
    a, b, key, verts = [], [], [], []

    def ring(xy: NDArray[np.float64], k: NDArray[np.int64]) -> None:
        a.append(xy)
        b.append(np.roll(xy, -1, axis=0))
        key.append(k)
        verts.append(xy)

    segments = opening_segments(site, frame)
    partners = partner_stretches(site, frame)
    for zi, zone in enumerate(site.zones):
        if zone.frame != frame:
            continue
        if segments or partners:  # openings are gaps; shared faces swap keys (planner.coverage.faces)
            pa, pb, pk = _solid_parts(site, zi, segments, partners)
            if partners:
                pa, pb, pk, pv = trim_at_junctions(site, zi, pa, pb, pk)
            else:
                pv = np.concatenate([pa, pb])
            a.append(pa)
            b.append(pb)
            key.append(pk)
            verts.append(pv)
            continue
        first = 1
        for xy in zone.rings:
            ring(xy, wall_key(zi, np.arange(first, first + len(xy))))
            first += len(xy)
    for ob in site.obstacles if frame == SITE_FRAME else ():
        ring(np.asarray(ob.vertices, dtype=float), np.full(len(ob.vertices), -1, dtype=np.int64))
    if not a:
        z = np.zeros((0, 2))
        return Blockers(z, z, np.zeros(0, np.int64), z)
    return Blockers(np.concatenate(a), np.concatenate(b), np.concatenate(key), np.concatenate(verts))


def _solid_parts(site: Site, zi: int, segments: list, partners: dict) -> tuple[NDArray, NDArray, NDArray]:
    """Start points, end points and wall keys of the solid parts of zone ``zi``'s walls (a stretch shared with another
    zone's face blocks under that face's key)."""
    a, b, key = [], [], []
    for w in site.zones[zi].walls:
        start, end = np.asarray(w.start, float), np.asarray(w.end, float)
        u = (end - start) / w.length_m
        own = int(wall_key(zi, w.index))
        for lo, hi in solid_intervals(w.length_m, wall_gaps(site, zi, w, segments)):
            for s0, s1, k in keyed_parts(lo, hi, own, partners.get((zi, w.index), [])):
                a.append(start + s0 * u)
                b.append(start + s1 * u)
                key.append(k)
    if not a:
        return np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0, np.int64)
    return np.array(a), np.array(b), np.array(key, dtype=np.int64)


def convex_alone(site: Site, frame: str) -> bool:
    """True when ``frame`` holds one convex zone without holes and (in the site frame) no obstacles: then every
    front-facing pair is in clear view, and the sight test is spared (finely drawn round rooms)."""
    zones = [z for z in site.zones if z.frame == frame]
    if len(zones) != 1 or zones[0].holes or (frame == SITE_FRAME and site.obstacles):
        return False
    poly = zones[0].polygon
    return poly.convex_hull.area - poly.area <= 1e-9 * poly.area


def _ordered(parts: list, order: NDArray[np.int64] | None, dtype: type) -> NDArray:
    """Concatenate per-block arrays and put them in CSR order."""
    a: NDArray[Any] = np.concatenate(parts).astype(dtype, copy=False) if parts else np.zeros(0, dtype)
    return a if order is None else a[order]


def block_size(n_targets: int) -> int:
    """Candidates per block: at most ``PROGRESS_BLOCK``, fewer when the frame has so many pieces that a block's worst
    case (every pair kept) would pass ``BLOCK_BUDGET_BYTES``; at least 16."""
    return int(max(16, min(PROGRESS_BLOCK, BLOCK_BUDGET_BYTES // max(1, n_targets * PAIR_WORST_BYTES))))


class ZoneSideBlockers:
    """The blockers that can hide a piece of one zone-side from a station on that side, built once per zone-side of a
    frame: from inside zone z only edges that meet z, from outside only edges not strictly inside z; a zone with
    openings keeps every blocker of the frame. A building of many rooms then does not test every room's walls against
    every view."""

    def __init__(self, site: Site, frame: str) -> None:
        self.site, self.all = site, blockers_for(site, frame)
        self._lines = shapely.linestrings(np.stack([self.all.a, self.all.b], axis=1)) if len(self.all.a) else None
        self._cache: dict[int, Blockers] = {}
        # zones with a gap in a wall: their own openings, or a neighbour's door through their shared wall
        segments = opening_segments(site, frame)
        self._open = {
            zi
            for zi, z in enumerate(site.zones)
            if z.frame == frame and segments and any(wall_gaps(site, zi, w, segments) for w in z.walls)
        }

    def of(self, zone_index: int, inside: bool) -> Blockers:
        key = 2 * zone_index + (0 if inside else 1)
        if key not in self._cache:
            zone = self.site.zones[zone_index]
            if self._lines is None or zone_index in self._open:
                self._cache[key] = self.all
            else:
                poly = zone.polygon
                keep = (
                    shapely.intersects(poly, self._lines) if inside else ~shapely.contains_properly(poly, self._lines)
                )
                b = self.all
                self._cache[key] = Blockers(b.a[keep], b.b[keep], b.key[keep], _kept_vertices(b, keep))
        return self._cache[key]

    def clear(
        self, xy: NDArray[np.float64], targets: Targets, pc: NDArray[np.int64], pt: NDArray[np.int64]
    ) -> NDArray[np.bool_]:
        """Sight test of the pairs (pc[k], pt[k]), zone-side by zone-side, in batches of SIGHT_BATCH pairs."""
        out = np.ones(len(pc), dtype=bool)
        group = targets.zone[pt].astype(np.int64) * 2 + targets.side[pt]
        by_group = np.argsort(group, kind="stable")  # each zone-side's pairs in their order
        cuts = np.flatnonzero(np.diff(group[by_group])) + 1
        for idx in np.split(by_group, cuts) if len(pc) else []:
            g = int(group[idx[0]])
            blockers = self.of(g // 2, g % 2 == 0)
            for lo in range(0, idx.size, SIGHT_BATCH):
                k = idx[lo : lo + SIGHT_BATCH]
                out[k] = sight_clear(
                    xy[pc[k]],
                    targets.a[pt[k]],
                    targets.b[pt[k]],
                    wall_key(targets.zone[pt[k]], targets.wall[pt[k]]),
                    blockers,
                )
        return out


def _kept_vertices(b: Blockers, keep: NDArray[np.bool_]) -> NDArray[np.float64]:
    """The blocker vertices (only those ``blockers_for`` gave: it drops the vertices of wall ends cut back at junctions,
    :func:`planner.coverage.faces.trim_at_junctions`) that are end points of the kept segments."""
    if not keep.any() or len(b.vertices) == 0:
        return np.zeros((0, 2))
    ends = {tuple(p) for p in np.vstack([b.a[keep], b.b[keep]]).tolist()}
    mask = np.array([tuple(p) in ends for p in b.vertices.tolist()], dtype=bool)
    return np.unique(b.vertices[mask], axis=0)


@dataclass(frozen=True, eq=False)
class Places:
    """Where stations stand: ``inside[c, z]`` (inside zone z), ``reason[c]`` why c stands nowhere ('' if fine)."""

    inside: NDArray[np.bool_]
    reason: tuple[str, ...]


def station_places(site: Site, xy: NDArray[np.float64], frames: Sequence[str]) -> Places:
    """Classify station positions: inside which zones, and forbidden ones with the reason: on a wall line or closer to
    one than the stand-off (``min_standoff_m``), inside an obstacle or closer to its edge than the stand-off, inside a
    no-go area, or outside the site boundary (these three in the site frame)."""
    n = len(xy)
    standoff = site.parameters.min_standoff_m
    frames_arr = np.asarray(frames, dtype=object)
    inside = np.zeros((n, len(site.zones)), dtype=bool)
    reason = [""] * n
    x, y = (xy[:, 0], xy[:, 1]) if n else (np.zeros(0), np.zeros(0))
    pts = shapely.points(xy) if n else np.zeros(0, dtype=object)
    # a point outside a zone's box grown by this is farther than both limits from its walls, and not inside it
    reach = max(standoff, ON_WALL_M)
    for zi, zone in enumerate(site.zones):
        x0, y0, x1, y1 = zone.polygon.bounds
        near = (frames_arr == zone.frame) & (x >= x0 - reach) & (x <= x1 + reach) & (y >= y0 - reach)
        near = np.flatnonzero(near & (y <= y1 + reach))
        if near.size == 0:
            continue
        inside[near, zi] = shapely.contains_xy(zone.polygon, x[near], y[near])
        dist = shapely.distance(zone.polygon.boundary, pts[near])
        for k, d in zip(near, dist):
            if d <= ON_WALL_M:
                reason[k] = reason[k] or f"on a wall of zone {zone.id}"
            elif d < standoff:
                reason[k] = reason[k] or f"{d:.3f} m from a wall of zone {zone.id} (stand-off {standoff:g} m)"
    in_site = frames_arr == SITE_FRAME
    if standoff > 0:
        for ob in site.obstacles:
            edge = shapely.Polygon(ob.vertices).boundary
            dist = shapely.distance(edge, pts) if n else np.zeros(0)
            for k in np.flatnonzero(in_site & (dist < standoff)):
                reason[k] = reason[k] or f"{dist[k]:.3f} m from obstacle {ob.name} (stand-off {standoff:g} m)"
    checks = [(ob.name, "inside obstacle", shapely.Polygon(ob.vertices)) for ob in site.obstacles]
    checks += [(ng.name, "in no-go area", shapely.Polygon(ng.vertices)) for ng in site.no_go_areas]
    for name, what, poly in checks:
        for k in np.flatnonzero(in_site & shapely.intersects_xy(poly, x, y)):
            reason[k] = reason[k] or f"{what} {name}"
    if site.boundary is not None:
        bnd = shapely.Polygon(site.boundary)
        for k in np.flatnonzero(in_site & ~shapely.intersects_xy(bnd, x, y)):
            reason[k] = reason[k] or "outside the site boundary"
    return Places(inside=inside, reason=tuple(reason))


def _on_own_side(site: Site, cands: Sequence[Candidate], places: Places) -> Places:
    """Also forbid a candidate that does not stand on its own zone-side (as verification does): with zones placed in one
    frame, a point made for one room (a corner ray, say) may lie in another room, and would otherwise cover that room's
    walls under the wrong zone's name. A candidate of no zone (``zone ''``: a position priced over the plane, whose
    owner its coverage decides) is left alone."""
    index = {z.id: i for i, z in enumerate(site.zones)}
    reason = list(places.reason)
    for k, c in enumerate(cands):
        zi = index.get(c.zone)
        if zi is not None and not reason[k] and bool(places.inside[k, zi]) != (c.side.value == "inside"):
            reason[k] = f"not {c.side.value} zone {c.zone}"
    return Places(places.inside, tuple(reason))


@dataclass(frozen=True, eq=False, kw_only=True)
class CoverageProblem:
    """Candidates, targets and the boolean coverage matrix in both views: ``by_candidate`` C x T and ``by_target`` T x C
    (CSR); ``slant_m`` and ``incidence_deg`` hold, on ``by_candidate``'s pattern, the worst slant range and incidence
    over each piece."""

    candidates: tuple[Candidate, ...]
    targets: Targets
    by_candidate: sp.csr_matrix
    by_target: sp.csr_matrix
    slant_m: sp.csr_matrix
    incidence_deg: sp.csr_matrix
    excluded: dict[int, str]
    limits: SightLimits

    @property
    def shape(self) -> tuple[int, int]:
        return self.by_candidate.shape

    def uncoverable(self) -> NDArray[np.int64]:
        """Targets no candidate sees (an infeasible cover)."""
        return np.flatnonzero(np.diff(self.by_target.indptr) == 0)

    def covered_by(self, selection: Sequence[int]) -> NDArray[np.int64]:
        """How many of the selected candidates see each target."""
        if len(selection) == 0:
            return np.zeros(self.shape[1], dtype=np.int64)
        return np.asarray(self.by_candidate[list(selection)].sum(axis=0)).ravel().astype(np.int64)


def build_coverage(
    site: Site, candidates: Sequence[Candidate], targets: Targets, limits: SightLimits, step: str = ""
) -> CoverageProblem:
    """Compute which candidate sees which target (:mod:`planner.coverage.visibility`); with ``step`` set, progress is
    reported every block of candidates under that name (:mod:`planner.core.progress`)."""
    cands = tuple(candidates)
    xy = np.array([c.xy for c in cands], dtype=float).reshape(-1, 2)
    places = _on_own_side(site, cands, station_places(site, xy, [c.frame for c in cands]))
    rows, cols, slant, inc = [], [], [], []
    cand_frame = np.array([c.frame for c in cands], dtype=object)
    usable = np.array([r == "" for r in places.reason], dtype=bool)
    total, done = int(usable.sum()), 0
    for fi, frame in enumerate(targets.frames):
        ci = np.flatnonzero((cand_frame == frame) & usable)
        ti = np.flatnonzero(targets.frame == fi)
        if ci.size == 0 or ti.size == 0:
            continue
        open_view = convex_alone(site, frame)  # nothing can block a front-facing piece of a lone convex zone
        views = None if open_view else zone_side_blockers(site, frame)
        for block in np.array_split(ci, math.ceil(len(ci) / block_size(len(ti)))):
            pairs = geometric_pairs(xy[block], places.inside[block], targets, ti, limits)
            pc, pt = block[pairs.cand], ti[pairs.target]
            clear = np.ones(len(pc), dtype=bool) if views is None else views.clear(xy, targets, pc, pt)
            rows.append(pc[clear].astype(np.int32))
            cols.append(pt[clear].astype(np.int32))
            slant.append(pairs.slant_m[clear])
            inc.append(pairs.incidence_deg[clear])
            done += len(block)
            if step:
                progress.report(step, done, total)
    if step:
        progress.report(step, total, total)
    shape = (len(cands), len(targets))
    r = np.concatenate(rows) if rows else np.zeros(0, np.int32)
    del rows
    # each candidate's pairs come from one block, sorted by piece: a stable sort by candidate is CSR order
    order = None if np.all(r[1:] >= r[:-1]) else np.argsort(r, kind="stable")
    indptr = np.concatenate([[0], np.cumsum(np.bincount(r, minlength=shape[0]))]).astype(
        np.int32 if r.size < 2**31 else np.int64
    )
    del r
    indices = _ordered(cols, order, np.int32)

    def mat(parts: list, dtype: type) -> sp.csr_matrix:  # the three matrices share one pattern (indices, indptr)
        return sp.csr_matrix((_ordered(parts, order, dtype), indices, indptr), shape=shape, copy=False)

    by_candidate = sp.csr_matrix((np.ones(len(indices), dtype=bool), indices, indptr), shape=shape, copy=False)
    return CoverageProblem(
        candidates=cands,
        targets=targets,
        by_candidate=by_candidate,
        by_target=by_candidate.T.tocsr(),
        slant_m=mat(slant, np.float64),
        incidence_deg=mat(inc, np.float64),
        excluded={k: why for k, why in enumerate(places.reason) if why},
        limits=limits,
    )


def merge_problems(p: CoverageProblem, q: CoverageProblem) -> CoverageProblem:
    """``p`` with the candidates of ``q`` appended (same targets and limits)."""
    by_c = sp.vstack([p.by_candidate, q.by_candidate]).tocsr()
    off = len(p.candidates)
    return CoverageProblem(
        candidates=p.candidates + q.candidates,
        targets=p.targets,
        by_candidate=by_c,
        by_target=by_c.T.tocsr(),
        slant_m=sp.vstack([p.slant_m, q.slant_m]).tocsr(),
        incidence_deg=sp.vstack([p.incidence_deg, q.incidence_deg]).tocsr(),
        excluded={**p.excluded, **{k + off: v for k, v in q.excluded.items()}},
        limits=p.limits,
    )
