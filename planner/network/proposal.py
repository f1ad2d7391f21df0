"""The proposed control traverse on a large site, fast: rooms of points, legs, needed ring points, spots, with the
work done in arrays (the same legs in the same order as pairwise loops): the room of each point once, every pair's
checks at once, the sight lines by :func:`planner.network.sight.sight_clear`, the shortest leg paths by scipy's Dijkstra.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import networkx as nx
import numpy as np
import shapely
from numpy.typing import NDArray
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from planner.network.graph import spots_around
from planner.network.sight import sight_clear
from planner.site.candidate import Candidate
from planner.site.model import ControlPoint, ScanSide, Site


def spaces(site: Site, points: Sequence[ControlPoint]) -> list[str]:
    """The room each point stands in (``in:<zone>``: the first zone of its frame scanned inside that holds it), or the
    ground outside the rooms of its frame (``out:<frame>``)."""
    out: list[str | None] = [None] * len(points)
    if not points:
        return []
    xy = np.array([(c.x, c.y) for c in points], dtype=float)
    frames = np.array([c.frame for c in points], dtype=object)
    for z in site.zones:
        if z.scan_side is ScanSide.OUTSIDE:
            continue
        todo = np.flatnonzero((frames == z.frame) & np.array([o is None for o in out]))
        if todo.size:
            inside = shapely.contains(z.polygon, shapely.points(xy[todo]))
            for k in todo[inside]:
                out[k] = f"in:{z.id}"
    return [o if o is not None else f"out:{c.frame}" for o, c in zip(out, points)]


def _within(xy: NDArray[np.float64], i: int, j: NDArray[np.int64], limit: float) -> NDArray[np.bool_]:
    """math.dist(xy[i], xy[j]) <= limit for each j (numpy's distance, math.dist where it is a near call)."""
    d = np.hypot(xy[j, 0] - xy[i, 0], xy[j, 1] - xy[i, 1])
    ok = d <= limit
    for k in np.flatnonzero(np.abs(d - limit) <= 1e-9 * max(limit, 1.0)):
        ok[k] = math.dist(tuple(xy[i]), tuple(xy[j[k]])) <= limit
    return ok


def legs(site: Site, nodes: Sequence[ControlPoint], ts_range_m: float) -> list[tuple[str, str]]:
    """Every pair of ``nodes`` (in the order of ``itertools.combinations``) of one frame and one room (a door's ``TP.``
    point joins both), within ``ts_range_m`` and intervisible."""
    n = len(nodes)
    xy = np.array([(c.x, c.y) for c in nodes], dtype=float).reshape(-1, 2)
    frame = np.array([c.frame for c in nodes], dtype=object)
    room = np.array(spaces(site, nodes), dtype=object)
    door = np.array([c.name.startswith("TP.") for c in nodes], dtype=bool)
    first, second = [], []
    for i in range(n - 1):
        j = np.arange(i + 1, n)
        ok = (frame[j] == frame[i]) & (door[i] | door[j] | (room[j] == room[i]))
        j = j[ok]
        j = j[_within(xy, i, j, ts_range_m)]
        first.append(np.full(len(j), i))
        second.append(j)
    a = np.concatenate(first) if first else np.zeros(0, dtype=np.int64)
    b = np.concatenate(second) if second else np.zeros(0, dtype=np.int64)
    clear = np.zeros(len(a), dtype=bool)
    for f in dict.fromkeys(frame[a].tolist()):
        m = frame[a] == f
        clear[m] = sight_clear(site, f, xy[a[m]], xy[b[m]])
    return [(nodes[i].name, nodes[j].name) for i, j in zip(a[clear].tolist(), b[clear].tolist())]


def needed(
    ring: Sequence[ControlPoint], nodes: Sequence[ControlPoint], leg_list: Sequence[tuple[str, str]]
) -> set[str]:
    """The ring points on the shortest leg paths between the other points, as networkx's ``single_source_dijkstra_path``
    from each of them finds the paths (its choice among paths of equal length: a node's predecessor is the one settled
    first that reaches it at its distance)."""
    names = {r.name for r in ring}
    pos = {n.name: (n.x, n.y) for n in nodes}
    g = nx.Graph()
    g.add_weighted_edges_from((u, v, math.dist(pos[u], pos[v])) for u, v in leg_list)
    real = [n.name for n in nodes if n.name not in names and n.name in g]
    order = list(g)
    index = {v: k for k, v in enumerate(order)}
    eu = np.array([index[u] for u, v in g.edges()] + [index[v] for u, v in g.edges()], dtype=np.int64)
    ev = np.array([index[v] for u, v in g.edges()] + [index[u] for u, v in g.edges()], dtype=np.int64)
    ew = np.array([w for _, _, w in g.edges(data="weight")] * 2, dtype=float)
    is_ring = np.array([v in names for v in order], dtype=bool)
    kept: set[str] = set()
    if not real or not len(ew):
        return kept
    if not np.all(ew > 0):  # a leg of length 0 (coincident points): networkx decides
        return _needed_networkx(g, real, names)
    dist = dijkstra(csr_matrix((ew, (eu, ev)), shape=(len(order), len(order))), indices=[index[r] for r in real])
    for row, src in zip(dist, real):
        pred = _predecessors(row, eu, ev, ew, index[src])
        if pred is None:  # two predecessors settled at the same distance: networkx decides
            kept |= _needed_networkx(g, [src], names, real)
            continue
        on_path = np.zeros(len(order), dtype=bool)
        on_path[[index[r] for r in real if r != src and np.isfinite(row[index[r]])]] = True
        for v in np.argsort(-row, kind="stable"):
            if on_path[v] and pred[v] >= 0:
                on_path[pred[v]] = True
        kept.update(order[v] for v in np.flatnonzero(on_path & is_ring))
    return kept


def _predecessors(
    d: NDArray[np.float64], eu: NDArray[np.int64], ev: NDArray[np.int64], ew: NDArray[np.float64], src: int
) -> NDArray[np.int64] | None:
    """Each node's predecessor on the Dijkstra tree from ``src`` (-1: the source, or not reached); None where two
    predecessors reach a node at equal distances (then the order they were settled in decides)."""
    reach = np.isfinite(d[eu]) & (d[eu] + ew == d[ev]) & (ev != src)
    u, v = eu[reach], ev[reach]
    o = np.lexsort((d[u], v))
    u, v = u[o], v[o]
    first = np.ones(len(v), dtype=bool)
    first[1:] = v[1:] != v[:-1]
    second = np.zeros(len(v), dtype=bool)
    second[1:] = ~first[1:] & first[:-1]
    if np.any(second & (d[u] == np.roll(d[u], 1))):  # the nearest two reach it at one distance
        return None
    pred = np.full(len(d), -1, dtype=np.int64)
    pred[v[first]] = u[first]
    return pred


def _needed_networkx(
    g: nx.Graph, sources: Sequence[str], names: set[str], real: Sequence[str] | None = None
) -> set[str]:
    kept: set[str] = set()
    targets = list(real if real is not None else sources)
    for src in sources:
        paths = nx.single_source_dijkstra_path(g, src)
        for dst in targets:
            if dst != src and dst in paths:
                kept.update(n for n in paths[dst] if n in names)
    return kept


def best_spot(site: Site, st: Candidate, points: Sequence[ControlPoint]) -> tuple[float, float] | None:
    """A control spot 1.5-6 m from station ``st`` that it sees, seeing as many of ``points`` (control points, doors) as
    it can (the first such, nearest radius first); None when no spot fits."""
    spots = spots_around(site, [st])[0]
    if not spots:
        return None
    mine = np.array([(c.x, c.y) for c in points if c.frame == st.frame], dtype=float).reshape(-1, 2)
    if not len(mine):
        return spots[0]
    p = np.repeat(np.array(spots), len(mine), axis=0)
    seen = sight_clear(site, st.frame, p, np.tile(mine, (len(spots), 1))).reshape(len(spots), len(mine)).sum(axis=1)
    return spots[int(np.argmax(seen))]
