"""Candidates aligned through openings: positions from which a plain cover's stations, each kept where it still sees
what only it sees, may see each other through a door.

Where registration joins rooms and the ground outside through their openings (``site`` registration), a link across an
opening needs two stations whose segment passes through it (:func:`planner.coverage.links.opening_links`): a sight line
through a 3-m door between two rooms 50 m deep is a thin wedge, and a grid of the pool seldom holds both of its ends.
A room that one station covers must hold that station where it sees the whole room and, from there, see its neighbours
through several doors at once.

:func:`aligned_candidates` takes a plain cover (no registration) and, for each of its stations, the region where a
station still covers the pieces that only it covers (the intersection of those pieces' coverage regions R_t: moving
there keeps the cover). For each opening between two spaces it keeps the part of each such region from which some
position of a region across the opening is seen through it (:func:`planner.coverage.openings.seen_through`), and
samples it on a grid: the opening's width over :data:`PER_WIDTH` apart, coarser where that would pass
:data:`PER_REGION` points. A plan chosen among these candidates and the cover's stations covers every piece wherever it
takes one candidate per station's region; the registration it may reach is the solver's to find.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.candidates.closed_form import side_candidate
from planner.candidates.from_regions import largest_part_pole
from planner.candidates.pool import dedupe
from planner.coverage.matrix import CoverageProblem
from planner.coverage.openings import opening_spaces, seen_through, space_of
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import Site

#: grid points per opening width (a 3-m door: 1 m apart): a room's one station must line up with several doors at once
PER_WIDTH = 3
#: grid points per region at most (the grid is made coarser to stay under it)
PER_REGION = 250
#: regions smaller than this (m^2) are sampled at their pole only
MIN_AREA_M2 = 1e-6
#: the kind of an aligned candidate (a point of the coverage regions)
KIND = CandidateKind.REGION


def movement_regions(
    problem: CoverageProblem, selected: Sequence[int], regions: Callable[[list[int]], dict[int, Any]]
) -> list[shapely.Geometry | None]:
    """For each station of the cover ``selected`` (rows of ``problem``): where a station of its zone-side still covers
    every piece that only it covers (None where it covers none alone). ``regions``: the coverage regions R_t of the
    pieces asked for (drawn where missing)."""
    rows = problem.by_candidate[list(selected)].tocsr()
    counts = np.asarray(rows.sum(axis=0)).ravel()
    alone = [rows.indices[rows.indptr[k] : rows.indptr[k + 1]] for k in range(len(selected))]
    alone = [a[counts[a] == 1] for a in alone]
    drawn = regions([int(p) for a in alone for p in a])
    return [shapely.intersection_all([drawn[int(p)] for p in a]) if a.size else None for a in alone]


def aligned_candidates(
    site: Site,
    problem: CoverageProblem,
    selected: Sequence[int],
    regions: Callable[[list[int]], dict[int, Any]],
    reach_m: float,
) -> list[Candidate]:
    """Candidates in the movement regions of the cover ``selected`` (:func:`movement_regions`) from which a region of
    the cover across an opening is seen through it, within ``reach_m`` (module docstring); none where the site has no
    opening between two spaces of the cover's stations."""
    cands = [problem.candidates[i] for i in selected]
    zones = {z.id: z for z in site.zones}
    space = [space_of(zones[c.zone], c.side) for c in cands]
    openings = [(ends, a, b) for ends, a, b in opening_spaces(site, passable_only=False) if a != b]
    if not any(a in space and b in space for _e, a, b in openings):
        return []
    moves = movement_regions(problem, selected, regions)
    views: list[list[shapely.Geometry]] = [[] for _ in cands]
    width = [math.inf] * len(cands)
    for ends, a, b in openings:
        for here, there in ((a, b), (b, a)):
            across = [m for m, s in zip(moves, space, strict=True) if s == there and m is not None and not m.is_empty]
            if not across:
                continue
            view = shapely.union_all([seen_through(m, ends, reach_m) for m in across])
            for k, s in enumerate(space):
                if s == here and moves[k] is not None:
                    views[k].append(view)
                    width[k] = min(width[k], float(np.hypot(*(ends[1] - ends[0]))))
    out: list[Candidate] = []
    for k, c in enumerate(cands):
        if not views[k]:
            continue
        part = shapely.intersection(moves[k], shapely.union_all(views[k]))
        for x, y in _samples(part, width[k] / PER_WIDTH):
            out.append(side_candidate(c.zone, c.side, c.frame, f"T{len(out) + 1}", float(x), float(y), KIND))
    return dedupe(out)


def _samples(region: shapely.Geometry, spacing_m: float) -> NDArray[np.float64]:
    """Grid points of ``region`` ``spacing_m`` apart (coarser where that would pass :data:`PER_REGION`), or its pole
    where none falls inside; none for an empty region."""
    if region.is_empty or region.area < MIN_AREA_M2:
        return np.zeros((0, 2))
    h = max(spacing_m, math.sqrt(region.area / PER_REGION))
    x0, y0, x1, y1 = region.bounds
    gx, gy = np.meshgrid(np.arange(x0 + h / 2, x1, h), np.arange(y0 + h / 2, y1, h))
    xs, ys = gx.ravel(), gy.ravel()
    inside = shapely.contains_xy(region, xs, ys)
    if inside.any():
        return np.c_[xs[inside], ys[inside]]
    pole = largest_part_pole(region, min_tolerance_m=1e-7)
    return np.array([[pole.x, pole.y]])
