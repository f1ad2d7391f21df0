"""Sight, range and incidence tests on hand-checkable tiny sites."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.coverage.matrix import build_coverage
from planner.coverage.targets import make_targets
from planner.coverage.visibility import SightLimits, segments_touch
from planner.site import ScanSide, Site, Zone
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import Obstacle


def room(w: float = 20.0, d: float = 20.0, h: float = 3.0, obstacles=()) -> Site:
    z = Zone("R", ScanSide.INSIDE, ((0, 0), (w, 0), (w, d), (0, d)), (h,) * 4)
    return Site("room", (z,), obstacles=tuple(obstacles))


def station(x: float, y: float, zone: str = "R", side: ScanSide = ScanSide.INSIDE) -> Candidate:
    return Candidate(f"s{x},{y}", zone, side, "site", x, y, CandidateKind.GRID)


def seen(site: Site, stations, limits: SightLimits, spacing: float = 1.0):
    t = make_targets(site, spacing)
    cov = build_coverage(site, stations, t, limits)
    return t, cov


def test_segments_touch_cases():
    p, q = np.array([[0.0, 0.0]]), np.array([[2.0, 0.0]])
    assert segments_touch(p, q, np.array([[1.0, -1.0]]), np.array([[1.0, 1.0]]))[0]  # crossing
    assert segments_touch(p, q, np.array([[2.0, 0.0]]), np.array([[3.0, 1.0]]))[0]  # touching an end
    assert segments_touch(p, q, np.array([[1.0, 0.0]]), np.array([[3.0, 0.0]]))[0]  # collinear overlap
    assert not segments_touch(p, q, np.array([[3.0, 0.0]]), np.array([[4.0, 0.0]]))[0]  # collinear, apart
    assert not segments_touch(p, q, np.array([[0.0, 1.0]]), np.array([[2.0, 1.0]]))[0]  # parallel


def test_centre_of_a_square_room_sees_every_wall():
    # from (10, 10) each wall is 10 m away; its ends at atan(10/10) = 45 deg <= 68: all 80 pieces seen
    t, cov = seen(room(), [station(10, 10)], SightLimits(95.913, 68.0))
    assert len(t) == 80 and cov.by_candidate.nnz == 80


def test_incidence_limit_cuts_a_long_wall():
    # 2 m from wall 1 (y = 0) at x = 10: seen while atan(|x - 10| / 2) <= 68 deg, i.e. |x - 10| <= 4.95 m; the whole 1 m
    # pieces inside 5.05..14.95 are 6-7 .. 13-14: 8 pieces (5-6 and 14-15 are cut)
    t, cov = seen(room(), [station(10, 2)], SightLimits(95.913, 68.0))
    wall1 = [i for i in cov.by_candidate[0].indices if t.wall[i] == 1]
    assert [int(t.s0_m[i]) for i in sorted(wall1)] == [6, 7, 8, 9, 10, 11, 12, 13]


def test_range_limit_uses_the_top_of_the_wall():
    # a 20 m square room, 3 m walls, station in a corner region at (1, 1): the far corner (20, 20) is sqrt(19^2 + 19^2)
    # = 26.87 m away horizontally, sqrt(26.87^2 + 3^2) = 27.04 m slant.
    t, full = seen(room(), [station(10, 10)], SightLimits(27.1, 89.0))
    _, cut = seen(room(), [station(1, 1)], SightLimits(27.0, 89.0))
    far = [i for i in range(len(t)) if t.wall[i] == 2 and t.s1_m[i] == 20.0]
    assert far and all(i not in set(cut.by_candidate[0].indices) for i in far)
    _, ok = seen(room(), [station(1, 1)], SightLimits(27.05, 89.0))
    assert all(i in set(ok.by_candidate[0].indices) for i in far)


def test_obstacle_hides_the_wall_behind_it():
    col = Obstacle("column", ((9, 9), (11, 9), (11, 11), (9, 11)), 5.0)
    site = room(obstacles=[col])
    t, cov = seen(site, [station(10, 2)], SightLimits(95.913, 89.0))
    north = {int(t.s0_m[i]) for i in cov.by_candidate[0].indices if t.wall[i] == 3}
    # wall 3 runs from (20, 20) to (0, 20): s = 20 - x. Rays from (10, 2) through the column's corners (9, 11) and (11,
    # 11) reach y = 20 at x = 10 -/+ 1 * 18/9 = 8 .. 12, hidden
    assert not north & {8, 9, 10, 11}
    assert {0, 1, 2, 16, 17, 18, 19} <= north


def test_thin_column_between_the_two_sight_lines_hides_the_piece():
    # piece on wall 1 of a room from x = 9 to 11; the station at (10, 18); a 0.1 m column at (10, 9): both end rays pass
    # it (at x = 10 -/+ 0.5), but it stands inside the triangle: not seen
    col = Obstacle("pin", ((9.95, 8.95), (10.05, 8.95), (10.05, 9.05), (9.95, 9.05)), 5.0)
    site = room(obstacles=[col])
    t = make_targets(site, 2.0)
    cov = build_coverage(site, [station(10, 18)], t, SightLimits(95.913, 89.0))
    piece = next(i for i in range(len(t)) if t.wall[i] == 1 and t.s0_m[i] == 8.0)  # 8..10
    other = next(i for i in range(len(t)) if t.wall[i] == 1 and t.s0_m[i] == 2.0)
    assert piece not in set(cov.by_candidate[0].indices) and other in set(cov.by_candidate[0].indices)


def test_station_outside_sees_only_outer_faces():
    z = Zone("B", ScanSide.BOTH, ((0, 0), (10, 0), (10, 10), (0, 10)), (3.0,) * 4)
    site = Site("b", (z,))
    t = make_targets(site, 1.0)
    cov = build_coverage(site, [station(5, -5, "B", ScanSide.OUTSIDE)], t, SightLimits(95.913, 68.0))
    sides = {int(t.side[i]) for i in cov.by_candidate[0].indices}
    walls = {int(t.wall[i]) for i in cov.by_candidate[0].indices}
    assert sides == {1} and walls == {1}  # only the outer face of the south wall


def test_both_views_agree_and_excluded_stations_see_nothing():
    col = Obstacle("column", ((9, 9), (11, 9), (11, 11), (9, 11)), 5.0)
    site = room(obstacles=[col])
    t = make_targets(site, 1.0)
    cov = build_coverage(site, [station(10, 10), station(5, 5)], t, SightLimits(95.913, 68.0))
    assert cov.excluded == {0: "inside obstacle column"}
    assert cov.by_candidate.getrow(0).nnz == 0
    assert (cov.by_target != cov.by_candidate.T.tocsr()).nnz == 0
    # the slant ranges follow the pieces seen: from (5, 5) the column's corner (11, 9) shades the east wall x = 20 from
    # y = 5 + 15 * 4 / 6 = 15 up (the piece 14..15 grazes that corner and counts as hidden), so the farthest point seen
    # is the top of (20, 14), 3 m walls, instrument at 0 m: sqrt(15^2 + 9^2 + 3^2) = 17.748
    assert cov.slant_m.getrow(1).max() == pytest.approx(math.sqrt(315.0))
    assert cov.slant_m.getrow(0).nnz == 0


@pytest.mark.parametrize(
    "height, incidence_3d, pieces",
    [
        # a 20 x 20 room, station at (10, 2), 2 m from the south wall; theta_max 68 deg, cos 68 = 0.3746. horizontal
        # incidence: cos = 2 / sqrt(u^2 + 4) >= 0.3746 for |u| <= 4.95 m, whole 1-m pieces 6..13
        (3.0, False, list(range(6, 14))),
        # 3-D incidence to the wall top (3 m, instrument at 0): cos = 2 / sqrt(u^2 + 4 + 9), |u| <= 3.94 m: pieces 7..12
        (3.0, True, list(range(7, 13))),
        # 10 m walls: cos <= 2 / sqrt(4 + 100) = 0.196 < 0.3746 anywhere: nothing of the south wall in 3-D
        (10.0, True, []),
    ],
)
def test_incidence_in_plan_and_in_3d_by_hand(height, incidence_3d, pieces):
    site = room(h=height)
    t, cov = seen(site, [station(10, 2)], SightLimits(95.913, 68.0, incidence_3d=incidence_3d))
    south = sorted(int(t.s0_m[i]) for i in cov.by_candidate[0].indices if t.wall[i] == 1)
    assert south == pieces
