"""The field sheet across storeys (issue 46, step 3; :mod:`planner.field.storeys`): each frame's walks joined by
the stairs, the order, the sheet's files, house2 read with ``--storey all``, and the refusal where no stair
joins the frames.

The hand-checked site (two frames, plan coordinates shared):

- frame ``F1``, zone ``Hall``: 0..10 x 0..4; the stair's footprint 2..6 x 1..2 stands in it (4 m long, 1 m wide,
  rise 3 m), walkable round it in this model (the lower frame knows nothing of the stair);
- frame ``F2``, zone ``Landing``: 6..10 x 0..4, whose west wall x = 6 runs along the stair's east end: that end
  is the head, the west end the foot;
- the ends of the footprint's long axis: (2, 1.5) and (6, 1.5); the foot (2, 1.5) lies in the Hall's walkable
  area; the head moves to the Landing's, past the 0.05 m wall clearance: (6.05, 1.5); the stair leg: run 4.05 m
  (foot to head in plan) + rise 3 m = 7.05 m;
- a walk from a Hall station at (2, 3) to a Landing station at (8, 1.5): 1.5 m to the foot, 7.05 m on the stair,
  1.95 m from the head = 10.5 m.
"""

from __future__ import annotations

import json
import math

import pytest

from planner.core.errors import InfeasibleError
from planner.field.run import FieldOptions, field_plan
from planner.field.sheet import geojson, write_sheet
from planner.field.storeys import directions, flights, joined_frames, stair_ends, storey_spaces, storey_walks
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Site, Zone
from planner.site.stairs import Stair
from tests.conftest import INSTANCES

FOOT = ((2.0, 1.0), (6.0, 1.0), (6.0, 2.0), (2.0, 2.0))
RUN = 4.05  # foot (2, 1.5) to head (6.05, 1.5)
RISE = 3.0


def _zone(zid: str, frame: str, ring: list[tuple[float, float]]) -> Zone:
    return Zone(
        id=zid, scan_side=ScanSide.INSIDE, vertices=tuple(ring), vertex_heights_m=(2.5,) * len(ring), frame=frame
    )


def _site(stairs: bool = True, landing: list[tuple[float, float]] | None = None) -> Site:
    hall = _zone("Hall", "F1", [(0, 0), (10, 0), (10, 4), (0, 4)])
    up = _zone("Landing", "F2", landing or [(6, 0), (10, 0), (10, 4), (6, 4)])
    stair = Stair(name="S1", lower_zone="Hall", upper_zone="Landing", footprint=FOOT, z_min_m=0.0, z_max_m=RISE)
    return Site(name="two storeys", zones=(hall, up), stairs=(stair,) if stairs else ())


def _station(sid: str, zone: str, x: float, y: float) -> Candidate:
    frame = "F1" if zone == "Hall" else "F2"
    return Candidate(id=sid, zone=zone, side=ScanSide.INSIDE, frame=frame, x=x, y=y, kind=CandidateKind.GRID)


STATIONS = [
    _station("h1", "Hall", 2.0, 3.0),
    _station("h2", "Hall", 8.0, 3.0),
    _station("l1", "Landing", 8.0, 1.5),
    _station("l2", "Landing", 8.0, 3.0),
]


def test_stair_ends_and_direction() -> None:
    site = _site()
    assert stair_ends(site.stairs[0]) == ((2.0, 1.5), (6.0, 1.5))
    assert directions(site, site.stairs[0]) == [((2.0, 1.5), (6.0, 1.5))]  # the Landing touches the east end
    (f,) = flights(site, site.stairs[0], storey_spaces(site, ["F1", "F2"], STATIONS))
    assert f.foot == pytest.approx((2.0, 1.5)) and f.head == pytest.approx((6.05, 1.5), abs=1e-5)
    assert f.run_m == pytest.approx(RUN, abs=1e-5) and f.rise_m == RISE and f.length_m == pytest.approx(RUN + RISE)
    # a Landing that touches neither end (east of the stair, apart): the direction is a tie, both flights offered
    apart = _site(landing=[(7, 0), (10, 0), (10, 4), (7, 4)])
    assert len(directions(apart, apart.stairs[0])) == 2


def test_walk_between_storeys_is_the_hand_computed_path() -> None:
    site = _site()
    spaces = storey_spaces(site, ["F1", "F2"], STATIONS)
    w = storey_walks(site, spaces, [s.xy for s in STATIONS], [s.frame for s in STATIONS])
    # h1 -> l1: 1.5 to the foot + 7.05 on the stair + 1.95 from the head
    assert w.dist[0, 2] == pytest.approx(1.5 + RUN + RISE + 1.95, abs=1e-4)
    assert w.dist[0, 2] == pytest.approx(10.5, abs=1e-4)
    # h2 -> l2: (8, 3) to the foot (2, 1.5), the stair, the head (6.05, 1.5) to (8, 3)
    want = math.hypot(6.0, 1.5) + RUN + RISE + math.hypot(1.95, 1.5)
    assert w.dist[1, 3] == pytest.approx(want, abs=1e-4)
    # within a storey: the straight walk
    assert w.dist[0, 1] == pytest.approx(6.0) and w.dist[2, 3] == pytest.approx(1.5)
    pts, frames, used = w.route(0, 2)
    assert [f.stair for f in used] == ["S1"]
    assert pts[0] == (2.0, 3.0) and pts[-1] == (8.0, 1.5)
    assert frames[0] == "F1" and frames[-1] == "F2" and frames.count("F1") == 2  # the station and the foot
    plan = sum(math.dist(p, q) for p, q in zip(pts, pts[1:]))
    assert plan + RISE == pytest.approx(w.dist[0, 2], abs=1e-4)  # the polyline in plan, plus the rise


def test_field_sheet_across_storeys(tmp_path) -> None:
    site = _site()
    fp = field_plan(site, STATIONS, FieldOptions(start="h1"))
    assert sorted(fp.order) == [0, 1, 2, 3] and fp.order[0] == 0
    assert [sp.frame for sp in fp.spaces] == ["F1", "F2"]
    assert len(fp.stair_legs) == 1  # the walk goes up once
    # the route is its legs: each leg's plan length, plus the rise of each stair leg it takes
    walked = sum(sum(math.dist(p, q) for p, q in zip(leg, leg[1:])) for leg in fp.legs)
    assert walked + RISE * len(fp.stair_legs) == pytest.approx(fp.route_length_m, abs=1e-3)
    # the shortest order: h1, h2 along the hall (6), back to the foot (hypot(6, 1.5)), up, then the landing
    best = min(
        6.0 + math.hypot(6.0, 1.5) + RUN + RISE + math.hypot(1.95, 1.5) + 1.5,  # h1 h2 l2 l1 / h1 h2 l1 l2
        6.0 + math.hypot(6.0, 1.5) + RUN + RISE + 1.95 + 1.5,
        1.5 + RUN + RISE + 1.95 + 1.5 + 1.5 + RUN + RISE + math.hypot(6.0, 1.5),  # up and down again
    )
    assert fp.route_length_m == pytest.approx(best, abs=1e-3) and fp.lower_bound_m == pytest.approx(best, abs=1e-3)
    assert sum(s.walk_m for s in fp.time.setups) == pytest.approx(fp.route_length_m, abs=1e-3)
    paths = write_sheet(fp, tmp_path)
    assert [p.name for p in paths] == ["field.html", "field.csv", "field.geojson", "field.json", "field.pdf"]
    assert all(p.stat().st_size > 0 for p in paths)
    d = json.loads((tmp_path / "field.json").read_text())
    assert d["frames"] == ["F1", "F2"] and len(d["stair_legs"]) == 1 and d["stair_legs"][0]["way"] == "up"
    assert d["stair_legs"][0]["length_m"] == pytest.approx(RUN + RISE, abs=1e-5)
    assert [len(f) for f in d["leg_frames"]] == [len(leg) for leg in d["legs"]]
    g = geojson(fp)
    assert {f["properties"]["frame"] for f in g["features"] if f["properties"]["role"] == "route"} == {"F1", "F2"}
    assert [f["properties"]["stair"] for f in g["features"] if f["properties"]["role"] == "stair"] == ["S1"]


def test_frames_no_stair_joins_are_refused() -> None:
    with pytest.raises(InfeasibleError, match="cannot be walked between"):
        field_plan(_site(stairs=False), STATIONS)
    assert joined_frames(_site(stairs=False), ["F1", "F2"]) is None
    assert joined_frames(_site(), ["F1", "F2"]) == ["F1", "F2"]


def test_one_frame_sheet_has_no_storey_fields() -> None:
    """Stations of one frame take the one-frame path: no spaces, no leg frames, no storey keys in field.json
    (the existing sheets of tests/field are unchanged)."""
    from planner.field.record import to_dict

    fp = field_plan(_site(), STATIONS[:2])
    assert fp.spaces == () and fp.leg_frames == () and fp.stair_legs == ()
    d = to_dict(fp)
    assert "frames" not in d and "leg_frames" not in d and "stair_legs" not in d
    assert fp.route_length_m == pytest.approx(6.0)


@pytest.mark.slow
def test_house2_all_storeys_field_sheet(tmp_path) -> None:
    """house2.ifc --storey all: one plan of both storeys, and its field sheet walks up the stair."""
    from planner.cli import main

    plan_dir, sheet = tmp_path / "plan", tmp_path / "field"
    assert main(["plan", str(INSTANCES / "house2.ifc"), "--storey", "all", "--out", str(plan_dir)]) == 0
    assert main(["field", str(plan_dir / "plan.json"), "--out", str(sheet)]) == 0
    d = json.loads((sheet / "field.json").read_text())
    assert set(d["frames"]) == {"Ground floor", "Upper floor"}
    assert len(d["stair_legs"]) >= 1 and {s["stair"] for s in d["stair_legs"]} == {"S-hall-landing"}
    assert len(d["order"]) == len(set(d["order"])) == len(json.loads((plan_dir / "plan.json").read_text())["stations"])
    t = d["time"]
    assert t["total_s"] == pytest.approx(t["walking_s"] + t["station_s"], abs=1e-6)
    walks = sum(float(r["walk m"]) for r in d["setups"])
    assert walks == pytest.approx(d["route_length_m"], abs=0.05 * len(d["setups"]))  # the rows round to 0.1 m
    assert (sheet / "field.pdf").stat().st_size > 0 and (sheet / "field.html").stat().st_size > 0


def test_figure_and_site_map_have_each_storey() -> None:
    """The plan figure: one panel per storey, the stair leg drawn in both; the site map: each stretch of the route in
    its own storey, the stair leg in both, every point of a line where the sheet put it."""
    from planner.field.figure import figure
    from planner.field.site_map import field_site_map

    fp = field_plan(_site(), STATIONS, FieldOptions(start="h1"))
    fig = figure(fp)
    panels = [ax for ax in fig.axes if ax.get_visible()]
    assert [ax.get_title() for ax in panels] == ["F1", "F2"]
    for ax in panels:
        assert any(c.get_gid() == "stair" for c in ax.collections)
    route = field_site_map(fp).route
    assert {ln.frame for ln in route} == {"F1", "F2"}
    stair = [ln for ln in route if ln.label.endswith("stair")]
    assert {ln.frame for ln in stair} == {"F1", "F2"} and len(stair) == 2
    xy = {(round(p[0], 2), round(p[1], 2)) for ln in stair for p in ln.points}
    assert xy == {(2.0, 1.5), (6.05, 1.5)}  # the foot and the head


def test_storeys_walked_through_are_those_between_stations() -> None:
    """Three storeys F1 - F2 - F3 joined by two stairs: stations on F1 and F3 walk through F2; stations on F1 and
    F2 leave F3 out; a storey no stair reaches is refused (None)."""
    hall = _zone("Hall", "F1", [(0, 0), (10, 0), (10, 4), (0, 4)])
    mid = _zone("Mid", "F2", [(0, 0), (10, 0), (10, 4), (0, 4)])
    top = _zone("Top", "F3", [(0, 0), (10, 0), (10, 4), (0, 4)])
    alone = _zone("Shed", "F4", [(20, 0), (24, 0), (24, 4), (20, 4)])
    s1 = Stair(name="S1", lower_zone="Hall", upper_zone="Mid", footprint=FOOT, z_min_m=0.0, z_max_m=3.0)
    s2 = Stair(name="S2", lower_zone="Mid", upper_zone="Top", footprint=FOOT, z_min_m=3.0, z_max_m=6.0)
    site = Site(name="three storeys", zones=(hall, mid, top, alone), stairs=(s1, s2))
    assert joined_frames(site, ["F1", "F3"]) == ["F1", "F2", "F3"]
    assert joined_frames(site, ["F1", "F2"]) == ["F1", "F2"]
    assert joined_frames(site, ["F1", "F4"]) is None


def test_walk_through_a_storey_between() -> None:
    """Stations on F1 (2, 3) and F3 (8, 3) of three storeys, both stairs on the footprint 2..6 x 1..2 inside the
    rooms (no outline meets an end: a tie, both directions offered), each 4 + 3 = 7 m: the shortest walk takes S1
    from (6, 1.5) up to (2, 1.5), S2 from there up to (6, 1.5): hypot(4, 1.5) + 7 + 0 + 7 + hypot(2, 1.5)."""
    hall = _zone("Hall", "F1", [(0, 0), (10, 0), (10, 4), (0, 4)])
    mid = _zone("Mid", "F2", [(0, 0), (10, 0), (10, 4), (0, 4)])
    top = _zone("Top", "F3", [(0, 0), (10, 0), (10, 4), (0, 4)])
    s1 = Stair(name="S1", lower_zone="Hall", upper_zone="Mid", footprint=FOOT, z_min_m=0.0, z_max_m=3.0)
    s2 = Stair(name="S2", lower_zone="Mid", upper_zone="Top", footprint=FOOT, z_min_m=3.0, z_max_m=6.0)
    site = Site(name="three storeys", zones=(hall, mid, top), stairs=(s1, s2))
    st = [
        Candidate(id="a", zone="Hall", side=ScanSide.INSIDE, frame="F1", x=2.0, y=3.0, kind=CandidateKind.GRID),
        Candidate(id="b", zone="Top", side=ScanSide.INSIDE, frame="F3", x=8.0, y=3.0, kind=CandidateKind.GRID),
    ]
    fp = field_plan(site, st, FieldOptions(start="a"))
    assert fp.route_length_m == pytest.approx(math.hypot(4, 1.5) + 7.0 + 7.0 + math.hypot(2, 1.5), abs=1e-6)
    assert [f.stair for _, f in fp.stair_legs] == ["S1", "S2"] and [sp.frame for sp in fp.spaces] == ["F1", "F2", "F3"]
