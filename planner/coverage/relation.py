"""The registration relation of a plan's stations (:func:`station_relation`): which pairs share enough wall,
within their registration groups, or link through an opening. The network check, the scanner survey and the
field sheet all read it from here."""

from __future__ import annotations

from collections.abc import Sequence

import networkx as nx
import numpy as np

from planner.coverage.links import default_registration, registration_groups
from planner.coverage.matrix import CoverageProblem
from planner.coverage.overlap import overlap_graph, piece_lengths, rule_of
from planner.site.candidate import Candidate
from planner.site.model import Site


def station_relation(
    site: Site, stations: Sequence[Candidate], problem: CoverageProblem, mode: str | None = None
) -> nx.Graph:
    """The overlap relation of ``stations`` (node = index into them) at the site's overlap share, within each
    registration group of ``mode`` (default :func:`planner.coverage.links.default_registration`); each edge
    has ``shared_m`` (wall both see) and ``fraction`` (of the smaller station's covered wall).

    ``problem``: the stations' coverage, rows in the order of ``stations``.
    """
    lengths = piece_lengths(problem.targets.s0_m, problem.targets.s1_m)
    covered = np.asarray(problem.by_candidate.astype(np.float64) @ lengths).ravel()
    reach = problem.limits.effective_range_m
    labels, links = registration_groups(site, stations, mode or default_registration(site).mode, reach)
    xy = np.array([s.xy for s in stations], dtype=float).reshape(-1, 2)
    g = nx.Graph()
    g.add_nodes_from(range(len(stations)))
    groups: dict[object, list[int]] = {}
    for i, label in enumerate(labels):
        groups.setdefault(label, []).append(i)
    rule = rule_of(site.parameters.overlap)
    for nodes in groups.values():
        sub = overlap_graph(problem.by_candidate, lengths, nodes, rule, xy, links)
        for u, v, data in sub.edges(data=True):
            small = min(covered[u], covered[v])
            g.add_edge(u, v, shared_m=data["shared_m"], fraction=data["shared_m"] / small if small > 0 else 0.0)
    return g
