"""The 3-D sight test (planner.coverage.rays) on its site mesh (planner.coverage.mesh): hand-checked rooms, the
accelerated search against brute force, and the issue-46 property: on walls-only rooms the 3-D verdict is the plan
view's."""

from __future__ import annotations

import dataclasses
import math
from unittest import mock

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.coverage import rays
from planner.coverage.matrix import blockers_for
from planner.coverage.mesh import (
    KIND_CEILING,
    KIND_FLOOR,
    KIND_OBSTACLE,
    KIND_SLAB,
    KIND_WALL,
    SiteMesh,
    Slab,
    ceiling_key,
    floor_key,
    obstacle_key,
    site_mesh,
    slab_key,
)
from planner.coverage.rays import NO_SKIP, occluded, segment_hits_triangles, shortened_ends
from planner.coverage.visibility import segments_touch, sight_clear, wall_key
from planner.site import ScanSide, Site, Zone
from planner.site.model import Obstacle, Opening

QUICK = settings(deadline=None, derandomize=True, database=None)


def room(*obstacles: Obstacle, h: float = 3.0, openings: tuple[Opening, ...] = ()) -> Site:
    """A 10 m x 10 m room with walls ``h`` high; walls 1..4 are y = 0, x = 10, y = 10, x = 0."""
    z = Zone("R", ScanSide.INSIDE, ((0, 0), (10, 0), (10, 10), (0, 10)), (h,) * 4, openings=openings)
    return Site("room", (z,), obstacles=obstacles)


def block(x0: float, y0: float, x1: float, y1: float, h: float) -> Obstacle:
    return Obstacle("block", ((x0, y0), (x1, y0), (x1, y1), (x0, y1)), h)


def test_mesh_of_a_room_with_a_door_a_block_and_a_slab():
    # 4 walls, wall 1 cut by a door at 4..5 m into 2 parts: 5 quads = 10 triangles, keys 1..4 (zone 0); the block: 4
    # side quads (8) + its square top (2); the slab: a square (2); a floor level of 2 m lifts walls
    site = room(block(4, 4, 5, 5, 2.0), openings=(Opening(1, 4.0, 5.0),))
    m = site_mesh(site, floors_m={"R": 2.0}, slabs=[Slab(((0, 0), (10, 0), (10, 10), (0, 10)), 3.0)])
    assert len(m) == 10 + 10 + 2
    assert sorted(set(m.source[m.kind == KIND_WALL].tolist())) == [1, 2, 3, 4]
    assert set(m.source[m.kind == KIND_OBSTACLE].tolist()) == {obstacle_key(0)} == {-1}
    assert set(m.source[m.kind == KIND_SLAB].tolist()) == {slab_key(0)}
    walls = m.corners()[m.kind == KIND_WALL]
    assert walls[..., 2].min() == 2.0 and walls[..., 2].max() == 5.0  # floor 2 m, top 2 + 3 m
    door = m.corners()[m.source == 1][..., 0]
    assert not np.any((door > 4.0) & (door < 5.0))  # nothing of wall 1 inside the door
    # sight through the door (x = 4.5) out of the room is clear; 1 m beside it (x = 3.5) the wall blocks
    o = np.array([[4.5, 5.0, 3.5], [3.5, 5.0, 3.5]])
    assert occluded(site_mesh(site, floors_m={"R": 2.0}), o, o - [0, 10, 0]).tolist() == [False, True]


def test_floor_level_floor_and_ceiling_of_a_zone():
    # a zone with its floor at 2 m and a 3 m ceiling: walls from 2 to 2 + 3 = 5 m, the floor at 2 m, the ceiling at 5 m,
    # each square in two triangles; from (5, 5, 3.5) straight up to 5.5 m crosses the ceiling, down to 1.5 m the floor,
    # to 4.9 m neither; a point of the floor at (5, 8, 2) is seen, its floor skipped
    z = Zone("R", ScanSide.INSIDE, ((0, 0), (10, 0), (10, 10), (0, 10)), (3.0,) * 4, floor_level_m=2.0)
    site = Site("room", (dataclasses.replace(z, ceiling_height_m=3.0),))
    m = site_mesh(site, floors=True, ceilings=True)
    assert len(m) == 8 + 2 + 2
    assert m.corners()[m.kind == KIND_WALL][..., 2].min() == 2.0 and m.vertices[:, 2].max() == 5.0
    assert set(m.corners()[m.kind == KIND_FLOOR][..., 2].ravel()) == {2.0}
    assert set(m.corners()[m.kind == KIND_CEILING][..., 2].ravel()) == {5.0}
    assert set(m.source[m.kind == KIND_CEILING].tolist()) == {ceiling_key(0)}
    o = np.tile([5.0, 5.0, 3.5], (4, 1))
    ends = np.array([[5, 5, 5.5], [5, 5, 1.5], [5, 5, 4.9], [5, 8, 2.0]])
    skip = np.array([NO_SKIP, NO_SKIP, NO_SKIP, floor_key(0)])
    assert occluded(m, o, ends, skip).tolist() == [True, True, False, False]
    assert len(site_mesh(site)) == 8  # walls only unless asked


def test_at_a_corner_the_plan_views_line_tolerance_blocks_more():
    # a known difference, why the property below draws its wall points off the corners. The sight line from (0, 10) to
    # the corner (0, 0) stops 1e-5 m short, at (0, 1e-5); the next wall runs from the corner away from the station, to
    # (10 sin 0.3 deg, -10 cos 0.3 deg). The line's end is 1e-5 * sin 0.3 deg = 5.2e-8 m from that wall's LINE, within
    # EPS_SIGHT_M = 1e-7, and the corner is on the sight line, so segments_touch (side-of-line tests within EPS) says
    # touching; the Euclidean distance to the wall is 1e-5 m, so the 3-D test says clear
    a = math.radians(0.3)
    far = np.array([10 * math.sin(a), -10 * math.cos(a)])
    end = np.array([[0.0, 1e-5]])
    assert segments_touch(np.array([[0.0, 10.0]]), end, np.array([[0.0, 0.0]]), far[None])[0]
    v = np.array([[0, 0, 0], [far[0], far[1], 0], [far[0], far[1], 3], [0, 0, 3]], float)
    wall = SiteMesh(v, np.array([[0, 1, 2], [0, 2, 3]]), np.array([7, 7]), np.zeros(2, np.int8))
    assert not occluded(wall, [[0.0, 10.0, 1.5]], [[0.0, 0.0, 1.5]])[0]


def test_from_the_centre_of_a_room_every_wall_point_is_seen():
    # the room is convex and empty: from (5, 5, 1.5) each segment to a point of a wall (corners, foot and top edge
    # included) stays inside [0, 10]^2 x [0, 3] and stops 1e-5 m short of its own (skipped) wall
    m = site_mesh(room())
    s = np.arange(0.0, 10.01, 0.5)
    pts, keys = [], []
    for w, (x, y) in enumerate([(s, 0 * s), (10 + 0 * s, s), (10 - s, 10 + 0 * s), (0 * s, 10 - s)], start=1):
        for z in (0.0, 0.75, 1.5, 2.25, 3.0):
            pts.append(np.stack([x, y, np.full_like(s, z)], axis=1))
            keys.append(np.full(len(s), int(wall_key(0, w))))
    ends = np.concatenate(pts)
    assert len(ends) == 4 * 5 * 21
    assert not occluded(m, np.tile([5.0, 5.0, 1.5], (len(ends), 1)), ends, np.concatenate(keys)).any()


def test_a_two_metre_block_hides_the_wall_behind_it():
    # block 4.5..5.5 x 4.5..5.5, 2 m high; station (2, 5, 1.5) towards wall 2 (x = 10) along y = 5: at the block's near
    # face x = 4.5 the line to (10, 5, z) is at 1.5 + (z - 1.5) * 2.5 / 8 < 2 for every z <= 3 (it would need z > 3.1),
    # so the whole height of the wall behind is hidden; at y = 2 the block is not in the way (the line from (2, 5) to
    # (10, 2) is at y = 4.06 < 4.5 by x = 4.5)
    m = site_mesh(room(block(4.5, 4.5, 5.5, 5.5, 2.0)))
    ends = np.array([[10, 5, 0.0], [10, 5, 1.5], [10, 5, 3.0], [10, 2, 1.5]])
    got = occluded(m, np.tile([2.0, 5.0, 1.5], (4, 1)), ends, np.full(4, wall_key(0, 2)))
    assert got.tolist() == [True, True, True, False]


def test_a_sight_line_passes_over_a_one_metre_block_and_touching_is_blocked():
    # block 4..5 x 4.5..5.5, 1 m high; station (1, 5, 1.5) to (10, 5, z) on wall 2: at the block's far top edge x = 5
    # (4/9 of the way) the line is at 1.5 + (z - 1.5) * 4/9, = 1 for z = 0.375: it touches the edge there (blocked, the
    # convention); z = 0.384 passes 4 mm above (1.004 at x = 5, 1.128 at x = 4): seen; z = 0.366 is at 0.996 at x = 5,
    # so it enters the block's top near x = 4.97: blocked; z = 1.5 passes 0.5 m above: seen
    m = site_mesh(room(block(4, 4.5, 5, 5.5, 1.0)))
    ends = np.array([[10, 5, 0.375], [10, 5, 0.384], [10, 5, 0.366], [10, 5, 1.5]])
    got = occluded(m, np.tile([1.0, 5.0, 1.5], (4, 1)), ends, np.full(4, wall_key(0, 2)))
    assert got.tolist() == [True, False, True, False]


def test_touching_a_walls_top_edge_is_blocked():
    # from (5, 5, 1.5) out over wall 2 (x = 10, top at 3 m): the line to (15, 5, z) is at 1.5 + (z - 1.5) / 2 at x = 10;
    # z = 4.5 gives 3.0 exactly, the top edge: blocked (touching counts); z = 4.6 passes 5 cm above; z = 4.4 hits the
    # wall 5 cm below its top
    m = site_mesh(room())
    ends = np.array([[15, 5, 4.5], [15, 5, 4.6], [15, 5, 4.4]])
    assert occluded(m, np.tile([5.0, 5.0, 1.5], (3, 1)), ends).tolist() == [True, False, True]


def brute_force(mesh, o, e, skip):
    """Every segment against every triangle with the same pair test: no tree, no height filter, no chunks."""
    e = shortened_ends(o, e)
    corners = mesh.corners()
    out = np.zeros(len(o), dtype=bool)
    for i in range(len(o)):
        mine = mesh.source != skip[i]
        k = int(mine.sum())
        out[i] = segment_hits_triangles(np.tile(o[i], (k, 1)), np.tile(e[i], (k, 1)), corners[mine]).any()
    return out


half_grid = st.integers(0, 8).map(lambda k: k / 2.0)  # 0, 0.5, .. 4: touching and parallel cases are common


TREE_CASES = {
    "tri": st.lists(st.tuples(*[half_grid] * 9), min_size=1, max_size=12),
    "seg": st.lists(st.tuples(*[half_grid] * 6), min_size=1, max_size=12),
    "skips": st.lists(st.integers(0, 13), min_size=12, max_size=12),
}


def _tree_search_finds_what_brute_force_finds(tri, seg, skips):
    # the plan-view tree (whole segments, and pieces of 0.7 m), the filters, the chunks (3 segments each) and the early
    # exit drop no pair the exact test would block; on a half-metre grid many segments touch edges, lie in planes or are
    # vertical
    t = len(tri)
    mesh = SiteMesh(
        np.array(tri, float).reshape(-1, 3), np.arange(3 * t).reshape(-1, 3), np.arange(t) % 4, np.zeros(t, np.int8)
    )
    s = np.array(seg, float)
    skip = np.array([k if k < 4 else NO_SKIP for k in skips[: len(s)]], np.int64)  # skip a source, or nothing
    want = brute_force(mesh, s[:, :3], s[:, 3:], skip).tolist()
    for piece in (rays.PIECE_M, 0.7):  # the default, and pieces shorter than most segments here
        with mock.patch.object(rays, "PIECE_M", piece):
            assert occluded(mesh, s[:, :3], s[:, 3:], skip, chunk=3).tolist() == want


@settings(QUICK, max_examples=25)
@given(**TREE_CASES)
def test_the_tree_search_finds_what_brute_force_finds_on_a_few_cases(tri, seg, skips):
    _tree_search_finds_what_brute_force_finds(tri, seg, skips)


@pytest.mark.slow
@QUICK
@given(**TREE_CASES)
def test_the_tree_search_finds_what_brute_force_finds(tri, seg, skips):
    # hypothesis's default 100 cases (the quick twin above runs 25)
    _tree_search_finds_what_brute_force_finds(tri, seg, skips)


def moller_trumbore(o, e, v0, v1, v2):
    """The classic segment-triangle test (no tolerance), one pair in plain Python floats."""
    d, e1, e2 = e - o, v1 - v0, v2 - v0
    p = np.cross(d, e2)
    det = float(e1 @ p)
    if abs(det) < 1e-12:
        return False
    s = o - v0
    u = float(s @ p) / det
    q = np.cross(s, e1)
    v = float(d @ q) / det
    t = float(e2 @ q) / det
    return u >= 0 and v >= 0 and u + v <= 1 and 0 <= t <= 1


@settings(QUICK, max_examples=50)
@given(seed=st.integers(0, 2**32 - 1))
def test_the_pair_test_is_moller_trumbore_away_from_the_tolerance(seed):
    # continuous random triangles and segments in a 10 m cube: a pair within 1e-7 m of touching has a chance of order
    # 1e-7, so the tolerant test and the classic one agree on all 300 pairs
    rng = np.random.default_rng(seed)
    tri, o, e = rng.uniform(0, 10, (300, 3, 3)), rng.uniform(0, 10, (300, 3)), rng.uniform(0, 10, (300, 3))
    got = segment_hits_triangles(o, e, tri)
    want = [moller_trumbore(o[i], e[i], *tri[i]) for i in range(300)]
    assert got.tolist() == want


# the full-strength run is in the slow tier, marked here rather than by a decorator: hypothesis derandomises
# a property by its source, decorators included, so a marker line would change the cases it has always run
test_the_pair_test_is_moller_trumbore_away_from_the_tolerance = pytest.mark.slow(
    test_the_pair_test_is_moller_trumbore_away_from_the_tolerance
)


@settings(QUICK, max_examples=10)
@given(seed=st.integers(0, 2**32 - 1))
def test_the_pair_test_is_moller_trumbore_away_from_the_tolerance_on_fewer_cases(seed):
    # the quick twin: the body of the test above on 10 cases (the test above runs 50, in the slow tier)
    test_the_pair_test_is_moller_trumbore_away_from_the_tolerance.hypothesis.inner_test(seed=seed)


@st.composite
def walls_only_rooms(draw):
    """A star-shaped room of 4-10 walls of one height H about (cx, cy), maybe a block of height H near its middle,
    stations inside (not in the block), points on the walls off their corners (heights 0..H), an instrument height
    0.5H..H. Off the corners: see test_at_a_corner_the_plan_views_line_tolerance_blocks_more. Vertex k is at angle 2 pi
    (k + j_k) / n, |j_k| <= 1/4, radius 3..10 m: the gaps are under 180 deg, so the outline is simple and star-shaped
    about the centre, and a station at 0.1..0.97 of the way from the centre to a point of a wall is inside (with reflex
    corners that hide walls). The block (radii 0.5..2.5 m, shrunk until it stands 0.1 m inside the room) is a prism of
    height H; stations within 0.05 m of it are dropped."""
    n = draw(st.integers(4, 10))
    cx, cy = draw(st.floats(-100, 100)), draw(st.floats(-100, 100))
    h = draw(st.floats(2.0, 6.0))

    def star(k, r0, r1):
        j = draw(st.lists(st.floats(-0.25, 0.25), min_size=k, max_size=k))
        r = np.array(draw(st.lists(st.floats(r0, r1), min_size=k, max_size=k)))
        a = 2 * math.pi * (np.arange(k) + np.array(j)) / k
        return np.column_stack([r * np.cos(a), r * np.sin(a)])

    xy = star(n, 3.0, 10.0) + [cx, cy]
    poly = shapely.Polygon(xy)
    obstacles, keep_out = (), shapely.Polygon()
    if draw(st.booleans()):
        b = star(draw(st.integers(3, 6)), 0.5, 2.5)
        while not poly.buffer(-0.1).contains(shapely.Polygon(b + [cx, cy])):
            b = b * 0.8
        obstacles = (Obstacle("block", tuple(map(tuple, b + [cx, cy])), h),)
        keep_out = shapely.Polygon(b + [cx, cy]).buffer(0.05)
    site = Site("star", (Zone("R", ScanSide.INSIDE, tuple(map(tuple, xy)), (h,) * n),), obstacles=obstacles)

    def on_wall():
        w, t = draw(st.integers(0, n - 1)), draw(st.floats(0.001, 0.999))
        return w + 1, xy[w] + t * (xy[(w + 1) % n] - xy[w])

    stations = [np.array([cx, cy]) + draw(st.floats(0.1, 0.97)) * (on_wall()[1] - [cx, cy]) for _ in range(6)]
    stations = [s for s in stations if not keep_out.contains(shapely.Point(s))]
    points = [(*on_wall(), draw(st.floats(0.0, h))) for _ in range(10)]
    return site, h * draw(st.floats(0.5, 1.0)), np.array(stations).reshape(-1, 2), points


@settings(QUICK, max_examples=150)
@given(case=walls_only_rooms())
def test_3d_sight_equals_the_plan_view_on_walls_only_rooms(case):
    # every (station, wall point) pair gets the same verdict from the 3-D test as from the plan view's sight_clear on a
    # point piece (a = b), with the blockers of blockers_for and the piece's own wall skipped in both. Each line runs
    # from the instrument (height ih <= H) to a point at 0..H, so where the plan view crosses a wall or the block's edge
    # the 3-D line is at a height inside 0..H there: it meets the wall; where the plan view is clear it passes
    site, ih, stations, points = case
    c = np.repeat(stations, len(points), axis=0)
    p = np.tile(np.array([q for _, q, _ in points]), (len(stations), 1))
    z = np.tile(np.array([h for _, _, h in points]), len(stations))
    key = np.tile(np.array([int(wall_key(0, w)) for w, _, _ in points]), len(stations))
    plan_clear = sight_clear(c, p, p, key, blockers_for(site, site.zones[0].frame))
    o3, e3 = np.column_stack([c, np.full(len(c), ih)]), np.column_stack([p, z])
    blocked = occluded(site_mesh(site), o3, e3, key)
    assert blocked.tolist() == (~plan_clear).tolist()


# the full-strength run is in the slow tier, marked here rather than by a decorator: hypothesis derandomises
# a property by its source, decorators included, so a marker line would change the cases it has always run
test_3d_sight_equals_the_plan_view_on_walls_only_rooms = pytest.mark.slow(
    test_3d_sight_equals_the_plan_view_on_walls_only_rooms
)


@settings(QUICK, max_examples=40)
@given(case=walls_only_rooms())
def test_3d_sight_equals_the_plan_view_on_walls_only_rooms_on_fewer_cases(case):
    # the quick twin: the body of the test above on 40 cases (the test above runs 150, in the slow tier)
    test_3d_sight_equals_the_plan_view_on_walls_only_rooms.hypothesis.inner_test(case=case)


@settings(QUICK, max_examples=40)
@given(case=walls_only_rooms(), shift=st.tuples(st.floats(-1e4, 1e4), st.floats(-1e4, 1e4), st.floats(-50, 50)))
def test_same_input_same_output_and_a_translated_scene_the_same_verdicts(case, shift):
    # determinism: the same call twice, and a fresh mesh of the same site, give the same booleans; moving the mesh, the
    # stations and the points by one vector changes no verdict (the pair test works relative to each origin)
    site, ih, stations, points = case
    c = np.repeat(stations, len(points), axis=0)
    o = np.column_stack([c, np.full(len(c), ih)])
    e = np.tile(np.array([[*q, h] for _, q, h in points]), (len(stations), 1))
    key = np.tile(np.array([int(wall_key(0, w)) for w, _, _ in points]), len(stations))
    mesh = site_mesh(site)
    first = occluded(mesh, o, e, key)
    assert first.tolist() == occluded(mesh, o, e, key).tolist() == occluded(site_mesh(site), o, e, key).tolist()
    d = np.array(shift)
    assert occluded(mesh.translated(*shift), o + d, e + d, key).tolist() == first.tolist()


# the full-strength run is in the slow tier, marked here rather than by a decorator: hypothesis derandomises
# a property by its source, decorators included, so a marker line would change the cases it has always run
test_same_input_same_output_and_a_translated_scene_the_same_verdicts = pytest.mark.slow(
    test_same_input_same_output_and_a_translated_scene_the_same_verdicts
)


@settings(QUICK, max_examples=10)
@given(case=walls_only_rooms(), shift=st.tuples(st.floats(-1e4, 1e4), st.floats(-1e4, 1e4), st.floats(-50, 50)))
def test_same_input_same_output_and_a_translated_scene_the_same_verdicts_on_fewer_cases(case, shift):
    # the quick twin: the body of the test above on 10 cases (the test above runs 40, in the slow tier)
    test_same_input_same_output_and_a_translated_scene_the_same_verdicts.hypothesis.inner_test(case=case, shift=shift)
