"""The 3-D view's scene (:mod:`planner.figures.view3d`) checked by hand: one 10 x 6 m room with 3 m walls (four
wall quads, corner to corner, floor to top; one station covering each wall in one run), floors and ceilings at
their levels, the storey filter's choices, and the fragment's JSON (compact, escaped, no address)."""

from __future__ import annotations

import json
import re
from dataclasses import replace

import numpy as np
import pytest

import planner
from planner.figures.view3d import render_view3d, scene_3d, scene_json, views
from planner.site.model import ScanSide, Site, Zone

ROOM = [("R", "inside", 1, 10, 3, 90, 3), ("R", "inside", 2, 6, 3, 90, 3)] * 2


def room_rows() -> list[tuple]:
    return [(z, s, k, L, h, a, v) for k, (z, s, _, L, h, a, v) in enumerate(ROOM, 1)]


@pytest.fixture
def room(write_csv):
    """The 10 x 6 m room (walls 3 m) planned by greedy: one station in it."""
    site = planner.load_site(write_csv(room_rows()))
    plan = planner.plan_site(site, planner.PlanOptions(method="greedy"))
    return planner.outcome_from_plan(plan)


def test_four_wall_quads_corner_to_corner_floor_to_top(room):
    s = scene_3d(room.site, room.stations, room.coverage.problem)
    corners = [(0, 0), (10, 0), (10, 6), (0, 6)]
    assert len(s.walls) == 4 and [w.wall for w in s.walls] == [1, 2, 3, 4]
    for k, w in enumerate(s.walls):
        np.testing.assert_allclose([w.a, w.b], [corners[k], corners[(k + 1) % 4]], atol=1e-9)
        assert (w.floor_m, w.top_a_m, w.top_b_m) == (0.0, 3.0, 3.0)
        np.testing.assert_allclose(
            w.corners(),
            [(*corners[k], 0), (*corners[(k + 1) % 4], 0), (*corners[(k + 1) % 4], 3), (*corners[k], 3)],
            atol=1e-9,
        )
    assert [w.length_m for w in s.walls] == pytest.approx([10, 6, 10, 6])
    # the table CSV zone has a floor and no ceiling; one frame, one level: one view of everything
    assert [(f.kind, f.level_m) for f in s.surfaces] == [("floor", 0.0)]
    assert [(v.name, v.zones) for v in s.views] == [("all", (0,))]


def test_the_station_covers_each_wall_in_one_run(room):
    s = scene_3d(room.site, room.stations, room.coverage.problem)
    (st,) = s.stations
    assert (st.id, st.label, st.zone) == (room.stations[0].id, "1", 0)
    assert (st.x, st.y) == (room.stations[0].x, room.stations[0].y)
    assert [(c.wall, c.pieces) for c in st.covered] == [(0, 10), (1, 6), (2, 10), (3, 6)]  # 1 m pieces
    assert [c.s0_m for c in st.covered] == [0, 0, 0, 0]
    assert [c.s1_m for c in st.covered] == pytest.approx([10, 6, 10, 6])
    assert st.pieces == 32 == len(room.coverage.targets)
    assert s.covered == st.covered  # one station: the union is its own
    # the part of wall 1 a run covers, from 2 m to 5 m along it, is the quad between those offsets
    np.testing.assert_allclose(s.walls[0].corners(2, 5), [(2, 0, 0), (5, 0, 0), (5, 0, 3), (2, 0, 3)], atol=1e-9)


def test_stations_stand_at_instrument_height_above_their_floor(room):
    s = scene_3d(room.site, room.stations, room.coverage.problem, instrument_height_m=1.6)
    assert (s.stations[0].floor_m, s.stations[0].z_m) == (0.0, 1.6)
    raised = room.site.with_parameters(instrument_height_m=1.2)
    assert scene_3d(raised, room.stations).stations[0].z_m == pytest.approx(1.2)  # the site's, by default
    assert scene_3d(raised, room.stations).stations[0].covered == ()  # no coverage problem: nothing covered


def _storeys() -> Site:
    """Two rooms on one plan frame, a storey apart: floors at 0 and 3 m, ceilings 2.7 and 2.5 m above them."""
    sq = ((0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0))
    lo = Zone("G/a", ScanSide.INSIDE, sq, (2.7,) * 4, frame="G", floor_level_m=0.0, ceiling_height_m=2.7)
    hi = Zone("U/b", ScanSide.INSIDE, sq, (2.5, 2.5, 2.0, 2.0), frame="U", floor_level_m=3.0, ceiling_height_m=2.5)
    return Site("two storeys", (lo, hi))


def test_storeys_floors_ceilings_and_sloped_tops_at_their_levels():
    site = _storeys()
    s = scene_3d(site, ())
    assert [(f.zone, f.kind, f.level_m) for f in s.surfaces] == [
        (0, "floor", 0.0),
        (0, "ceiling", 2.7),
        (1, "floor", 3.0),
        (1, "ceiling", 5.5),
    ]
    upper = [w for w in s.walls if w.zone == 1]
    assert [(w.floor_m, w.top_a_m, w.top_b_m) for w in upper] == [(3, 5.5, 5.5), (3, 5.5, 5), (3, 5, 5), (3, 5, 5.5)]
    assert [(v.name, v.zones) for v in s.views] == [("all storeys", (0, 1)), ("G (0 m)", (0,)), ("U (3 m)", (1,))]


def test_frames_that_are_not_storeys_are_shown_one_at_a_time(write_csv):
    # two table zones, each in its own local frame at level 0: their coordinates are not shared, no "all"
    rows = room_rows() + [("Q", "inside", k, 5, 2, 90, 2) for k in range(1, 5)]
    site = planner.load_site(write_csv(rows))
    assert [z.frame for z in site.zones] == ["R", "Q"]
    assert [(v.name, v.zones) for v in views(site, ())] == [("R", (0,)), ("Q", (1,))]
    # one frame with two levels: all, then each level
    lo, hi = _storeys().zones
    beside = tuple((x + 5, y) for x, y in hi.vertices)  # the same outline twice in one frame is refused
    one_frame = Site("one frame", (replace(lo, frame="F"), replace(hi, frame="F", vertices=beside)))
    assert [v.name for v in views(one_frame, ())] == ["all", "level 0 m", "level 3 m"]


def test_fragment_json_is_compact_escaped_and_has_no_address(room):
    s = scene_3d(room.site, room.stations, room.coverage.problem)
    site = room.site
    text = scene_json(replace(s, title="</script><b>x</b> & co"))
    assert "</script>" not in text and "<" not in text and "&" not in text
    data = json.loads(text)
    assert data["title"] == "</script><b>x</b> & co"
    assert data["walls"][0] == [0, 1, 0, 0, 10, 0, 0, 3, 3]
    assert data["stations"][0][7] == [[0, 0, 10, 10], [1, 0, 6, 6], [2, 0, 10, 10], [3, 0, 6, 6]]
    assert data["surfaces"] == [[0, "f", 0, [[0, 0, 10, 0, 10, 6, 0, 6]]]]
    fragment = render_view3d(s, dom_id="v")
    assert not re.search(r"https?://", fragment, re.IGNORECASE) and "<canvas" in fragment
    assert (
        fragment.count('type="application/json"') == 1
        and site.name in json.loads(fragment.split('class="v3-data">')[1].split("</script>")[0])["title"]
    )


def test_the_inlined_script_cannot_end_its_element():
    from planner.figures.webmap.render import asset

    js = asset("view3d.js", "planner.figures.view3d")
    assert "</script" not in js.lower() and "<!--" not in js and not re.search(r"https?://", js)
