"""Floor and ceiling patches (planner.coverage.surfaces) counts, areas, blocks cut out, heights, normals."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from planner.coverage.surfaces import CEILING, FLOOR, make_surface_targets
from planner.io.load import load_site
from planner.site.model import NoGoArea, Obstacle, Site, Zone
from tests.conftest import square_rows

RECT = ((0.0, 0.0), (10.0, 0.0), (10.0, 6.0), (0.0, 6.0))
#: an L: 10 x 4 along the bottom and 4 x 6 up the left arm, 40 + 24 = 64 m2
ELL = ((0.0, 0.0), (10.0, 0.0), (10.0, 4.0), (4.0, 4.0), (4.0, 10.0), (0.0, 10.0))


def room(vertices=RECT, zone_id: str = "R", **kw) -> Zone:
    return Zone(zone_id, "inside", vertices, (5.0,) * len(vertices), **kw)


def box(x0: float, y0: float, x1: float, y1: float) -> tuple[tuple[float, float], ...]:
    return ((x0, y0), (x1, y0), (x1, y1), (x0, y1))


def test_a_10_by_6_room_at_1_m_is_60_floor_patches_of_1_m2_and_no_ceiling():
    t = make_surface_targets(Site("s", (room(),)), 1.0)
    # 10 columns x 6 rows of 1 m x 1 m cells, all inside: 60 patches of 1 m2, 60 m2 in all; no ceiling given
    assert len(t) == 60 and set(t.kind.tolist()) == {FLOOR}
    np.testing.assert_allclose(t.area_m2, 1.0)
    assert t.total_area_m2() == pytest.approx(60.0)
    np.testing.assert_array_equal(t.normal, np.tile([0.0, 0.0, 1.0], (60, 1)))
    assert np.all(t.height_m == 0.0) and np.all(t.n_corners == 4)
    assert sorted(map(tuple, t.cell.tolist())) == [(i, j) for i in range(10) for j in range(6)]
    assert t.label(0) == "R/floor cell 0,0 at 0.50, 0.50 m"
    with pytest.raises(ValueError):
        t.area_m2[0] = 2.0  # read-only arrays


def test_a_ceiling_is_a_second_layer_at_floor_level_plus_its_height():
    t = make_surface_targets(Site("s", (room(floor_level_m=-2.0, ceiling_height_m=3.5),)), 1.0)
    floor, ceiling = t.kind == FLOOR, t.kind == CEILING
    assert floor.sum() == ceiling.sum() == 60
    # the floor at -2 m, the ceiling 3.5 m above it: -2 + 3.5 = 1.5 m; the ceiling's normal looks down
    assert set(t.height_m[floor].tolist()) == {-2.0} and set(t.height_m[ceiling].tolist()) == {1.5}
    np.testing.assert_array_equal(t.normal[ceiling], np.tile([0.0, 0.0, -1.0], (60, 1)))
    assert len(make_surface_targets(Site("s", (room(ceiling_height_m=3.5),)), 1.0, kinds=("floor",))) == 60


@pytest.mark.parametrize("spacing", [1.0, 1.5, 0.7])
def test_an_l_shaped_room_sums_to_its_area_in_patches_no_wider_than_the_spacing(spacing):
    t = make_surface_targets(Site("s", (room(ELL),)), spacing)
    # 64 m2 whatever the grid (at 1 m: 64 whole cells; at 1.5 m the 10 x 10 box is cut into 7 x 7 cells of 1.4286 m,
    # clipped at the inner corner (4, 4)); every patch's box no wider than the spacing
    assert t.total_area_m2() == pytest.approx(64.0, abs=1e-9)
    bounds = shapely.bounds(t.polygon)
    assert np.all(bounds[:, 2] - bounds[:, 0] <= spacing + 1e-12) and np.all(
        bounds[:, 3] - bounds[:, 1] <= spacing + 1e-12
    )
    if spacing == 1.0:
        assert len(t) == 64
    union = shapely.union_all(t.polygon)
    assert union.symmetric_difference(shapely.Polygon(ELL)).area == pytest.approx(0.0, abs=1e-9)


def test_floor_under_an_obstacle_or_a_hole_is_no_target_and_no_go_areas_stay():
    ob = Obstacle("plinth", box(3.0, 2.0, 5.0, 3.0), 1.0)  # 2 m x 1 m = 2 m2, 1 m high
    column = Obstacle("column", box(6.2, 2.2, 6.6, 2.6), 3.0)  # 0.4 x 0.4 = 0.16 m2 inside one cell
    pier = room(holes=(box(8.0, 4.0, 9.0, 5.0)[::-1],), hole_heights_m=((3.0,) * 4,), ceiling_height_m=3.0)
    site = Site("s", (pier,), obstacles=(ob, column), no_go_areas=(NoGoArea("lawn", box(0.0, 0.0, 2.0, 2.0)),))
    t = make_surface_targets(site, 1.0)
    floor = t.kind == FLOOR
    # floor: 60 - 2 (plinth) - 0.16 (column) - 1 (pier) = 56.84 m2; the lawn (a no-go area) is floor
    assert t.total_area_m2(kind=FLOOR) == pytest.approx(56.84)
    blocks = shapely.union_all([shapely.Polygon(ob.vertices), shapely.Polygon(column.vertices)])
    assert shapely.area(shapely.intersection(t.polygon[floor], blocks)).max() == pytest.approx(0.0, abs=1e-12)
    # ceiling 3 m: the 1 m plinth leaves the ceiling above it, the 3 m column and pier reach it: 60 - 0.16 - 1
    assert t.total_area_m2(kind=CEILING) == pytest.approx(58.84)
    # no patch holds a hole: the cell round the column is cut through the column's centroid, into two patches
    assert all(len(p.interiors) == 0 for p in t.polygon)
    around = [k for k in np.flatnonzero(floor) if tuple(t.cell[k]) == (6, 2)]
    assert len(around) == 2 and sum(t.area_m2[around]) == pytest.approx(1.0 - 0.16)


def test_corners_are_each_patchs_own_vertices_padded_by_the_last():
    site = Site("s", (room(),), obstacles=(Obstacle("column", box(6.2, 2.2, 6.6, 2.6), 3.0),))
    t = make_surface_targets(site, 1.0)
    k_max = int(t.n_corners.max())
    assert t.corners.shape == (len(t), k_max, 2) and k_max > 4
    for k in range(len(t)):
        own = np.asarray(t.polygon[k].exterior.coords)[:-1]
        n = int(t.n_corners[k])
        np.testing.assert_array_equal(t.corners[k, :n], own)
        np.testing.assert_array_equal(t.corners[k, n:], np.repeat(own[-1:], k_max - n, axis=0))


def test_outside_zones_and_table_csvs(write_csv):
    outside = Zone("O", "outside", box(20.0, 0.0, 30.0, 6.0), (5.0,) * 4, ceiling_height_m=3.0)
    assert len(make_surface_targets(Site("s", (outside,)), 1.0)) == 0  # a building's outline has no floor here
    site = load_site(write_csv(square_rows()))  # a 10 m square table zone: floor at 0, no ceiling
    t = make_surface_targets(site, 2.0)
    assert len(t) == 25 and set(t.kind.tolist()) == {FLOOR} and t.frames == ("S",)


def test_obstacles_cut_only_zones_in_the_site_frame():
    own_frame = Zone("T", "inside", RECT, (5.0,) * 4, frame="T")  # a table zone in its own frame
    t = make_surface_targets(Site("s", (own_frame,), obstacles=(Obstacle("c", box(3, 2, 5, 3), 2.0),)), 1.0)
    assert t.total_area_m2() == pytest.approx(60.0)


def test_translation_moves_the_patches_and_nothing_else():
    shift = np.array([1234.25, -567.5])
    moved = tuple(tuple(np.add(v, shift)) for v in ELL)
    a, b = (make_surface_targets(Site("s", (room(v),)), 1.5) for v in (ELL, moved))
    assert len(a) == len(b)
    np.testing.assert_allclose(b.centroid - shift, a.centroid, atol=1e-9)
    np.testing.assert_allclose(b.area_m2, a.area_m2, atol=1e-9)
    np.testing.assert_array_equal(b.cell, a.cell)


def test_slivers_are_dropped_and_bad_arguments_refused():
    # a 10 x 6 room whose upper half starts at x = 1.99999: the column 1..2 keeps a 0.00001 x 1 m strip in each of the 3
    # upper rows, 1e-5 m2 < SLIVER_SHARE x 1 m2, dropped: 30 + 3 x 8 = 54 whole cells, 54.00003 - 3e-5 m2
    notched = ((0.0, 0.0), (10.0, 0.0), (10.0, 6.0), (1.99999, 6.0), (1.99999, 3.0), (0.0, 3.0))
    t = make_surface_targets(Site("s", (room(notched),)), 1.0)
    assert shapely.Polygon(notched).area == pytest.approx(54.00003)
    assert len(t) == 54 and t.total_area_m2() == pytest.approx(54.0) and t.area_m2.min() == pytest.approx(1.0)
    for bad in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="spacing"):
            make_surface_targets(Site("s", (room(),)), bad)
    with pytest.raises(ValueError, match="roof"):
        make_surface_targets(Site("s", (room(),)), 1.0, kinds=("floor", "roof"))
