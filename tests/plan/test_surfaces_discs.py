"""Tripod discs that keep the floor: :func:`planner.plan.surfaces.surface_discs` tests the rims of every unsettled
station in one sight test per halving step. Its discs equal those of the station-by-station test written here
(each station's patches, its rim tested alone, halved three times at most, then 0), and the vectorised probe
classification of :mod:`planner.plan.tripod` equals :func:`planner.candidates.final_step.misplacement` point by
point.

The room: 10 m x 6 m with a 6 x 2 m corner cut out of it (an L) and a column, walls 3 m, instrument 1.5 m; the
stations stand on a 0.5 m grid over its floor, 0.4 m clear of walls and column.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import shapely

from planner.candidates.final_step import misplacement
from planner.coverage.surface_sight import surface_sight
from planner.coverage.surfaces import open_area
from planner.plan import PlanOptions
from planner.plan.problem import resolve
from planner.plan.surfaces import _margins, standing_zones, surface_cover, surface_discs
from planner.plan.tripod import MIN_RADIUS_M, RIM_POINTS, TripodDisc, _misplaced
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Site, Zone
from planner.site.params import Parameters


def _site() -> Site:
    xy = ((0.0, 0.0), (10.0, 0.0), (10.0, 6.0), (6.0, 6.0), (6.0, 4.0), (0.0, 4.0))
    column = ((2.0, 2.0), (2.0, 2.6), (2.6, 2.6), (2.6, 2.0))
    zone = Zone("R", ScanSide.INSIDE, xy, (3.0,) * len(xy), holes=(column,), hole_heights_m=((3.0,) * 4,))
    return Site("L room", (zone,), parameters=Parameters(instrument_height_m=1.5))


def _one_by_one(site, setup, cover, selected, stations, discs):
    """The discs as the station-by-station test gives them (the docstring's rule, one sight test per rim)."""
    m = cover.matrix[list(selected)].tocoo()
    rows, pid = m.row.astype(np.int64), cover.seen[m.col]
    xy = np.array([s.xy for s in stations], dtype=float).reshape(-1, 2)
    zone = standing_zones(site, stations)
    margin = _margins(site, setup, xy[rows], zone[rows], pid)
    order = np.lexsort((-margin, pid))
    first = order[np.r_[True, pid[order][1:] != pid[order][:-1]]]
    angles = np.linspace(0.0, 2 * math.pi, RIM_POINTS, endpoint=False)
    ring = np.column_stack([np.cos(angles), np.sin(angles)])
    out = list(discs)
    for k in np.unique(rows[first]):
        mine = first[rows[first] == k]
        r, need, ok = min(discs[k].radius_m, float(margin[mine].min())), pid[mine], False
        for _ in range(4):
            if r < MIN_RADIUS_M:
                break
            seen = surface_sight(site, setup.patches, xy[k] + r * ring, np.full(RIM_POINTS, zone[k]), setup.limits)
            if seen[:, need].toarray().all():
                ok = True
                break
            r /= 2
        r = r if ok and r >= MIN_RADIUS_M else 0.0
        if r < discs[k].radius_m:
            out[k] = replace(discs[k], radius_m=r)
    return out


def test_batched_rims_give_the_discs_of_the_station_by_station_test():
    # stations on a 0.5 m grid, each with a 1 m disc to start from and answering for the patches it sees best:
    # the column and the L's inner corner hide patches from some rims, so some discs are halved
    site = _site()
    problem = resolve(site, PlanOptions(surfaces=("walls", "floors")))
    setup = problem.surfaces
    assert setup is not None
    g = np.arange(0.45, 10.0, 0.5)
    pts = [(float(x), float(y)) for x in g for y in g if y < 6.0]
    stand = open_area(site, 0).buffer(-0.4)
    stations = [
        Candidate(f"S{k}", "R", ScanSide.INSIDE, site.zones[0].frame, x, y, CandidateKind.GRID)
        for k, (x, y) in enumerate(p for p in pts if stand.contains(shapely.Point(p)))
    ]
    cover = surface_cover(site, setup, stations)
    selected = tuple(range(len(stations)))
    discs = tuple(TripodDisc(s.id, 1.0, s.xy, 0) for s in stations)
    got, shrunk = surface_discs(site, setup, cover, selected, stations, discs)
    want = _one_by_one(site, setup, cover, selected, stations, discs)
    radii = [d.radius_m for d in got]
    assert radii == [d.radius_m for d in want]
    assert shrunk == sum(r < 1.0 for r in radii) > 0
    halved = [r for r, w in zip(radii, _first_radii(site, setup, cover, selected, stations)) if 0 < r < w]
    assert halved, "no disc was halved: the rim test is not exercised"


def _first_radii(site, setup, cover, selected, stations):
    """Each station's radius before any rim test: the smallest margin of its patches, at most 1 m."""
    m = cover.matrix[list(selected)].tocoo()
    rows, pid = m.row.astype(np.int64), cover.seen[m.col]
    xy = np.array([s.xy for s in stations], dtype=float).reshape(-1, 2)
    margin = _margins(site, setup, xy[rows], standing_zones(site, stations)[rows], pid)
    order = np.lexsort((-margin, pid))
    first = order[np.r_[True, pid[order][1:] != pid[order][:-1]]]
    out = np.full(len(stations), 1.0)
    np.minimum.at(out, rows[first], margin[first])
    return out.tolist()


def test_probe_classification_matches_misplacement_point_by_point():
    site = _site()
    c = Candidate("c", "R", ScanSide.INSIDE, site.zones[0].frame, 5.0, 2.0, CandidateKind.GRID)
    pts = np.array([[x, y] for x in np.linspace(-0.5, 10.5, 23) for y in np.linspace(-0.5, 6.5, 15)])
    outside = replace(c, side=ScanSide.OUTSIDE)
    for cand in (c, outside):
        got = _misplaced(site, [cand] * len(pts), pts)
        want = np.array([bool(misplacement(site, cand, float(x), float(y))) for x, y in pts])
        assert np.array_equal(got, want) and want.any() and not want.all()
