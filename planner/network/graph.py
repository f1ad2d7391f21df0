"""The station network (networkx): stations and control points, sight lines, triangulation, registration.

This is the earlier design, kept behind ``--ts-everywhere``: a total station on every scanner station.
The default network of a plan (:mod:`planner.network.traverse`) observes with the total station only
the legs of a control traverse; the control proposal and the sight test here serve both.

One network per frame (table zones each have their own frame and are never
linked to each other). Edges carry ``kinds`` (a set of ``sight``, ``delaunay``,
``registration``) and ``length_m``:

- ``sight``: two nodes intervisible (no wall or obstacle edge in between) and
  within the total station's range;
- ``delaunay``: an edge of the Delaunay triangulation of the frame's nodes,
  kept where intervisible (the dissertation's figs 4.9-4.10);
- ``registration``: two stations related by the overlap relation.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import networkx as nx
import numpy as np
from scipy.spatial import Delaunay

from planner.candidates.final_step import misplacement
from planner.site.candidate import Candidate
from planner.coverage.matrix import blockers_for
from planner.coverage.visibility import segments_touch
from planner.site.model import ControlPoint, Site

MIN_CONTROL_SPACING_M = 5.0
#: control spots are tried at these distances from each station (smaller ones for small rooms)
CONTROL_OFFSETS_M = (6.0, 4.0, 3.0, 2.0, 1.5)


#: blockers of the last sites asked (a site is immutable: its blockers are built once per frame)
_BLOCKERS: dict[tuple[int, str], tuple[Site, Any]] = {}


def _blockers(site: Site, frame: str) -> Any:
    hit = _BLOCKERS.get((id(site), frame))
    if hit is None or hit[0] is not site:
        if len(_BLOCKERS) > 32:
            _BLOCKERS.clear()
        hit = _BLOCKERS[(id(site), frame)] = (site, blockers_for(site, frame))
    return hit[1]


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
    paths_to_control: dict[str, list[str]]
    articulation_points: list[str]


def propose_control(site: Site, stations: Sequence[Candidate], graph: nx.Graph,
                    notes: list[str] | None = None) -> list[ControlPoint]:
    """Three control points per connected part of the station graph: spots 6, 4 or 3 m from its
    stations (8 directions) where a station of that zone could stand and which see that station; of these
    the three spanning the largest triangle, each pair more than 5 m apart. Marked as proposed.
    A spot closer than the site's stand-off (``min_standoff_m``) to a wall or obstacle is no spot:
    :func:`misplacement` refuses it, as it refuses a station there."""
    out: list[ControlPoint] = []
    by_id = {s.id: s for s in stations}
    for k, comp in enumerate(nx.connected_components(graph.subgraph([s.id for s in stations]))):
        spots = []
        for sid in sorted(comp):
            s = by_id[sid]
            for radius in CONTROL_OFFSETS_M:
                for a in range(8):
                    t = a * math.pi / 4
                    x, y = s.x + radius * math.cos(t), s.y + radius * math.sin(t)
                    if not misplacement(site, s, x, y) and intervisible(site, s.frame, s.xy, (x, y)):
                        spots.append((x, y))
        best, score = None, (False, 0.0)
        for p, q, r in itertools.combinations(spots[:120], 3):
            gap = min(math.dist(p, q), math.dist(q, r), math.dist(p, r))
            a2 = abs((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])) / 2
            if a2 < 1e-6:
                continue  # collinear
            # spread more than 5 m apart first (largest triangle); in a room too small for that,
            # the triple with the largest smallest spacing
            key = (gap > MIN_CONTROL_SPACING_M, a2 if gap > MIN_CONTROL_SPACING_M else gap)
            if key > score:
                best, score = (p, q, r), key
        if best is not None and not score[0] and notes is not None:
            notes.append(f"control points of {', '.join(sorted(comp))} are only {score[1]:.1f} m apart: "
                         "no three spots more than 5 m apart fit there")
        frame = by_id[sorted(comp)[0]].frame
        for j, (x, y) in enumerate(best or []):
            out.append(ControlPoint(f"CP{k + 1}.{j + 1}", x, y, proposed=True, frame=frame))
    return out


def station_network(site: Site, stations: Sequence[Candidate], control: Sequence[ControlPoint],
                    registration: Sequence[tuple[str, str]], ts_range_m: float) -> nx.Graph:
    """The network of the plan's stations and the control points (see the module docstring).

    A site's own control points live in the site frame; proposed ones in the
    frame of the stations they serve.
    """
    g = nx.Graph()
    for s in stations:
        g.add_node(s.id, kind="station", x=s.x, y=s.y, frame=s.frame, zone=s.zone)
    for c in control:
        g.add_node(c.name, kind="control", x=c.x, y=c.y, frame=c.frame, proposed=c.proposed)
    frames: dict[str, list[str]] = {}
    for n, d in g.nodes(data=True):
        frames.setdefault(d["frame"], []).append(n)
    for frame, nodes in frames.items():
        xy = {n: (g.nodes[n]["x"], g.nodes[n]["y"]) for n in nodes}
        for u, v in itertools.combinations(nodes, 2):
            d = math.dist(xy[u], xy[v])
            if d <= ts_range_m and intervisible(site, frame, xy[u], xy[v]):
                _link(g, u, v, "sight", d)
        if len(nodes) >= 3:
            pts = np.array([xy[n] for n in nodes])
            try:
                tri = Delaunay(pts)
            except Exception:  # collinear points: no triangulation
                tri = None
            for simplex in (tri.simplices if tri is not None else []):
                for i, j in itertools.combinations(simplex, 2):
                    u, v = nodes[i], nodes[j]
                    if intervisible(site, frame, xy[u], xy[v]):
                        _link(g, u, v, "delaunay", math.dist(xy[u], xy[v]))
    for u, v in registration:
        _link(g, u, v, "registration", math.dist((g.nodes[u]["x"], g.nodes[u]["y"]), (g.nodes[v]["x"], g.nodes[v]["y"])))
    return g


def _link(g: nx.Graph, u: str, v: str, kind: str, length: float) -> None:
    if g.has_edge(u, v):
        g.edges[u, v]["kinds"].add(kind)
    else:
        g.add_edge(u, v, kinds={kind}, length_m=length)


def diagnostics(g: nx.Graph) -> Diagnostics:
    """Connected parts, stations with no path to a control point, each station's path to its nearest
    control point (fewest edges), and articulation points (nodes whose loss splits the network)."""
    control = [n for n, d in g.nodes(data=True) if d["kind"] == "control"]
    paths, untied = {}, []
    for n, d in g.nodes(data=True):
        if d["kind"] != "station":
            continue
        best = None
        for c in control:
            if nx.has_path(g, n, c):
                p = nx.shortest_path(g, n, c)
                if best is None or len(p) < len(best):
                    best = p
        if best is None:
            untied.append(n)
        else:
            paths[n] = best
    return Diagnostics([sorted(c) for c in nx.connected_components(g)], sorted(untied), paths,
                       sorted(nx.articulation_points(g)))
