"""Candidates aligned through openings (planner/candidates/aligned.py) on two rooms joined by a door."""

from __future__ import annotations

import numpy as np
import pytest

from planner.candidates.aligned import aligned_candidates, movement_regions
from planner.coverage.links import opening_links
from planner.coverage.openings import space_of
from planner.coverage.regions import coverage_regions
from planner.engine import problem_of
from planner.site import ScanSide
from planner.site.candidate import Candidate, CandidateKind
from tests.plan.test_aligned import _two_rooms


def _setup(tmp_path, door):
    site = _two_rooms(tmp_path, door)
    problem = problem_of(site)
    t, sight = problem.targets, problem.sight
    cache: dict = {}

    def regions(pieces):
        missing = [p for p in pieces if p not in cache]
        if missing:
            cache.update(coverage_regions(site, t, sight.limits, missing, {}))
        return cache

    # the plain cover by hand: each room's middle sees all of it (the far corners at atan(5/3) = 59 deg < 68)
    centres = [
        Candidate(f"{z}@mid", z, ScanSide.INSIDE, "site", x, 3.0, CandidateKind.GRID)
        for z, x in (("R1", 5.0), ("R2", 15.0))
    ]
    cover = sight.coverage(centres, t)
    return site, problem, cover, regions


def test_each_candidate_keeps_what_its_station_alone_covers_and_pairs_see_through_the_door(tmp_path):
    site, problem, cover, regions = _setup(tmp_path, (1.8, 2.8))
    assert cover.covered_by([0, 1]).min() == 1  # each piece by one of them: its room's station covers it alone
    moves = movement_regions(cover, [0, 1], regions)
    assert all(m is not None and m.area > 0 for m in moves)
    new = aligned_candidates(site, cover, [0, 1], regions, problem.registration.reach_m)
    assert {c.zone for c in new} == {"R1", "R2"}
    got = problem.sight.coverage(new, problem.targets)
    t = problem.targets
    for k, c in enumerate(new):  # every piece of its room: what its room's station covered alone
        room = t.zone_ids.index(c.zone)
        assert set(np.flatnonzero(t.zone == room)) <= set(got.by_candidate[k].indices), c.id
    xy = np.array([c.xy for c in new])
    spaces = [space_of(site.zone(c.zone), c.side) for c in new]
    links = opening_links(site, xy, [c.frame for c in new], spaces, problem.registration.reach_m)
    assert links.nnz > 0  # pairs across the door that see each other through it


def test_no_candidate_where_no_pair_of_whole_room_stations_can_see_through_the_door(tmp_path):
    # a station sees the whole room only 2.02..3.98 m up it: a segment between two such crosses x = 10 above 2.02 m
    site, problem, cover, regions = _setup(tmp_path, (0.5, 1.5))
    assert aligned_candidates(site, cover, [0, 1], regions, problem.registration.reach_m) == []


@pytest.mark.parametrize("door", [(1.8, 2.8), (0.5, 1.5)])
def test_the_same_candidates_twice(tmp_path, door):
    site, problem, cover, regions = _setup(tmp_path, door)
    reach = problem.registration.reach_m
    assert aligned_candidates(site, cover, [0, 1], regions, reach) == aligned_candidates(
        site, cover, [0, 1], regions, reach
    )
