"""The registration of a plan's stations, checked afresh (:func:`registration_check`), and where they stand
(:func:`placed_stations`: the tripod discs, and stations recentred on them)."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import networkx as nx
import numpy as np

from planner.coverage.links import default_registration, registration_groups
from planner.coverage.matrix import CoverageProblem
from planner.coverage.overlap import OverlapRule, overlap_graph, piece_lengths
from planner.plan.options import PlanOptions
from planner.plan.tripod import TripodDisc, tripod_discs
from planner.site.candidate import Candidate
from planner.site.model import Site


def placed_stations(
    site: Site,
    problem: CoverageProblem,
    selected: tuple[int, ...],
    options: PlanOptions,
    partners: dict[int, list[int]],
) -> tuple[list[Candidate], tuple[TripodDisc, ...]]:
    """The chosen stations and, with ``options.tripod`` or ``options.recentre``, their tripod discs (relied
    pieces only, checked on centre and rim); ``recentre`` moves each station to its disc's centre."""
    stations = [problem.candidates[i] for i in selected]
    if not (options.tripod or options.recentre):
        return stations, ()
    tripods = tuple(tripod_discs(site, problem, selected, problem.limits, partners, options.recentre))
    if options.recentre:
        stations = [replace(s, x=d.centre[0], y=d.centre[1]) for s, d in zip(stations, tripods)]
    return stations, tripods


def registration_check(
    problem: CoverageProblem,
    selected: tuple[int, ...],
    rule: OverlapRule,
    site: Site | None = None,
    mode: str | None = "zone",
    reach_m: float = math.inf,
) -> tuple[dict[str, int], dict[int, list[int]]]:
    """Components of each registration group's chosen stations under the overlap relation, computed afresh
    with networkx (independent of any solver), and each station's registration partners.

    Groups: each zone-side (``mode="zone"``), or each accessible area of ``site`` with links through
    openings (``"site"``; ``None``: :func:`default_registration`)."""
    lengths = piece_lengths(problem.targets.s0_m, problem.targets.s1_m)
    chosen = [problem.candidates[i] for i in selected]
    xy = np.array([c.xy for c in chosen], dtype=float).reshape(-1, 2)
    mode = mode or (default_registration(site).mode if site is not None else "zone")
    labels, links = (
        registration_groups(site, chosen, mode, reach_m)
        if site is not None
        else (tuple((c.zone, c.side.value) for c in chosen), None)
    )
    groups: dict[Any, list[int]] = {}  # labels: (zone, side) pairs or ("area", k)
    for k, label in enumerate(labels):
        groups.setdefault(label, []).append(k)
    out, partners = {}, {}
    sub = problem.by_candidate[list(selected)] if selected else problem.by_candidate[:0]
    for label, nodes in groups.items():
        g = overlap_graph(sub, lengths, nodes, rule, xy, links)
        names = sorted({f"{chosen[k].zone}/{chosen[k].side.value}" for k in nodes})
        key = (
            "/".join(label)
            if mode == "zone"
            else f"area {label[1]} ({', '.join(names[:4])}{', ...' if len(names) > 4 else ''})"
        )
        out[key] = nx.number_connected_components(g)
        partners.update({selected[n]: sorted(selected[m] for m in g.neighbors(n)) for n in nodes})
    return out, partners
