"""Registration groups by accessible area: rooms, separated open ground, and the old labels kept."""

from __future__ import annotations

from planner.candidates.model import Candidate, CandidateKind
from planner.coverage.groups import registration_groups
from planner.site.model import Obstacle, ScanSide, Site, Zone
from planner.site.load import load_site
from tests.conftest import INSTANCES


def _cand(name: str, x: float, y: float, zone: str = "hall") -> Candidate:
    return Candidate(name, zone, ScanSide.OUTSIDE, "site", x, y, CandidateKind.GRID)


def test_a_wall_across_the_site_makes_two_areas() -> None:
    """Boundary 0..100 x 0..40; an obstacle 48..52 across the whole height cuts the ground in two:
    a station at x=20 and one at x=80 stand in different areas, two at x=10 and x=30 in the same."""
    hall = Zone("hall", ScanSide.OUTSIDE, ((10, 10), (20, 10), (20, 20), (10, 20)), (5, 5, 5, 5))
    shed = Zone("shed", ScanSide.OUTSIDE, ((70, 10), (80, 10), (80, 20), (70, 20)), (5, 5, 5, 5))
    wall = Obstacle("wall", ((48, -1), (52, -1), (52, 41), (48, 41)), 3.0)
    site = Site("split", (hall, shed), obstacles=(wall,), boundary=((0, 0), (100, 0), (100, 40), (0, 40)))
    g = registration_groups(site, [_cand("a", 5, 5), _cand("b", 30, 30), _cand("c", 80, 30, "shed"), _cand("d", 60, 5)])
    assert g[0] == g[1] == "site/area 1"
    assert g[2] == g[3] == "site/area 2"


def test_rooms_keep_their_label_and_a_lone_outline_keeps_its_own() -> None:
    site = load_site(INSTANCES / "courtyard.json")
    g = registration_groups(site, [_cand("in court", 20, 12, "hall"), _cand("out", 45, 30, "court")])
    assert g == ("court/inside", "hall/outside")  # by where they stand, not by the zone that proposed them
