"""The station network (networkx) behind ``--ts-everywhere``: a total station on every scanner station. The default
network (:mod:`planner.network.traverse`) observes with the total station only the legs of
a control traverse; the control proposal and the sight test here serve both.

One network per frame. Edges carry ``length_m`` and ``kinds``, a set of: ``sight`` (two nodes intervisible and within
the total station's range), ``delaunay`` (an edge of the Delaunay triangulation of the frame's nodes, kept where
intervisible: the dissertation's figs 4.9-4.10) and ``registration`` (two related stations).
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import networkx as nx
import numpy as np
from numpy.typing import NDArray
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import shortest_path
from scipy.spatial import Delaunay

from planner.coverage.matrix import station_places
from planner.coverage.visibility import segments_touch
from planner.network.sight import blockers as _blockers
from planner.network.sight import sight_clear
from planner.site.candidate import Candidate
from planner.site.model import ControlPoint, ScanSide, Site

MIN_CONTROL_SPACING_M = 5.0
#: control spots are tried at these distances from each station (smaller ones for small rooms)
CONTROL_OFFSETS_M = (6.0, 4.0, 3.0, 2.0, 1.5)


def intervisible(site: Site, frame: str, p: tuple[float, float], q: tuple[float, float]) -> bool:
    """No wall or obstacle edge of the frame touches the segment p-q."""
    b = _blockers(site, frame)
    if len(b.a) == 0:
        return True
    n = len(b.a)
    hit = segments_touch(np.tile(p, (n, 1)), np.tile(q, (n, 1)), b.a, b.b)
    return not bool(hit.any())


@dataclass(frozen=True)
class Diagnostics:
    components: list[list[str]]
    untied_stations: list[str]
    articulation_points: list[str]
    paths_to_control: dict[str, list[str]]


def spots_around(site: Site, stations: Sequence[Candidate]) -> list[list[tuple[float, float]]]:
    """The control spots of each station: ``CONTROL_OFFSETS_M`` from it in 8 directions (nearest radius first), where a
    station of its zone-side could stand and which it sees. Whether one could stand there is what
    :func:`planner.candidates.final_step.misplacement` says, in one classification of all spots."""
    rings = [
        [
            (s.x + radius * math.cos(a * math.pi / 4), s.y + radius * math.sin(a * math.pi / 4))
            for radius in CONTROL_OFFSETS_M
            for a in range(8)
        ]
        for s in stations
    ]
    if not rings:
        return []
    per = len(rings[0])
    xy = np.array([p for ring in rings for p in ring], dtype=float).reshape(-1, 2)
    places = station_places(site, xy, [s.frame for s in stations for _ in range(per)])
    zone = {z.id: i for i, z in enumerate(site.zones)}
    ok = ~np.array([bool(r) for r in places.reason]).reshape(len(stations), per)
    for k, s in enumerate(stations):
        ok[k] &= places.inside[k * per : (k + 1) * per, zone[s.zone]] == (s.side is ScanSide.INSIDE)
    from_ = np.repeat(np.array([s.xy for s in stations], dtype=float).reshape(-1, 2), per, axis=0)
    frames = np.repeat(np.array([s.frame for s in stations], dtype=object), per)
    seen = np.zeros(len(xy), dtype=bool)
    for f in dict.fromkeys(frames.tolist()):
        m = frames == f
        seen[m] = sight_clear(site, f, from_[m], xy[m])
    ok &= seen.reshape(len(stations), per)
    return [[p for p, good in zip(ring, row) if good] for ring, row in zip(rings, ok)]


def widest_triangle(
    spots: Sequence[tuple[float, float]],
) -> tuple[tuple[tuple[float, float], ...] | None, tuple[bool, float]]:
    """Of all triples of ``spots`` (in the order of ``itertools.combinations``), the first one of largest area whose
    spots are all more than ``MIN_CONTROL_SPACING_M`` apart, else the first one of largest smallest spacing; collinear
    triples (twice the area below 1e-6) never. Returns it (None: no triple) and its key (spread apart, area or
    spacing)."""
    m = len(spots)
    if m < 3:
        return None, (False, 0.0)
    d = np.zeros((m, m))
    for a, b in itertools.combinations(range(m), 2):
        d[a, b] = d[b, a] = math.dist(spots[a], spots[b])
    i, j, k = _triples(m)
    xy = np.array(spots, dtype=float)
    gap = np.minimum(np.minimum(d[i, j], d[j, k]), d[i, k])
    p, q, r = xy[i], xy[j], xy[k]
    a2 = np.abs((q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1]) - (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0])) / 2
    valid = a2 >= 1e-6
    spread = valid & (gap > MIN_CONTROL_SPACING_M)
    if spread.any():
        t = int(np.argmax(np.where(spread, a2, -np.inf)))
        key = (True, float(a2[t]))
    elif (valid & (gap > 0.0)).any():
        t = int(np.argmax(np.where(valid, gap, -np.inf)))
        key = (False, float(gap[t]))
    else:
        return None, (False, 0.0)
    return (spots[i[t]], spots[j[t]], spots[k[t]]), key


@functools.lru_cache(maxsize=128)
def _triples(m: int) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
    t = np.array(list(itertools.combinations(range(m), 3)), dtype=np.int64).reshape(-1, 3)
    return t[:, 0], t[:, 1], t[:, 2]


def propose_control(
    site: Site, stations: Sequence[Candidate], graph: nx.Graph, notes: list[str] | None = None
) -> list[ControlPoint]:
    """Three control points per connected part of the station graph: spots 6, 4 or 3 m from its stations (8 directions)
    where a station of that zone could stand and which see that station; of these the three spanning the largest
    triangle, each pair more than 5 m apart. Marked as proposed. A spot closer than the site's stand-off
    (``min_standoff_m``) to a wall or obstacle is no spot: :func:`planner.candidates.final_step.misplacement` refuses
    it, as it refuses a station there."""
    out: list[ControlPoint] = []
    by_id = {s.id: s for s in stations}
    around = dict(zip(by_id, spots_around(site, list(by_id.values()))))
    for k, comp in enumerate(nx.connected_components(graph.subgraph([s.id for s in stations]))):
        spots = [p for sid in sorted(comp) for p in around[sid]]
        best, score = widest_triangle(spots[:120])
        if best is not None and not score[0] and notes is not None:
            notes.append(
                f"control points of {', '.join(sorted(comp))} are only {score[1]:.1f} m apart: "
                "no three spots more than 5 m apart fit there"
            )
        frame = by_id[sorted(comp)[0]].frame
        for j, (x, y) in enumerate(best or []):
            out.append(ControlPoint(f"CP{k + 1}.{j + 1}", x, y, proposed=True, frame=frame))
    return out


def station_network(
    site: Site,
    stations: Sequence[Candidate],
    control: Sequence[ControlPoint],
    registration: Sequence[tuple[str, str]],
    ts_range_m: float,
) -> nx.Graph:
    """The network of the plan's stations and the control points (see the module docstring).

    A site's own control points live in the site frame; proposed ones in the frame of the stations they serve.
    """
    g = point_graph(stations, control)
    frames: dict[str, list[str]] = {}
    for n, d in g.nodes(data=True):
        frames.setdefault(d["frame"], []).append(n)
    for frame, nodes in frames.items():
        xy = {n: (g.nodes[n]["x"], g.nodes[n]["y"]) for n in nodes}
        for u, v in itertools.combinations(nodes, 2):
            d = math.dist(xy[u], xy[v])
            if d <= ts_range_m and intervisible(site, frame, xy[u], xy[v]):
                add_link(g, u, v, "sight", d)
        if len(nodes) >= 3:
            pts = np.array([xy[n] for n in nodes])
            try:
                tri = Delaunay(pts)
            except Exception:  # collinear points: no triangulation
                tri = None
            for simplex in tri.simplices if tri is not None else []:
                for i, j in itertools.combinations(simplex, 2):
                    u, v = nodes[i], nodes[j]
                    if intervisible(site, frame, xy[u], xy[v]):
                        add_link(g, u, v, "delaunay", math.dist(xy[u], xy[v]))
    for u, v in registration:
        add_link(g, u, v, "registration")
    return g


def point_graph(stations: Sequence[Candidate], control: Sequence[ControlPoint]) -> nx.Graph:
    """A graph of the stations (``kind`` station) and control points (``kind`` control), no edges yet."""
    g = nx.Graph()
    for s in stations:
        g.add_node(s.id, kind="station", x=s.x, y=s.y, frame=s.frame, zone=s.zone)
    for c in control:
        g.add_node(c.name, kind="control", x=c.x, y=c.y, frame=c.frame, proposed=c.proposed)
    return g


def add_link(g: nx.Graph, u: str, v: str, kind: str, length_m: float | None = None) -> None:
    """Add ``kind`` to the edge u-v (made, of ``length_m``, or the nodes' distance, where there is none)."""
    if g.has_edge(u, v):
        g.edges[u, v]["kinds"].add(kind)
    else:
        if length_m is None:
            length_m = math.dist((g.nodes[u]["x"], g.nodes[u]["y"]), (g.nodes[v]["x"], g.nodes[v]["y"]))
        g.add_edge(u, v, kinds={kind}, length_m=length_m)


def diagnostics(g: nx.Graph) -> Diagnostics:
    """Connected parts, stations with no path to a control point, each station's path to its nearest control point
    (fewest edges; of equally near ones the first control point of the graph, and the path ``nx.shortest_path`` gives),
    and articulation points (nodes whose loss splits the network)."""
    order = list(g)
    index = {n: k for k, n in enumerate(order)}
    control = np.array([index[n] for n, d in g.nodes(data=True) if d["kind"] == "control"], dtype=np.int64)
    stations = [n for n, d in g.nodes(data=True) if d["kind"] == "station"]
    paths, untied = {}, []
    if stations and len(control):
        edges = np.array([(index[u], index[v]) for u, v in g.edges()], dtype=np.int64).reshape(-1, 2)
        adj = csr_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(len(order), len(order)))
        hops = shortest_path(adj, directed=False, unweighted=True, indices=[index[n] for n in stations])
        for n, row in zip(stations, hops.reshape(len(stations), -1)):
            to_control = row[control]
            if not np.isfinite(to_control).any():
                untied.append(n)
                continue
            paths[n] = nx.shortest_path(g, n, order[control[int(np.argmin(to_control))]])
    else:
        untied = list(stations)
    return Diagnostics(
        [sorted(c) for c in nx.connected_components(g)], sorted(untied), sorted(nx.articulation_points(g)), paths
    )
