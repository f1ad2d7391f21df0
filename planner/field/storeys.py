"""Walking across storeys: the walk graphs of several frames joined by their stairs.

A building read with every storey holds one frame per storey; the frames share plan coordinates and differ by
name only (:mod:`planner.site.stairs`). Within a frame the walk is that of :mod:`planner.field.walking`. A
stair joins the frame of its lower zone to that of its upper zone by one **stair leg**:

- its two ends are the ends of the footprint's long axis: the middles of the two short sides of the
  footprint's minimum rotated rectangle (:func:`stair_ends`), each moved to the nearest point of its zone's
  walkable area (the foot into the lower zone's, the head into the upper zone's: the footprint's edge is a
  wall of the room or the stairwell);
- the flight's direction is not in the site model (a footprint and a z range), so the end the upper zone's
  outline touches more is the **head** (where the stair arrives upstairs) and the other end is the **foot**
  (downstairs); where the upper zone touches both ends alike, the end the lower zone touches more is the foot;
  where both tie, either end may be the foot and both flights are offered (the walk takes the shorter);
- the leg runs from the foot, in the lower frame, to the head, in the upper frame; its length is the
  stair's **run** (the distance in plan between the foot and the head) **plus its rise** (``z_max_m - z_min_m``),
  timed at the walking speed like any walk.

The distance between two points of different frames is the shortest walk through the stair(s): Dijkstra over a
small graph whose nodes are the stations, the start and the stair ends, each frame's walks between them and the
stair legs (:func:`storey_walks`). Frames that no stair joins keep the refusal of one frame's sheet.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import networkx as nx
import numpy as np
import shapely
import shapely.ops
from numpy.typing import NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components, dijkstra

from planner.field.walking import SNAP_M, WalkGraph, WalkSpace, walk_graph, walk_nodes, walk_space
from planner.site.candidate import Candidate
from planner.site.model import Site
from planner.site.stairs import Stair

if TYPE_CHECKING:
    from planner.field.run import FieldPlan

#: a zone's outline this close to a footprint's short side touches it (m)
TOUCH_M = 0.05


@dataclass(frozen=True)
class Flight:
    """A stair leg: from ``foot`` in frame ``lower`` up to ``head`` in frame ``upper``; ``length_m`` is
    ``run_m + rise_m``."""

    stair: str
    lower: str
    upper: str
    foot: tuple[float, float]
    head: tuple[float, float]
    run_m: float
    rise_m: float

    @property
    def length_m(self) -> float:
        return self.run_m + self.rise_m


def stair_sides(stair: Stair) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The two short sides (2 x 2 each) of the footprint's minimum rotated rectangle, the one whose middle is
    lower in (x, y) first (a square: the first pair of opposite sides)."""
    rect = shapely.minimum_rotated_rectangle(shapely.Polygon(stair.footprint))
    c = np.asarray(rect.exterior.coords, dtype=float)[:4]
    if float(np.hypot(*(c[1] - c[0]))) <= float(np.hypot(*(c[2] - c[1]))) + 1e-9:
        a, b = c[[0, 1]], c[[2, 3]]
    else:
        a, b = c[[1, 2]], c[[3, 0]]
    return (a, b) if tuple(a.mean(axis=0)) <= tuple(b.mean(axis=0)) else (b, a)


def stair_ends(stair: Stair) -> tuple[tuple[float, float], tuple[float, float]]:
    """The ends of the footprint's long axis: the middles of its rectangle's short sides (:func:`stair_sides`)."""
    a, b = stair_sides(stair)
    return _pt(a.mean(axis=0)), _pt(b.mean(axis=0))


def _pt(p: NDArray[np.float64]) -> tuple[float, float]:
    return float(p[0]), float(p[1])


def _touch(site: Site, zone: str, side: NDArray[np.float64]) -> float:
    """Length of the short ``side`` that ``zone``'s outline runs along (within :data:`TOUCH_M`, m)."""
    edge = site.zone(zone).polygon.boundary.buffer(TOUCH_M)
    return float(shapely.LineString(side).intersection(edge).length)


def directions(site: Site, stair: Stair) -> list[tuple[tuple[float, float], tuple[float, float]]]:
    """(foot end, head end) of ``stair``: one pair, or both where its direction is a tie (see the module text)."""
    sa, sb = stair_sides(stair)
    a, b = stair_ends(stair)
    up_a, up_b = _touch(site, stair.upper_zone, sa), _touch(site, stair.upper_zone, sb)
    lo_a, lo_b = _touch(site, stair.lower_zone, sa), _touch(site, stair.lower_zone, sb)
    if abs(up_a - up_b) > 1e-6:
        return [(b, a)] if up_a > up_b else [(a, b)]
    if abs(lo_a - lo_b) > 1e-6:
        return [(a, b)] if lo_a > lo_b else [(b, a)]
    return [(a, b), (b, a)]


def _place(space: WalkSpace, site: Site, zone: str, end: tuple[float, float]) -> tuple[float, float] | None:
    """The point of ``zone``'s walkable area nearest ``end`` (None: none within :data:`SNAP_M`)."""
    room = space.area.intersection(site.zone(zone).polygon)
    if room.is_empty:
        return None
    p = shapely.ops.nearest_points(room, shapely.Point(end))[0]
    return (float(p.x), float(p.y)) if math.dist((p.x, p.y), end) <= SNAP_M else None


def flights(site: Site, stair: Stair, spaces: dict[str, WalkSpace]) -> list[Flight]:
    """The stair leg(s) of ``stair`` whose foot and head lie in the walkable area of its lower and upper
    zone (within :data:`SNAP_M` of the footprint's ends; ``spaces``: the frames' walkable areas)."""
    lower, upper = site.zone(stair.lower_zone).frame, site.zone(stair.upper_zone).frame
    if lower not in spaces or upper not in spaces:
        return []
    rise = max(0.0, stair.z_max_m - stair.z_min_m)
    out = []
    for f_end, h_end in directions(site, stair):
        foot = _place(spaces[lower], site, stair.lower_zone, f_end)
        head = _place(spaces[upper], site, stair.upper_zone, h_end)
        if foot is not None and head is not None:
            out.append(Flight(stair.name, lower, upper, foot, head, math.dist(foot, head), rise))
    return out


def joined_frames(site: Site, frames: Sequence[str]) -> list[str] | None:
    """The frames a walk from ``frames`` (those the stations stand in) may pass through: the frames of the
    stairs' component holding them, less those beyond every station's storey (a storey above the top one with
    stations, and so on), in the site's zone order; None where no chain of stairs joins them all."""
    g = nx.Graph()
    g.add_nodes_from(frames)
    for s in site.stairs:
        g.add_edge(site.zone(s.lower_zone).frame, site.zone(s.upper_zone).frame)
    comp = nx.node_connected_component(g, frames[0])
    if any(f not in comp for f in frames):
        return None
    sub = nx.Graph(g.subgraph(comp))
    # a storey beyond the last one with stations is never walked through
    while leaves := [f for f in sub if sub.degree(f) <= 1 and f not in frames]:
        sub.remove_nodes_from(leaves)
    comp = set(sub)
    order = list(dict.fromkeys(z.frame for z in site.zones))
    return [f for f in order if f in comp] + sorted(f for f in comp if f not in order)


@dataclass(frozen=True, eq=False)
class StoreyWalk:
    """Shortest walks between ``points`` of several frames joined by stairs: ``points[i]`` stands in frame
    ``frames[i]``; ``dist[i, j]`` in m (inf: not reachable); ``component[i]``: the walkable part point i stands in
    (parts joined by a stair are one)."""

    points: NDArray[np.float64]
    frames: tuple[str, ...]
    spaces: dict[str, WalkSpace]
    graphs: dict[str, WalkGraph]
    local: dict[str, list[int]]  # frame -> node ids (into ``nodes``) of that frame's walk graph's points
    node_frame: tuple[str, ...]
    stair_edges: dict[tuple[int, int], Flight]
    dist: NDArray[np.float64]
    predecessors: NDArray[np.int32]
    component: NDArray[np.int32]

    def route(self, i: int, j: int) -> tuple[list[tuple[float, float]], list[str], list[Flight]]:
        """The walk from point i to point j: its polyline, the frame of each of its points, the flights climbed."""
        chain = walk_nodes(self.predecessors, i, j)
        pts: list[tuple[float, float]] = []
        frs: list[str] = []
        used: list[Flight] = []
        for u, v in zip(chain, chain[1:]):
            fl = self.stair_edges.get((u, v)) or self.stair_edges.get((v, u))
            if fl is not None and self.node_frame[u] != self.node_frame[v]:
                used.append(fl)
                continue  # the flight: the line from the foot to the head (both ends are nodes)
            f = self.node_frame[u]
            loc = self.local[f]
            seg = self.graphs[f].path(loc.index(u), loc.index(v))
            for p in seg:
                if not pts or frs[-1] != f or math.dist(p, pts[-1]) > 1e-9:
                    pts.append(p)
                    frs.append(f)
        if not pts:
            pts, frs = [tuple(map(float, self.points[i]))], [self.frames[i]]  # type: ignore[list-item]
        return pts, frs, used


def storey_spaces(site: Site, frames: Sequence[str], stations: Sequence[Candidate]) -> dict[str, WalkSpace]:
    """The walkable area of each of ``frames`` (:func:`~planner.field.walking.walk_space`, with its stations)."""
    return {fr: walk_space(site, fr, [s.xy for s in stations if s.frame == fr]) for fr in frames}


def storey_walks(
    site: Site, spaces: dict[str, WalkSpace], points: Sequence[tuple[float, float]], point_frames: Sequence[str]
) -> StoreyWalk:
    """The walks between ``points`` (``point_frames[i]``: the frame point i stands in) through the frames of
    ``spaces`` (:func:`joined_frames`, :func:`storey_spaces`) and their stairs (see the module text)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    frames = list(spaces)
    fl = [f for s in site.stairs for f in flights(site, s, spaces)]
    at = [(fr, p) for f in fl for fr, p in ((f.lower, f.foot), (f.upper, f.head))]
    ends = {fr: list(dict.fromkeys(p for g, p in at if g == fr)) for fr in frames}
    graphs: dict[str, WalkGraph] = {}
    local: dict[str, list[int]] = {}
    node_frame: list[str] = list(point_frames)
    extra: dict[tuple[str, tuple[float, float]], int] = {}  # (frame, stair end) -> its node, after the points
    n = len(pts)
    for fr in frames:
        here = [k for k in range(len(pts)) if point_frames[k] == fr]
        extra |= {(fr, p): n + t for t, p in enumerate(ends[fr])}
        local[fr] = here + list(range(n, n + len(ends[fr])))
        node_frame += [fr] * len(ends[fr])
        n += len(ends[fr])
        graphs[fr] = walk_graph(spaces[fr], [tuple(pts[k]) for k in here] + ends[fr])  # type: ignore[arg-type]
    rows: list[int] = []
    cols: list[int] = []
    w: list[float] = []
    for fr in frames:  # each frame's walks between its points and stair ends
        ids, d = np.asarray(local[fr], dtype=int), graphs[fr].dist
        a, b = np.triu_indices(len(ids), k=1)
        ok = np.isfinite(d[a, b])
        rows += ids[a[ok]].tolist()
        cols += ids[b[ok]].tolist()
        w += np.maximum(d[a[ok], b[ok]], 1e-9).tolist()
    edges: dict[tuple[int, int], Flight] = {}
    for f in fl:
        u, v = extra[(f.lower, f.foot)], extra[(f.upper, f.head)]
        if (u, v) not in edges or f.length_m < edges[(u, v)].length_m:
            edges[(u, v)] = f
    rows += [u for u, _ in edges]
    cols += [v for _, v in edges]
    w += [max(f.length_m, 1e-9) for f in edges.values()]
    g = coo_matrix((w + w, (rows + cols, cols + rows)), shape=(n, n)).tocsr()
    d, pred = dijkstra(g, directed=False, indices=np.arange(len(pts)), return_predecessors=True)
    dist = d[:, : len(pts)]
    np.fill_diagonal(dist, 0.0)
    comp = connected_components(g, directed=False)[1][: len(pts)].astype(np.int32)
    frs, pred = tuple(point_frames), pred.astype(np.int32)
    return StoreyWalk(pts, frs, spaces, graphs, local, tuple(node_frame), edges, dist, pred, comp)


def climbs(flight: Flight, leg_frames: Sequence[str]) -> str:
    """ "up" or "down": which way a leg whose points stand in ``leg_frames`` takes ``flight``."""
    return "up" if leg_frames and leg_frames[0] == flight.lower else "down"


def stairs_line(fp: FieldPlan) -> str:
    """The summary's line for a sheet across storeys: the frames and every stair leg of the route (the stair, which
    way, the setup it walks to, its run and rise)."""
    said = []
    for k, f in fp.stair_legs:
        way = climbs(f, fp.leg_frames[k] if k < len(fp.leg_frames) else ())
        ends = f"{f.lower} to {f.upper}" if way == "up" else f"{f.upper} to {f.lower}"
        to = f"setup {k + 1}" if k < len(fp.order) else "the start"
        said.append(f"{f.stair} {way} ({ends}) on the walk to {to}: run {f.run_m:.1f} m + rise {f.rise_m:.1f} m")
    names, legs = ", ".join(s.frame for s in fp.spaces), "; ".join(said) or "none"
    return f"across storeys: {len(fp.spaces)} frames ({names}); stair legs {len(fp.stair_legs)}: {legs}"
