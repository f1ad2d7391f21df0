"""The array versions of the network's building steps give what the pairwise loops they replaced gave.

Each reference below is the loop as it stood before (issue 34, part 5): one sight line, one spot, one
pair or one shortest path at a time.
"""

from __future__ import annotations

import itertools
import math
from types import SimpleNamespace

import networkx as nx
import numpy as np
import pytest
import shapely

from planner.candidates.final_step import misplacement
from planner.io import load_site
from planner.network import graph, proposal, sight
from planner.network.graph import CONTROL_OFFSETS_M, diagnostics, intervisible, spots_around, widest_triangle
from planner.site.model import ControlPoint, ScanSide
from tests.conftest import INSTANCES


@pytest.fixture(scope="module")
def doors():
    return load_site(str(INSTANCES / "baalbek_site_doors.json"))


def test_sight_lines_equal_one_at_a_time(doors):
    b = sight.blockers(doors, "site")
    rng = np.random.default_rng(0)
    pts = rng.uniform(b.a.min(0) - 3, b.a.max(0) + 3, (150, 2))
    k = rng.integers(len(b.a), size=80)  # points on walls' lines, beyond and on the walls, and corners
    t = rng.choice([-1.5, -0.2, 0.0, 0.5, 1.0, 2.0], size=80)
    pts = np.vstack([pts, b.a[k] + t[:, None] * (b.b[k] - b.a[k]), b.a[:30]])
    i, j = rng.integers(len(pts), size=(2, 3000))
    fast = sight.sight_clear(doors, "site", pts[i], pts[j])
    slow = [intervisible(doors, "site", tuple(pts[a]), tuple(pts[c])) for a, c in zip(i, j)]
    assert fast.tolist() == slow and 0 < fast.sum() < len(fast)


def test_a_sight_line_along_a_wall_line_far_from_the_wall(monkeypatch):
    # the wall (0, 0)-(1, 0); a segment from (2, 0) on its line, nearly along it: the side test counts a
    # touch though the two lie 1 m apart, and the array version must say the same
    wall = SimpleNamespace(a=np.array([[0.0, 0.0], [50.0, 50.0]]), b=np.array([[1.0, 0.0], [51.0, 50.0]]))
    monkeypatch.setattr(sight, "blockers", lambda site, frame: wall)
    monkeypatch.setattr(graph, "_blockers", lambda site, frame: wall)
    p = np.array([[2.0, 0.0], [2.0, 0.0], [2.0, 5.0], [-3.0, -1.0]])
    q = np.array([[100.0, 1.5e-7 * 98 / 2], [100.0, 1.0], [100.0, 5.0], [3.0, 1.0]])
    slow = [intervisible(None, "site", tuple(a), tuple(c)) for a, c in zip(p, q)]  # type: ignore[arg-type]
    assert sight.sight_clear(None, "site", p, q).tolist() == slow  # type: ignore[arg-type]
    assert slow == [False, True, True, False]


def _old_legs(site, nodes, ts_range_m):
    def space(c):
        pt = shapely.Point(c.x, c.y)
        room = next(
            (
                z.id
                for z in site.zones
                if z.frame == c.frame and z.scan_side is not ScanSide.OUTSIDE and z.polygon.contains(pt)
            ),
            None,
        )
        return f"in:{room}" if room is not None else f"out:{c.frame}"

    def same(a, b):
        return a.name.startswith("TP.") or b.name.startswith("TP.") or space(a) == space(b)

    return [
        (a.name, b.name)
        for a, b in itertools.combinations(nodes, 2)
        if a.frame == b.frame
        and same(a, b)
        and math.dist((a.x, a.y), (b.x, b.y)) <= ts_range_m
        and intervisible(site, a.frame, (a.x, a.y), (b.x, b.y))
    ]


def _old_needed(ring, nodes, legs):
    names = {r.name for r in ring}
    pos = {n.name: (n.x, n.y) for n in nodes}
    g = nx.Graph()
    g.add_weighted_edges_from((u, v, math.dist(pos[u], pos[v])) for u, v in legs)
    real = [n.name for n in nodes if n.name not in names and n.name in g]
    kept = set()
    for src in real:
        paths = nx.single_source_dijkstra_path(g, src)
        for dst in real:
            if dst != src and dst in paths:
                kept.update(n for n in paths[dst] if n in names)
    return kept


def test_legs_rooms_and_ring_points_equal_the_pairwise_loops(doors):
    rng = np.random.default_rng(1)
    b = sight.blockers(doors, "site")
    lo, hi = b.a.min(0), b.a.max(0)
    nodes = [
        ControlPoint(f"{'TP.' if k % 9 == 0 else 'RP.' if k % 4 == 0 else 'CP'}{k}", *map(float, rng.uniform(lo, hi)))
        for k in range(120)
    ]
    legs = proposal.legs(doors, nodes, 40.0)
    assert legs == _old_legs(doors, nodes, 40.0) and legs
    ring = [n for n in nodes if n.name.startswith("RP.")]
    assert proposal.needed(ring, nodes, legs) == _old_needed(ring, nodes, legs)


@pytest.mark.parametrize("seed", range(4))
def test_ring_points_on_a_grid_of_equal_legs(seed):
    # a square grid: many shortest paths of equal length, where networkx's order of settling decides
    rng = np.random.default_rng(seed)
    nodes = [
        ControlPoint(f"{'RP.' if rng.random() < 0.5 else 'CP'}{x}.{y}", float(x), float(y))
        for x in range(7)
        for y in range(7)
    ]
    near = [
        (a.name, b.name)
        for a, b in itertools.combinations(nodes, 2)
        if math.dist((a.x, a.y), (b.x, b.y)) <= 1.5 and rng.random() < 0.9
    ]
    ring = [n for n in nodes if n.name.startswith("RP.")]
    assert proposal.needed(ring, nodes, near) == _old_needed(ring, nodes, near)


def _old_spots(site, s):
    out = []
    for radius in CONTROL_OFFSETS_M:
        for a in range(8):
            x, y = s.x + radius * math.cos(a * math.pi / 4), s.y + radius * math.sin(a * math.pi / 4)
            if not misplacement(site, s, x, y) and intervisible(site, s.frame, s.xy, (x, y)):
                out.append((x, y))
    return out


def _old_triangle(spots):
    best, score = None, (False, 0.0)
    for p, q, r in itertools.combinations(spots, 3):
        gap = min(math.dist(p, q), math.dist(q, r), math.dist(p, r))
        a2 = abs((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])) / 2
        if a2 < 1e-6:
            continue
        key = (gap > 5.0, a2 if gap > 5.0 else gap)
        if key > score:
            best, score = (p, q, r), key
    return best, score


def test_control_spots_and_triangles_equal_the_loops(doors):
    from planner.site.candidate import Candidate, CandidateKind

    rng = np.random.default_rng(2)
    zones = [z for z in doors.zones if z.scan_side is ScanSide.INSIDE][:6]
    stations = []
    for k, z in enumerate(zones):
        c = z.polygon.representative_point()
        stations.append(Candidate(f"S{k}", z.id, ScanSide.INSIDE, z.frame, c.x, c.y, CandidateKind.GRID))
    got = spots_around(doors, stations)
    assert got == [_old_spots(doors, s) for s in stations] and any(got)
    for spots in [
        *got,
        [(float(x), float(y)) for x in range(4) for y in range(4)],
        [tuple(map(float, p)) for p in rng.uniform(0, 20, (30, 2))],
        [(0.0, 0.0), (1.0, 1.0), (2.0, 2.0)],
    ]:
        assert widest_triangle(spots) == _old_triangle(spots)
    mine = [ControlPoint(f"C{k}", *map(float, rng.uniform(0, 60, 2))) for k in range(40)]

    def old_best(st):
        best, score = None, -1
        for x, y in _old_spots(doors, st):
            k = sum(c.frame == st.frame and intervisible(doors, c.frame, (x, y), (c.x, c.y)) for c in mine)
            if k > score:
                best, score = (x, y), k
        return best

    assert [proposal.best_spot(doors, s, mine) for s in stations] == [old_best(s) for s in stations]


def test_diagnostics_equal_the_pairwise_search():
    rng = np.random.default_rng(3)
    g = nx.gnp_random_graph(60, 0.05, seed=4)
    g = nx.relabel_nodes(g, {k: f"{'C' if rng.random() < 0.2 else 'S'}{k}" for k in g})
    for n in g:
        g.nodes[n]["kind"] = "control" if n.startswith("C") else "station"
    got = diagnostics(g)
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
    assert got.paths_to_control == paths and got.untied_stations == sorted(untied) and untied and paths
