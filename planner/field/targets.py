"""Registration targets: where two linked stations share little wall, targets both of them see.

Links: the overlap relation of the plan's stations (:func:`planner.coverage.overlap.overlap_graph`, in the site's
registration groups, with the links through openings, which share no wall). The crew registers along a chain: in
registration order each station on the earlier station it shares most with, otherwise the maximum spanning forest of the
relation by shared fraction (``shared / smaller covered length``). A chain link is weak when that fraction is below
``strong_overlap``; a weak link is made strong by :data:`TARGETS_PER_LINK` targets seen by both stations (target-based
registration needs three common targets, seed 003).

Target places: a checkerboard at the middle of a wall piece (1 m pieces) that both stations see within the instrument's
target range and target incidence, or a sphere on a tripod in the walkable area (a grid of :data:`SPHERE_GRID_M` within
target range of both, the pair's midpoint (else a point of the lens both reach, which a thin lens may hold without a
grid point), and the middle of every door and gate), at least :data:`MIN_TARGET_DISTANCE_M` from each and in sight of
both. Each weak link gets its own three places, spread apart: of the places both stations see, the triple with the
largest smallest pairwise distance among the triangles with no angle below :data:`~planner.field.spread.MIN_ANGLE_DEG`
(exact; :mod:`planner.field.spread`), with that distance, the triangle's smallest angle and, where the places allow no
:data:`~planner.field.spread.MIN_SPREAD_M` or no such triangle, why. Control points of the instance are targets too
(ties to control), listed with the stations that see them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import networkx as nx
import numpy as np
import shapely
from numpy.typing import NDArray

from planner.core.settings import DEFAULTS
from planner.coverage.matrix import CoverageProblem, blockers_for
from planner.coverage.openings import PASSABLE, opening_segments
from planner.coverage.stair_links import stair_edge
from planner.coverage.visibility import sight_clear
from planner.field.spread import Spread, spread
from planner.field.walking import WalkSpace
from planner.instrument.field_table import FieldProperties
from planner.site.candidate import Candidate
from planner.site.model import Site

TARGETS_PER_LINK = 3
SPHERE_GRID_M = 1.0
MIN_TARGET_DISTANCE_M = 2.0
#: a link sharing at least this fraction of the smaller scan's covered wall needs no targets
STRONG_OVERLAP: float = DEFAULTS["field.strong_overlap"]
_NO_WALL = -2


@dataclass(frozen=True)
class Link:
    """A registration link of the chain: stations ``a`` and ``b`` (ids), their shared wall, and its targets."""

    a: str
    b: str
    shared_m: float
    fraction: float
    weak: bool
    targets: tuple[str, ...] = ()
    places: int = 0  # target places both see (fewer than TARGETS_PER_LINK: the link stays weak)
    apart_m: float = 0.0  # straight-line distance of the two stations
    reason: str = ""  # why a weak link stays weak ("" when it is not)
    spread_m: float | None = None  # the smallest pairwise distance of its targets (two or more)
    min_angle_deg: float | None = None  # the smallest angle of their triangle (three)
    spread_note: str = ""  # why they stand closer than MIN_SPREAD_M or make a thinner triangle ("" when not)


@dataclass(frozen=True)
class Target:
    """A proposed (or control) target: where it stands and which stations see it."""

    id: str
    kind: str  # checkerboard | sphere | control
    x: float
    y: float
    where: str
    seen_by: tuple[str, ...]
    links: tuple[tuple[str, str], ...]


def chain_links(g: nx.Graph, order: Sequence[int] | None) -> list[tuple[int, int]]:
    """The links the crew registers on (see the module text; ``order`` None: the spanning forest)."""
    if order is None:
        forest = nx.maximum_spanning_tree(g, weight="fraction", algorithm="kruskal")
        return sorted((min(u, v), max(u, v)) for u, v in forest.edges())
    seen: list[int] = []
    out = []
    for node in order:
        earlier = [u for u in seen if g.has_edge(u, node)]
        if earlier:
            best = max(earlier, key=lambda u: (g[u][node]["fraction"], -u))
            out.append((best, node))
        seen.append(node)
    return out


def _sphere_places(
    space: WalkSpace, site: Site, xy: NDArray[np.float64], pairs: list[tuple[int, int]], reach: float
) -> NDArray[np.float64]:
    """Tripod places: a grid within ``reach`` of both stations of a pair, and the middle of every door."""
    pts = [ends.mean(axis=0) for _zi, _w, kind, ends in opening_segments(site, space.frame) if kind in PASSABLE]
    for i, j in pairs:
        lens = shapely.Point(xy[i]).buffer(reach).intersection(shapely.Point(xy[j]).buffer(reach))
        lens = lens.intersection(space.area)
        if lens.is_empty:
            continue
        mid = shapely.Point((xy[i] + xy[j]) / 2.0)  # a tripod half-way, else some point both reach
        pts.append(np.array((mid if lens.covers(mid) else lens.representative_point()).coords[0]))
        x0, y0, x1, y1 = lens.bounds
        gx, gy = np.meshgrid(
            np.arange(math.floor(x0), x1 + 1e-9, SPHERE_GRID_M), np.arange(math.floor(y0), y1 + 1e-9, SPHERE_GRID_M)
        )
        grid = np.column_stack([gx.ravel(), gy.ravel()])
        inside = shapely.contains_xy(lens, grid[:, 0], grid[:, 1]) if len(grid) else np.zeros(0, bool)
        pts += list(grid[inside])
    if not pts:
        return np.zeros((0, 2))
    return np.unique(np.round(np.asarray(pts, dtype=float), 6), axis=0)


def _sphere_sight(
    site: Site, frame: str, xy: NDArray[np.float64], places: NDArray[np.float64], reach: float
) -> NDArray[np.bool_]:
    """S x P: station s sees sphere place p (in range, not too close, nothing in between)."""
    seen = np.zeros((len(xy), len(places)), dtype=bool)
    if not len(places):
        return seen
    blockers = blockers_for(site, frame)
    for s, c in enumerate(xy):
        r = np.hypot(*(places - c).T)
        idx = np.flatnonzero((r <= reach) & (r >= MIN_TARGET_DISTANCE_M))
        if idx.size:
            cc = np.repeat(c[None], idx.size, axis=0)
            seen[s, idx] = sight_clear(cc, places[idx], places[idx], np.full(idx.size, _NO_WALL), blockers)
    return seen


def _storey_places(
    site: Site,
    stations: Sequence[Candidate],
    spaces: Mapping[str, WalkSpace],
    xy: NDArray[np.float64],
    pairs: list[tuple[int, int]],
    reach: float,
) -> tuple[NDArray[np.float64], NDArray[np.bool_], list[str]]:
    """Tripod places across storeys, what each station sees of them and where they stand: in each frame with
    stations, those of :func:`_sphere_places` for its pairs, seen from its own stations only (its own walls);
    for a pair of two frames (a link through a stair, :mod:`planner.coverage.stair_links`), the edge points
    of the stairs that join the two frames, each seen from the stations of both (each in its own frame)."""
    frame = np.array([s.frame for s in stations], dtype=str)
    blocks: list[NDArray[np.float64]] = []
    sights: list[NDArray[np.bool_]] = []
    where: list[str] = []
    for fr, sp in spaces.items():
        here = frame == fr
        if not here.any():
            continue
        p = _sphere_places(sp, site, xy, [(i, j) for i, j in pairs if frame[i] == fr == frame[j]], reach)
        seen = np.zeros((len(stations), len(p)), dtype=bool)
        seen[here] = _sphere_sight(site, fr, xy[here], p, reach)
        blocks.append(p)
        sights.append(seen)
        where += ["tripod"] * len(p)
    across = {frozenset((frame[i], frame[j])) for i, j in pairs if frame[i] != frame[j]}
    for stair in site.stairs:
        ends = (site.zone(stair.lower_zone).frame, site.zone(stair.upper_zone).frame)
        if frozenset(ends) not in across:
            continue
        e = stair_edge(stair)
        seen = np.zeros((len(stations), len(e)), dtype=bool)
        for fr in ends:
            here = frame == fr
            if here.any():
                seen[here] = _sphere_sight(site, fr, xy[here], e, reach)
        blocks.append(e)
        sights.append(seen)
        where += [f"tripod at the edge of stair {stair.name}"] * len(e)
    if not blocks:
        return np.zeros((0, 2)), np.zeros((len(stations), 0), dtype=bool), []
    return np.vstack(blocks), np.hstack(sights), where


def _wall_sight(problem: CoverageProblem, props: FieldProperties) -> NDArray[np.bool_]:
    """S x T: station s reads a checkerboard on piece t (seen, within target range and incidence)."""
    by = problem.by_candidate.tocsr()
    ok = (problem.slant_m.data <= props.target_range_m) & (problem.incidence_deg.data <= props.target_incidence_deg)
    out = np.zeros(by.shape, dtype=bool)
    rows = np.repeat(np.arange(by.shape[0]), np.diff(by.indptr))
    out[rows[ok], by.indices[ok]] = True
    return out


def propose_targets(
    site: Site,
    stations: Sequence[Candidate],
    space: WalkSpace,
    props: FieldProperties,
    relation: nx.Graph,
    problem: CoverageProblem,
    order: Sequence[int] | None = None,
    strong_overlap: float = STRONG_OVERLAP,
    spaces: Mapping[str, WalkSpace] | None = None,
) -> tuple[list[Link], list[Target]]:
    """The chain links (weak ones with their targets) and the targets (see the module text). ``relation``: the
    plan's registration relation of ``stations`` (:meth:`planner.coverage.relation.Registration.relation`);
    ``problem``: their coverage, rows in their order; ``order``: the visiting order as station indices (registration
    order; None: the spanning forest); ``spaces``: across storeys, the walkable area of every frame (None: ``space``).
    """
    g = relation
    chain = chain_links(g, order)
    weak = [(i, j) for i, j in chain if g[i][j]["fraction"] < strong_overlap]
    xy = np.array([s.xy for s in stations], dtype=float).reshape(-1, 2)
    reach = props.target_range_m
    wall = _wall_sight(problem, props)
    places, sphere, where_of = _storey_places(site, stations, spaces or {space.frame: space}, xy, weak, reach)
    t = problem.targets
    cand_xy = np.vstack([(t.a + t.b) / 2.0, places]) if len(places) else (t.a + t.b) / 2.0
    seen = np.hstack([wall, sphere])  # S x (pieces + places)
    own = {(i, j): _spread(seen, cand_xy, i, j) for i, j in weak}
    chosen = sorted({c for sp in own.values() for c in sp.chosen})
    targets: list[Target] = []
    tid: dict[int, str] = {}
    for c in chosen:
        tid[c] = f"T{len(targets) + 1}"
        serves = tuple((stations[i].id, stations[j].id) for (i, j), sp in own.items() if c in sp.chosen)
        if c < len(t):
            kind, where = "checkerboard", f"wall {t.label(c).split(' ')[0]} at {(t.s0_m[c] + t.s1_m[c]) / 2:.1f} m"
        else:
            kind, where = "sphere", where_of[c - len(t)]
        targets.append(
            Target(
                tid[c],
                kind,
                float(cand_xy[c, 0]),
                float(cand_xy[c, 1]),
                where,
                tuple(stations[int(s)].id for s in np.flatnonzero(seen[:, c])),
                serves,
            )
        )
    targets += _control_targets(site, stations, xy, reach, len(targets))
    links = []
    for i, j in chain:
        both = seen[i] & seen[j]
        sp = own.get((i, j), Spread((), None, None))
        still = (i, j) in weak and len(sp.chosen) < TARGETS_PER_LINK
        apart = float(np.hypot(*(xy[i] - xy[j])))
        links.append(
            Link(
                stations[i].id,
                stations[j].id,
                g[i][j]["shared_m"],
                g[i][j]["fraction"],
                still,
                tuple(tid[c] for c in sp.chosen),
                int(both.sum()),
                apart,
                _reason(apart, reach, int(both.sum())) if still else "",
                sp.min_distance_m,
                sp.min_angle_deg,
                sp.note,
            )
        )
    return links, targets


def _spread(seen: NDArray[np.bool_], cand_xy: NDArray[np.float64], i: int, j: int) -> Spread:
    """The spread triple (:func:`~planner.field.spread.spread`) of the places both stations of the weak link (i, j)
    see, as indices of ``cand_xy``."""
    cands = np.flatnonzero(seen[i] & seen[j])
    sp = spread(cand_xy[cands])
    return Spread(tuple(sorted(int(cands[k]) for k in sp.chosen)), sp.min_distance_m, sp.min_angle_deg, sp.note)


def _reason(apart: float, reach: float, places: int) -> str:
    """Why a weak link keeps fewer than :data:`TARGETS_PER_LINK` targets."""
    if apart > 2.0 * reach:
        return (
            f"the stations stand {apart:.1f} m apart, more than twice the {reach:g} m target range: no target "
            f"place is within range of both (register on the scans' overlap, or add a station between them)"
        )
    return (
        f"only {places} place(s) both stations see within the {reach:g} m target range and the target "
        f"incidence (walls, obstacles or the walkable area leave no more)"
    )


def _control_targets(
    site: Site, stations: Sequence[Candidate], xy: NDArray[np.float64], reach: float, first: int
) -> list[Target]:
    """A target on every control point of the instance, with the stations that see it (ties to control)."""
    out = []
    for k, cp in enumerate(site.control_points, 1):
        here = np.array([s.frame == cp.frame for s in stations], dtype=bool)
        p = np.array([[cp.x, cp.y]])
        seen = []
        if here.any():
            sight = _sphere_sight(site, cp.frame, xy[here], p, reach)[:, 0]
            ids = [s.id for s, h in zip(stations, here) if h]
            seen = [i for i, ok in zip(ids, sight) if ok]
        out.append(Target(f"T{first + k}", "control", cp.x, cp.y, f"control point {cp.name}", tuple(seen), ()))
    return out
