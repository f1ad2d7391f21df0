"""The network of a plan as a scanner survey: registration links, ties to control, chain accuracy.

Links: the overlap relation of the plan's stations, within each registration group (zone-side, or accessible area of the
site with links through openings; see :mod:`planner.coverage.links`). Ties: a station within ``TIE_RANGE_M`` of control
points it sees scans targets on them. Without control points in the instance, each registration part gets control by the
field's rules: at least 3, one per ``CHAIN_PER_CONTROL_M`` of chain (the part's minimum spanning tree of links), placed
one at a time where the chain's error is worst; the station nearest each spot scans ``DEFAULT_TARGETS`` targets there. A
proposed point's own error (``DEFAULT_CONTROL_SIGMA_M``) is part of every tie to it (formula 3).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import networkx as nx
import numpy as np

from planner.coverage.matrix import CoverageProblem
from planner.coverage.relation import Registration
from planner.coverage.sight import Sight, as_sight
from planner.network.chain import (
    DEFAULT_CONTROL_SIGMA_M,
    TIE_RANGE_M,
    ChainReport,
    chain_accuracy,
    control_count,
    place_ties,
    target_centre_sigma_m,
    tie_sigma_m,
)
from planner.network.graph import intervisible
from planner.site.candidate import Candidate
from planner.site.model import ControlPoint, Site

#: scan resolution 3 mm at 10 m (seed 003's example) as an angle in degrees
DEFAULT_RESOLUTION_DEG = math.degrees(0.003 / 10.0)
#: targets a tied station scans, and their range (seed 003: 5-7 targets within 10-20 m of a control point)
DEFAULT_TARGETS = 4
DEFAULT_TARGET_RANGE_M = 15.0
#: the total station coordinating the targets: 5", 2 mm (seed 003's example)
TS_ANGLE_ARCSEC, TS_DISTANCE_M = 5.0, 0.002


@dataclass(frozen=True)
class SurveyNetwork:
    """Registration parts, the ties, and the chain accuracy of a plan."""

    parts: tuple[tuple[str, ...], ...]
    links: tuple[tuple[str, str], ...]
    ties: dict[str, float]
    proposed: bool
    chain: ChainReport
    frames: tuple[str, ...]

    def to_dict(self) -> dict[str, object]:
        c = self.chain
        return {
            "parts": [list(p) for p in self.parts],
            "links": [list(k) for k in self.links],
            "ties_sigma_m": dict(self.ties),
            "proposed_control": self.proposed,
            "frames": list(self.frames),
            "station_sigma_m": dict(c.sigma_m),
            "links_from_control": dict(c.links_from_control),
            "weakest_chain": list(c.weakest_chain),
            "best_extra_tie": c.best_tie,
            "worst_after_extra_tie_m": c.worst_after_tie_m,
            "untied": list(c.untied),
        }

    def lines(self) -> list[str]:
        return [
            f"survey network: {len(self.parts)} registration part(s), {len(self.links)} registration links, "
            f"{len(self.ties)} station(s) tied to {'proposed ' if self.proposed else ''}control; "
            f"datum frame(s): {', '.join(self.frames)}"
        ] + self.chain.lines()


def can_tie(site: Site, frame: str, xy: tuple[float, float], c: ControlPoint) -> bool:
    """A station at ``xy`` in ``frame`` scans targets on ``c``: same frame, within ``TIE_RANGE_M``, in sight."""
    near = c.frame == frame and math.dist(xy, (c.x, c.y)) <= TIE_RANGE_M
    return near and intervisible(site, c.frame, xy, (c.x, c.y))


def _tie(control_sigma_m: float, ranges: Sequence[float]) -> float:
    centre = [target_centre_sigma_m(control_sigma_m, r, TS_DISTANCE_M, TS_ANGLE_ARCSEC) for r in ranges]
    return tie_sigma_m(list(ranges), DEFAULT_RESOLUTION_DEG, float(np.sqrt(np.mean(np.square(centre)))))


def registration_links(
    site: Site | Sight,
    stations: Sequence[Candidate],
    registration: Registration | str | None = None,
    problem: CoverageProblem | None = None,
) -> list[tuple[str, str]]:
    """Pairs of the plan's stations that can be registered (see the module text): the relation of the plan's
    ``registration`` (:meth:`planner.coverage.relation.Registration.relation`; a mode, or None: the site's default,
    at the site's overlap share); ``problem``: their coverage, when already built (rows in the order of
    ``stations``); ``site``: the plan's sight, or a site seen under its own parameters."""
    sight = as_sight(site)
    if problem is None:
        problem = sight.of_stations(stations)
    if not isinstance(registration, Registration):
        registration = Registration.of(sight, registration)
    g = registration.relation(stations, problem)
    return [(stations[u].id, stations[v].id) for u, v in g.edges()]


def survey_network(
    site: Site | Sight,
    stations: Sequence[Candidate],
    registration: Registration | str | None = None,
    links: Sequence[tuple[str, str]] | None = None,
) -> SurveyNetwork:
    """Links (``links``: already found by :func:`registration_links`, else found there under ``registration``), ties
    (given or proposed control) and the chain accuracy of a plan's stations; ``site``: the plan's sight, or a site
    alone."""
    if links is None:
        links = registration_links(site, stations, registration)
    site = site.site if isinstance(site, Sight) else site
    xy = {s.id: s.xy for s in stations}
    links = list(links)
    g = nx.Graph()
    g.add_nodes_from(xy)
    g.add_edges_from(links)
    parts = tuple(tuple(sorted(c)) for c in nx.connected_components(g))
    ties: dict[str, float] = {}
    proposed = not site.control_points
    if proposed:
        tie = _tie(DEFAULT_CONTROL_SIGMA_M, [DEFAULT_TARGET_RANGE_M] * DEFAULT_TARGETS)
        for part in parts:
            sub = [(u, v) for u, v in links if u in part]
            tree = nx.minimum_spanning_tree(
                nx.Graph([(u, v, {"w": math.dist(xy[u], xy[v])}) for u, v in sub]), weight="w"
            )
            length = sum(d["w"] for _, _, d in tree.edges(data=True))
            ties.update(place_ties({s: xy[s] for s in part}, sub, tie, control_count(length)))
    else:
        by_id = {s.id: s for s in stations}
        for sid, p in xy.items():
            seen = [c for c in site.control_points if can_tie(site, by_id[sid].frame, p, c)]
            if seen:
                ranges = [max(math.dist(p, (c.x, c.y)), 1.0) for c in seen]
                ties[sid] = _tie(max(max(c.sigma_x_m, c.sigma_y_m) for c in seen), ranges)
    chain = chain_accuracy(xy, links, ties)
    frames = tuple(dict.fromkeys(s.frame for s in stations))
    return SurveyNetwork(parts, tuple(links), ties, proposed, chain, frames)
