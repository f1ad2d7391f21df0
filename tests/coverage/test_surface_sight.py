"""Which stations see which floor and ceiling patches (planner.coverage.surface_sight) hand checks of the blind cone,
the incidence and range limits at their boundaries, own zone and plan-view sight."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from planner.coverage.surface_sight import SurfaceLimits, surface_limits, surface_pairs, surface_sight
from planner.coverage.surfaces import CEILING, FLOOR, SurfaceTargets, make_surface_targets
from planner.instrument.models import Scanner, load_instrument
from planner.site.model import Obstacle, Site
from tests.coverage.surface_oracle import Scene, oracle_sees
from tests.coverage.test_surfaces import box, room

STATION = np.array([[5.0, 3.0]])
#: tiny square patches (1e-5 m a side) stand for points: their corners are within 7.1e-6 m of the point
HALF = 5e-6


def points(site: Site, xy: list[tuple[float, float]], kind: int = FLOOR, zone: int = 0) -> SurfaceTargets:
    """Point-like patches of ``kind`` at ``xy`` in zone ``zone`` (the test's own targets, built field by field)."""
    z = site.zones[zone]
    polys = np.empty(len(xy), dtype=object)
    polys[:] = [shapely.box(x - HALF, y - HALF, x + HALF, y + HALF) for x, y in xy]
    corners = np.array(
        [[(x - HALF, y - HALF), (x + HALF, y - HALF), (x + HALF, y + HALF), (x - HALF, y + HALF)] for x, y in xy]
    )
    height = z.floor_level_m + ((z.ceiling_height_m or 0.0) if kind == CEILING else 0.0)
    n = len(xy)
    return SurfaceTargets(
        zone=np.full(n, zone, np.int32),
        kind=np.full(n, kind, np.int8),
        frame=np.zeros(n, np.int32),
        cell=np.zeros((n, 2), np.int32),
        polygon=polys,
        corners=corners,
        n_corners=np.full(n, 4, np.int32),
        centroid=np.asarray(xy, float),
        area_m2=np.full(n, (2 * HALF) ** 2),
        height_m=np.full(n, height),
        normal=np.tile([0.0, 0.0, 1.0 if kind == FLOOR else -1.0], (n, 1)),
        frames=("site",),
        zone_ids=tuple(z.id for z in site.zones),
        spacing_m=2 * HALF,
    )


def ring(d: float, n: int = 8) -> list[tuple[float, float]]:
    """n points at horizontal distance d round the station (5, 3)."""
    return [(5.0 + d * math.cos(2 * math.pi * k / n), 3.0 + d * math.sin(2 * math.pi * k / n)) for k in range(n)]


def seen(site: Site, patches: SurfaceTargets, limits: SurfaceLimits, xy=STATION) -> np.ndarray:
    return surface_sight(site, patches, xy, np.zeros(len(xy), int), limits).toarray()


def test_blind_cone_hand_check_17_5_deg():
    # station (5, 3), IH 1.5 m, blind half angle 17.5 deg: floor within 1.5 tan 17.5 deg = 0.4730 m is unseen
    site = Site("s", (room(),))
    r = 1.5 * math.tan(math.radians(17.5))
    assert r == pytest.approx(0.47295, abs=1e-5)
    limits = SurfaceLimits(100.0, 68.0, 1.5, nadir_blind_half_angle_deg=17.5)
    inside, outside = points(site, ring(r - 1e-4)), points(site, ring(r + 1e-4))
    assert not seen(site, inside, limits).any() and seen(site, outside, limits).all()
    # without a blind cone the points near the tripod are seen (incidence atan(0.47 / 1.5) = 17.5 deg)
    assert seen(site, inside, SurfaceLimits(100.0, 68.0, 1.5)).all()


def test_the_p30_blind_disc_is_1_05_m_at_1_5_m():
    # P30: 35 deg half angle (360 x 290 deg), its default 1.5 m height: 1.5 tan 35 deg = 1.0503 m
    site = Site("s", (room(),))
    limits = surface_limits(load_instrument("leica-p30"), 239.55, 68.0)  # type: ignore[arg-type]
    assert (limits.instrument_height_m, limits.nadir_blind_half_angle_deg) == (1.5, 35.0)
    assert not seen(site, points(site, ring(1.045)), limits).any()
    assert seen(site, points(site, ring(1.055)), limits).all()


def test_incidence_limit_on_the_floor_both_sides_of_its_boundary():
    # a floor point at horizontal distance d is seen at incidence atan(d / 1.5): d <= 1.5 tan 68 deg = 3.7126 m
    site = Site("s", (room(box(-10, -10, 20, 20)),))
    d = 1.5 * math.tan(math.radians(68.0))
    assert d == pytest.approx(3.7126, abs=1e-4)
    limits = SurfaceLimits(100.0, 68.0, 1.5)
    assert seen(site, points(site, ring(d - 1e-4)), limits).all()
    assert not seen(site, points(site, ring(d + 1e-4)), limits).any()
    # --theta-max-floor 60: d <= 1.5 tan 60 deg = 2.5981 m, walls keep their 68 deg
    floor60 = SurfaceLimits(100.0, 68.0, 1.5, theta_max_floor_deg=60.0)
    assert floor60.theta_for(FLOOR) == 60.0 == floor60.theta_for(CEILING)
    assert seen(site, points(site, ring(2.5980)), floor60).all()
    assert not seen(site, points(site, ring(2.5982)), floor60).any()


def test_range_limit_is_the_slant_range():
    # S_max 2.5 m, IH 1.5 m: horizontal reach sqrt(2.5^2 - 1.5^2) = 2 m (incidence allows 3.71 m)
    site = Site("s", (room(),))
    limits = SurfaceLimits(2.5, 68.0, 1.5)
    assert seen(site, points(site, ring(1.9999)), limits).all()
    assert not seen(site, points(site, ring(2.0001)), limits).any()


def test_ceiling_rules():
    # ceiling 3 m above the floor, instrument 1.5 m: dz = +1.5 m, the same incidence reach 3.7126 m at 68 deg; the nadir
    # cone never meets an upward ray, so the ceiling straight above the station is seen
    site = Site("s", (room(box(-10, -10, 20, 20), ceiling_height_m=3.0),))
    limits = SurfaceLimits(100.0, 68.0, 1.5, nadir_blind_half_angle_deg=35.0)
    above = points(site, [(5.0, 3.0), *ring(3.7125)], kind=CEILING)
    assert seen(site, above, limits).all()
    assert not seen(site, points(site, ring(3.7127), kind=CEILING), limits).any()
    # a zenith cone of 20 deg half angle: 1.5 tan 20 deg = 0.5460 m round the plumb line above
    zenith = SurfaceLimits(100.0, 68.0, 1.5, zenith_blind_half_angle_deg=20.0)
    assert not seen(site, points(site, ring(0.5459), kind=CEILING), zenith).any()
    assert seen(site, points(site, ring(0.5461), kind=CEILING), zenith).all()
    # a ceiling at 1.2 m, under the 1.5 m instrument, is never seen
    low = Site("s", (room(ceiling_height_m=1.2),))
    assert not seen(low, points(low, ring(1.0), kind=CEILING), limits).any()


def test_the_whole_patch_counts_not_only_its_corners():
    # a 1 m patch centred on the station: its corners are 0.707 m away, beyond the 0.473 m blind disc, but the disc lies
    # inside the patch, so the patch is not seen whole
    site = Site("s", (room(),))
    t = make_surface_targets(site, 1.0)
    centred = make_surface_targets(Site("s", (room(box(-0.5, -0.5, 10.5, 6.5)),)), 1.0)  # cells centred on integers
    limits = SurfaceLimits(100.0, 68.0, 1.5, nadir_blind_half_angle_deg=17.5)
    k = int(np.flatnonzero((np.abs(centred.centroid - [5.0, 3.0]) < 1e-9).all(axis=1))[0])
    assert np.hypot(*(centred.corners[k, :4] - [5.0, 3.0]).T).min() == pytest.approx(math.sqrt(0.5))
    big = Site("s", (room(box(-0.5, -0.5, 10.5, 6.5)),))
    assert not seen(big, centred, limits)[0, k]
    # the four cells round the station's corner point (5, 3) of the 1 m grid anchored at 0: all unseen
    near = np.flatnonzero(shapely.distance(shapely.Point(5.0, 3.0), t.polygon) == 0.0)
    assert len(near) == 4 and not seen(site, t, limits)[0, near].any()


def test_only_the_stations_own_zone_and_only_standing_on_its_floor():
    a = room(box(0.0, 0.0, 4.0, 6.0), "A")
    b = room(box(4.0, 0.0, 8.0, 6.0), "B")
    site = Site("s", (a, b))
    t = make_surface_targets(site, 1.0)
    limits = SurfaceLimits(100.0, 89.0, 1.5)
    m = surface_sight(site, t, np.array([[3.0, 3.0], [5.0, 3.0]]), np.array([0, 0]), limits).toarray()
    # station 1 stands in A: with 89 deg (reach 86 m) it sees all of A's 24 patches and none of B's
    assert m[0, t.zone == 0].all() and not m[0, t.zone == 1].any()
    # station 2 is given as A's but stands in B: it stands on no floor of A and sees nothing
    assert not m[1].any()


def test_plan_view_blocks_obstacles_taller_than_the_instrument_for_ceilings():
    # station (3, 3), a column 0.4 m square at x 4.0..4.4 across y = 3; points at (5, 3) behind it, (3, 5) beside
    column = Obstacle("column", box(4.0, 2.8, 4.4, 3.2), 1.0)  # 1 m high: under the 1.5 m instrument
    site = Site("s", (room(ceiling_height_m=3.0),), obstacles=(column,))
    limits = SurfaceLimits(100.0, 68.0, 1.5)
    xy = np.array([[3.0, 3.0]])
    floor = points(site, [(5.0, 3.0), (3.0, 5.0)])
    assert seen(site, floor, limits, xy).tolist() == [[False, True]]  # conservative: any block hides the floor
    ceiling = points(site, [(5.0, 3.0), (3.0, 5.0)], kind=CEILING)
    assert seen(site, ceiling, limits, xy).tolist() == [[True, True]]  # a 1 m block is under every upward ray
    tall = Site("s", (room(ceiling_height_m=3.0),), obstacles=(Obstacle("column", column.vertices, 2.0),))
    assert seen(tall, points(tall, [(5.0, 3.0), (3.0, 5.0)], kind=CEILING), limits, xy).tolist() == [[False, True]]


def test_a_thin_column_between_the_corner_rays_hides_the_patch():
    # patch 4.5..5.5 x 2.5..3.5 seen from (3, 3); a 2 cm column at (4.3, 3.0) lies between the rays to the patch's
    # corners (at x = 4.3 they pass 3 +- 0.5 x 1.3 / 1.5 = +-0.43 m and 3 +- 0.5 x 1.3 / 2.5 = +-0.26 m from it) but in
    # front of the patch's middle: the patch is not seen whole
    column = Obstacle("column", box(4.29, 2.99, 4.31, 3.01), 5.0)
    site = Site("s", (room(box(-0.5, -0.5, 10.5, 6.5)),), obstacles=(column,))
    t = make_surface_targets(site, 1.0)
    k = int(np.flatnonzero((np.abs(t.centroid - [5.0, 3.0]) < 1e-9).all(axis=1))[0])
    limits = SurfaceLimits(100.0, 68.0, 1.5)
    assert not seen(site, t, limits, np.array([[3.0, 3.0]]))[0, k]
    free = Site("s", (room(box(-0.5, -0.5, 10.5, 6.5)),))
    assert seen(free, make_surface_targets(free, 1.0), limits, np.array([[3.0, 3.0]]))[0, k]


def test_an_l_shaped_room_hides_the_floor_round_its_inner_corner():
    ell = ((0.0, 0.0), (10.0, 0.0), (10.0, 4.0), (4.0, 4.0), (4.0, 10.0), (0.0, 10.0))
    site = Site("s", (room(ell),))
    limits = SurfaceLimits(100.0, 85.0, 1.5)  # reach 1.5 tan 85 deg = 17.1 m
    # from (8, 2) the segment to (2, 7) crosses x = 4 at y = 2 + 4/6 x 5 = 5.33, outside the L: hidden
    assert seen(site, points(site, [(2.0, 7.0), (2.0, 2.0)]), limits, np.array([[8.0, 2.0]])).tolist() == [
        [False, True]
    ]


def test_the_matrix_is_sparse_boolean_stations_by_patches():
    site = Site("s", (room(ceiling_height_m=3.0),))
    t = make_surface_targets(site, 1.0)
    xy = np.array([[2.0, 2.0], [8.0, 4.0], [5.0, 3.0]])
    m = surface_sight(site, t, xy, np.zeros(3, int), SurfaceLimits(100.0, 68.0, 1.5))
    assert m.shape == (3, len(t)) and m.dtype == bool and m.format == "csr"
    pairs = surface_pairs(site, t, xy, np.zeros(3, int), SurfaceLimits(100.0, 68.0, 1.5))
    assert m.nnz == len(pairs.station) and np.all(pairs.incidence_deg <= 68.0 + 1e-6)
    np.testing.assert_allclose(np.cos(np.radians(pairs.incidence_deg)) * pairs.slant_m, 1.5)  # cos i = IH / S


def test_limits_are_checked():
    with pytest.raises(ValueError, match="instrument_height_m"):
        SurfaceLimits(100.0, 68.0, 0.0)
    with pytest.raises(ValueError, match="nadir_blind_half_angle_deg"):
        SurfaceLimits(100.0, 68.0, 1.5, nadir_blind_half_angle_deg=90.0)
    with pytest.raises(ValueError, match="theta_max_floor_deg"):
        SurfaceLimits(100.0, 68.0, 1.5, theta_max_floor_deg=0.0)
    with pytest.raises(ValueError, match="no instrument height"):
        surface_limits(Scanner(0.001, 1.0, 1.0, name="bare"), 100.0, 68.0)
    assert surface_limits(Scanner(0.001, 1.0, 1.0, name="bare"), 100.0, 68.0, 1.2).instrument_height_m == 1.2


@st.composite
def scenes(draw: st.DrawFn) -> tuple[Scene, list[tuple[float, float]], float]:
    """A convex room (a rectangle or a polygon on an ellipse), maybe a box obstacle, stations, limits, a spacing."""
    cx, cy = draw(st.floats(-20, 20)), draw(st.floats(-20, 20))
    if draw(st.booleans()):
        w, h = draw(st.floats(1.0, 10.0)), draw(st.floats(1.0, 10.0))
        ring_ = [(cx, cy), (cx + w, cy), (cx + w, cy + h), (cx, cy + h)]
    else:
        turns = sorted(draw(st.lists(st.floats(0.0, 1.0, exclude_max=True), min_size=3, max_size=7, unique=True)))
        gaps = np.diff([*turns, turns[0] + 1.0])
        assume(gaps.min() > 0.03)
        rx, ry = draw(st.floats(1.0, 6.0)), draw(st.floats(1.0, 6.0))
        ring_ = [(cx + rx * math.cos(2 * math.pi * a), cy + ry * math.sin(2 * math.pi * a)) for a in turns]
    xs, ys = [p[0] for p in ring_], [p[1] for p in ring_]
    x0, y0, w, h = min(xs), min(ys), max(xs) - min(xs), max(ys) - min(ys)
    frac = st.floats(0.0, 1.0)
    box_ = None
    if draw(st.booleans()):
        u0, v0 = draw(frac), draw(frac)
        u1, v1 = draw(st.floats(u0 + 0.05, u0 + 0.6)), draw(st.floats(v0 + 0.05, v0 + 0.6))
        box_ = (x0 + u0 * w, y0 + v0 * h, x0 + u1 * w, y0 + v1 * h)
    stations = [(x0 + draw(frac) * w, y0 + draw(frac) * h) for _ in range(draw(st.integers(1, 4)))]
    maybe_angle = st.none() | st.floats(0.0, 60.0)
    scene = Scene(
        room=ring_,
        floor_level=draw(st.floats(-3.0, 3.0)),
        ceiling=draw(st.none() | st.floats(0.5, 6.0)),
        box=box_,
        box_height=draw(st.floats(0.1, 6.0)),
        ih=draw(st.floats(0.3, 2.5)),
        s_max=draw(st.floats(0.5, 15.0)),
        theta=draw(st.floats(20.0, 89.9)),
        theta_floor=draw(st.none() | st.floats(20.0, 89.9)),
        nadir=draw(maybe_angle),
        zenith=draw(maybe_angle),
    )
    return scene, stations, draw(st.floats(0.5, 2.5))


def build(scene: Scene, shift: tuple[float, float] = (0.0, 0.0)) -> Site:
    move = lambda pts: tuple((x + shift[0], y + shift[1]) for x, y in pts)  # noqa: E731
    zone = room(move(scene.room), floor_level_m=scene.floor_level, ceiling_height_m=scene.ceiling)
    obstacles = () if scene.box is None else (Obstacle("box", move(box(*scene.box)), scene.box_height),)
    return Site("s", (zone,), obstacles=obstacles)


def scene_limits(scene: Scene) -> SurfaceLimits:
    return SurfaceLimits(scene.s_max, scene.theta, scene.ih, scene.theta_floor, scene.nadir, scene.zenith)


@settings(max_examples=60, deadline=None, derandomize=True, database=None)
@given(scenes(), st.tuples(st.floats(-500.0, 500.0), st.floats(-500.0, 500.0)))
def test_the_matrix_equals_a_brute_force_oracle_and_does_not_move_with_the_site(case, shift):
    scene, stations, spacing = case
    site = build(scene)
    t = make_surface_targets(site, spacing)
    xy = np.array(stations)
    m = surface_sight(site, t, xy, np.zeros(len(xy), int), scene_limits(scene)).toarray()
    for s, station in enumerate(stations):
        for k in range(len(t)):
            kind = "floor" if t.kind[k] == FLOOR else "ceiling"
            want = oracle_sees(scene, station, kind, float(t.height_m[k]), list(t.polygon[k].exterior.coords)[:-1])
            if want is not None:
                assert m[s, k] == want, (station, t.label(k), want)
    # the same room, obstacle and stations moved by ``shift``: the same patches, the same entries
    moved = build(scene, shift)
    t2 = make_surface_targets(moved, spacing)
    m2 = surface_sight(moved, t2, xy + shift, np.zeros(len(xy), int), scene_limits(scene)).toarray()
    assert len(t2) == len(t)
    np.testing.assert_array_equal(m2, m)
