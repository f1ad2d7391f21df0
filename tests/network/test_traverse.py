"""Total-station observations only on a planned control traverse; two rooms joined through a door.

Rooms A (0..10 x 0..8 m) and B (10..20 x 0..8 m) share the wall x = 10, with a 2 m door in it
(y 3..5). Station S1 (3, 7) stands in A, S2 (17, 7) in B: the line between them meets the wall at
y = 7, beside the door, so they do not see each other and no registration link joins them. Control
C0 (1, 4) and C1 (5, 4) in A are fixed; C2 (15, 4) in B has coordinates good to 50 mm only.
"""

from __future__ import annotations

import json
import math
import re

import pytest

from planner.cli import main
from planner.core.errors import InputError
from planner.network.check import run_network
from planner.network.traverse import NO_TRAVERSE, ControlTraverse, read_traverse
from planner.site import ScanSide, Site, Zone
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ControlPoint, Opening

TS_KINDS = {"sight", "delaunay", "traverse"}


def two_rooms(control: tuple[ControlPoint, ...] = ()) -> Site:
    a = Zone(
        "A",
        ScanSide.INSIDE,
        ((0, 0), (10, 0), (10, 8), (0, 8)),
        (3.0,) * 4,
        openings=(Opening(2, 3.0, 5.0, "door", "A-B"),),
    )
    b = Zone("B", ScanSide.INSIDE, ((10, 0), (20, 0), (20, 8), (10, 8)), (3.0,) * 4)
    return Site("two rooms", (a, b), instrument="dissertation-tables", control_points=control)


STATIONS = [
    Candidate("S1", "A", ScanSide.INSIDE, "site", 3, 7, CandidateKind.GRID),
    Candidate("S2", "B", ScanSide.INSIDE, "site", 17, 7, CandidateKind.GRID),
]
CONTROL = (
    ControlPoint("C0", 1, 4),
    ControlPoint("C1", 5, 4),
    ControlPoint("C2", 15, 4, sigma_x_m=0.05, sigma_y_m=0.05),
)
# the planned traverse: back-sight C0 - C1, then C1 - T1 (in the door) - C2, two legs of 5 m
LEGS = ControlTraverse((ControlPoint("T1", 10, 4),), (("C0", "C1"), ("C1", "T1"), ("T1", "C2")), False, "test")


def _station_ts_edges(rep) -> list[tuple[str, str]]:
    g = rep.graph
    return [
        (u, v)
        for u, v, d in g.edges(data=True)
        if d["kinds"] & TS_KINDS and g.nodes[u]["kind"] == "station" and g.nodes[v]["kind"] == "station"
    ]


def test_one_traverse_leg_pair_through_the_door_makes_one_network():
    rep = run_network(two_rooms(CONTROL), STATIONS, traverse=LEGS)
    assert len(rep.diagnostics.components) == 1
    g = rep.graph
    assert g.edges["C1", "T1"]["kinds"] == {"traverse"} and g.edges["C1", "T1"]["length_m"] == pytest.approx(5.0)
    assert g.edges["T1", "C2"]["length_m"] == pytest.approx(5.0)
    # S1 is 3.61 m from C1 (sqrt(2^2 + 3^2)), S2 3.61 m from C2: each tied, no station-to-station line
    assert g.edges["S1", "C1"]["kinds"] == {"tie"} and g.edges["S1", "C1"]["length_m"] == pytest.approx(math.sqrt(13))
    assert not g.has_edge("S1", "S2") and not _station_ts_edges(rep)
    # C2 from the fixed C1 through two 5 m legs (2 mm, 5"), oriented on C0: far better than its own 50 mm,
    # so S2 is held to a few mm, not to 50
    assert rep.station_sigma_m["S2"] < 0.01


def test_a_traverse_without_a_starting_azimuth_leaves_the_far_room_loose():
    # without the back-sight C0 - C1, one direction at C1 only fixes C1's orientation unknown: the
    # traverse may turn about C1, and C2 (so S2) rests on C2's own 50 mm coordinates
    legs = ControlTraverse(LEGS.points, LEGS.legs[1:], False, "test")
    rep = run_network(two_rooms(CONTROL), STATIONS, traverse=legs)
    assert len(rep.diagnostics.components) == 1
    assert rep.station_sigma_m["S2"] > 0.04


def test_without_the_traverse_the_rooms_are_two_networks():
    rep = run_network(two_rooms(CONTROL), STATIONS, traverse=NO_TRAVERSE)
    assert sorted(map(sorted, rep.diagnostics.components)) == [["C0", "C1", "S1"], ["C2", "S2"]]
    assert not any(d["kinds"] & TS_KINDS for _, _, d in rep.graph.edges(data=True))
    # S2 now rests on C2's 50 mm alone
    assert rep.station_sigma_m["S2"] > 0.04


def test_proposed_traverse_runs_through_the_door():
    rep = run_network(two_rooms(), STATIONS)
    assert len(rep.diagnostics.components) == 1
    tp = [n for n in rep.graph if n.startswith("TP.")]
    assert len(tp) == 1 and (rep.graph.nodes[tp[0]]["x"], rep.graph.nodes[tp[0]]["y"]) == pytest.approx((10.0, 4.0))
    assert not _station_ts_edges(rep)
    assert any("control traverse (PROPOSED" in n for n in rep.notes)


def test_ts_everywhere_keeps_the_earlier_design():
    rep = run_network(two_rooms(CONTROL), STATIONS, ts_everywhere=True)
    kinds = {k for _, _, d in rep.graph.edges(data=True) for k in d["kinds"]}
    assert "sight" in kinds and "traverse" not in kinds and "tie" not in kinds


def test_traverse_file_and_its_errors(tmp_path, capsys):
    path = tmp_path / "t.json"
    path.write_text(json.dumps({"points": [{"name": "T1", "x": 10, "y": 4}], "legs": [["C1", "T1"], ["T1", "C2"]]}))
    t = read_traverse(path)
    assert t.legs == (("C1", "T1"), ("T1", "C2")) and not t.proposed
    path.write_text(json.dumps({"legs": [["C1", "C1"]]}))
    with pytest.raises(InputError, match="two different names"):
        read_traverse(path)
    path.write_text(json.dumps({"legs": [["C1", "X9"]]}))
    with pytest.raises(InputError, match="names no control or traverse point"):
        run_network(two_rooms(CONTROL), STATIONS, traverse=read_traverse(path))
    # a typo in a key, or a coordinate in quotes, is refused (the value was dropped or converted before)
    for data, words in (
        ({"legs": [], "extra": 1}, "traverse: extra = 1: unknown key"),
        ({"points": [{"name": "T1", "x": 10, "y": 4, "colour": 1}], "legs": []}, "points[1]: colour = 1"),
        ({"points": [{"name": "T1", "x": "10", "y": 4}], "legs": []}, "x = '10': must be a number, not text"),
    ):
        path.write_text(json.dumps(data))
        with pytest.raises(InputError, match=re.escape(words)):
            read_traverse(path)
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"stations": [{"id": "S", "zone": "B", "side": "inside", "x": 50, "y": 40}]}))
    from tests.conftest import INSTANCES

    assert (
        main(["network", str(INSTANCES / "polygon_b.json"), str(plan), "--traverse", str(path), "--ts-everywhere"]) == 2
    )


def test_the_proposed_traverse_goes_round_a_building():
    # a block 20 x 8 m scanned from outside by S1 in front (10, -6) and S2 behind (10, 14): the block hides
    # them from each other, so each has control of its own; the traverse joins the two through points
    # 3 m out from the block's corners
    block = Zone("block", ScanSide.OUTSIDE, ((0, 0), (20, 0), (20, 8), (0, 8)), (3.0,) * 4)
    site = Site("block", (block,), instrument="dissertation-tables")
    stations = [
        Candidate("S1", "block", ScanSide.OUTSIDE, "site", 10, -6, CandidateKind.GRID),
        Candidate("S2", "block", ScanSide.OUTSIDE, "site", 10, 14, CandidateKind.GRID),
    ]
    rep = run_network(site, stations)
    ring = [n for n in rep.graph if n.startswith("RP.")]
    assert len(rep.diagnostics.components) == 1 and ring
    for n in ring:  # 3 m from a corner on its bisector: 3 / sqrt(2) = 2.121 m out in x and in y
        x, y = rep.graph.nodes[n]["x"], rep.graph.nodes[n]["y"]
        assert min(abs(x - cx) for cx in (0, 20)) == pytest.approx(3 / math.sqrt(2))
        assert min(abs(y - cy) for cy in (0, 8)) == pytest.approx(3 / math.sqrt(2))
    assert not _station_ts_edges(rep)
    assert len(run_network(site, stations, traverse=NO_TRAVERSE).diagnostics.components) == 2


def test_traverse_names_that_would_merge_points_are_refused(tmp_path):
    # A traverse point named like a control point (C1), or two traverse points of one name, would merge
    # into one network node (4 nodes instead of 5 before): refused, naming the file, the point and the name.
    # "points": null is no list of points.
    path = tmp_path / "t.json"
    cases = (
        (
            {"points": [{"name": "C1", "x": 10, "y": 2}], "legs": [["C1", "C2"]]},
            "points[1]: name = 'C1': names a control point",
        ),
        (
            {"points": [{"name": "T1", "x": 10, "y": 4}, {"name": "T1", "x": 15, "y": 4}], "legs": []},
            "points[2]: name = 'T1': traverse point name used twice (also points[1])",
        ),
        ({"points": None, "legs": []}, "points: must be a list"),
    )
    for data, words in cases:
        path.write_text(json.dumps(data))
        with pytest.raises(InputError, match=re.escape(words)) as err:
            run_network(two_rooms(CONTROL), STATIONS, traverse=read_traverse(path))
        assert str(path) in str(err.value)


def test_an_observation_sigma_below_a_micrometre_is_refused(tmp_path):
    # sigma 1e-300 m: 1/sigma^2 is 1e600, no float (ZeroDivisionError before). The least sigma is 1 um
    # (MIN_SIGMA_M); in mm that is 0.001 mm, and the message says it in the file's unit.
    from planner.network.adjustment import Obs, adjust

    coords = {"A": (0.0, 0.0), "B": (10.0, 0.0)}
    with pytest.raises(InputError, match=re.escape("sigma must be at least 0.001 mm, got 1e-300")):
        adjust(coords, ["A"], [Obs("distance", "A", "B", 10000.0, 1e-300)], observed=True, length_unit="mm")
