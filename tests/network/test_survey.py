"""The network as surveyed: registration links across a site's doors, ties to control, one network."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from planner.candidates.pool import PoolOptions
from planner.cli import main
from planner.coverage.matrix import build_coverage
from planner.coverage.targets import make_targets
from planner.coverage.visibility import sight_limits
from planner.engine import plan_site
from planner.io.load import load_site
from planner.network.chain import TIE_RANGE_M, control_count
from planner.network.check import run_network
from planner.network.survey import registration_links, survey_network
from planner.plan import PlanOptions
from planner.site import ScanSide
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ControlPoint
from planner.site.validate import validate_site
from tests.conftest import INSTANCES

HOUSE = INSTANCES / "house_doors.json"
# one station in each room of the house, in line with the doors (R1-R2 door at x = 10, y 3.0..4.5;
# R2-R3 door at x = 20, y 3.5..5.0), and one outside in front of the front door (y = 0, x 4.0..5.5)
STATIONS = [
    Candidate("S1", "R1", ScanSide.INSIDE, "site", 5.0, 4.0, CandidateKind.GRID),
    Candidate("S2", "R2", ScanSide.INSIDE, "site", 15.0, 4.0, CandidateKind.GRID),
    Candidate("S3", "R3", ScanSide.INSIDE, "site", 25.0, 4.2, CandidateKind.GRID),
    Candidate("S0", "house", ScanSide.OUTSIDE, "site", 4.7, -6.0, CandidateKind.GRID),
]


def test_rooms_link_only_through_their_doors_in_site_mode():
    site = load_site(HOUSE)
    site_links = {tuple(sorted(p)) for p in registration_links(site, STATIONS, "site")}
    # S1-S2 meets x = 10 at y = 4.0 (door 3.0..4.5); S2-S3 meets x = 20 at y = 4.1 (door 3.5..5.0);
    # S0-S1 meets y = 0 at x = 4.7 + 0.3 * 6/10 = 4.88 (front door 4.0..5.5); S1-S3 passes both inner doors
    # (x = 10 at y = 4.05, x = 20 at y = 4.15), 20 m long; S0-S2 meets y = 0 at x = 10.88 and S0-S3 at
    # x = 16.9: front wall
    assert site_links == {("S1", "S2"), ("S2", "S3"), ("S1", "S3"), ("S0", "S1")}
    # zone mode: one bundle per zone-side, so no station has a partner
    assert registration_links(site, STATIONS, "zone") == []


def test_house_survey_is_one_network_tied_by_the_field_rules():
    site = load_site(HOUSE)
    net = survey_network(site, STATIONS, "site")
    assert len(net.parts) == 1 and net.proposed
    # chain = the minimum spanning tree of the links: S0-S1 (10.0 m), S1-S2 (10 m), S2-S3 (10.0 m), 30 m:
    # at least 3 control points (one per 50 m of chain would be 1)
    assert len(net.ties) == control_count(30.0) == 3
    assert net.chain.untied == () and set(net.chain.sigma_m) == {s.id for s in STATIONS}
    # every station is at most one registration link from a tied station
    assert max(net.chain.links_from_control.values()) <= 2
    zone = survey_network(site, STATIONS, "zone")
    assert len(zone.parts) == 4  # no links: four parts, each held by ties of its own


def test_given_control_ties_stations_within_range_and_sight():
    site = load_site(HOUSE)
    cp = ControlPoint("K", 5.0, 7.0, sigma_x_m=0.003, sigma_y_m=0.003)  # in R1, 3 m from S1
    site = replace(site, control_points=(cp,))
    net = survey_network(site, STATIONS, "site")
    # S1 sees K (3 m); S2 (10.4 m) is behind the wall x = 10 above the door (the line meets x = 10 at y = 5.5);
    # S0 sees K through the front door (meets y = 0 at x = 4.84), 13.0 m; S3 is 20.1 m off (beyond 20 m)
    assert set(net.ties) == {"S0", "S1"} and not net.proposed
    assert all(math.dist((s.x, s.y), (cp.x, cp.y)) <= TIE_RANGE_M for s in STATIONS if s.id in net.ties)
    # the chain grows away from the tie: S3 (two doors away) is the weakest
    assert net.chain.worst[0] == "S3" and net.chain.sigma_m["S3"] > net.chain.sigma_m["S2"] > net.chain.sigma_m["S1"]


@pytest.mark.slow
def test_house_plan_network_is_one_network_and_the_cli_prints_the_chain(tmp_path, capsys):
    site = load_site(HOUSE)
    plan = plan_site(site, PlanOptions(method="milp", pool=PoolOptions(grid_spacing_m=2.0)))
    report = run_network(site, list(plan.stations))
    assert len(report.diagnostics.components) == 1
    assert report.survey is not None and len(report.survey.parts) == 1
    assert "survey network: 1 registration part(s)" in report.summary()
    assert report.to_dict()["survey"]["parts"] == [sorted(s.id for s in plan.stations)]


def test_coverage_refuses_a_station_off_its_own_zone_side():
    # with zones in one frame, a point made for R1 that lies in R2 must not cover R2's walls under R1's name
    site = load_site(HOUSE)
    limits = sight_limits(validate_site(site), False, True)
    bad = Candidate("R1-in-X", "R1", ScanSide.INSIDE, "site", 15.0, 4.0, CandidateKind.FIELD)
    good = Candidate("R2-in-X", "R2", ScanSide.INSIDE, "site", 15.0, 4.0, CandidateKind.FIELD)
    p = build_coverage(site, [bad, good], make_targets(site, 1.0), limits)
    assert p.excluded == {0: "not inside zone R1"}
    assert p.by_candidate[0].nnz == 0 and p.by_candidate[1].nnz > 0


@pytest.mark.parametrize("argv", [["--registration", "zone"], []])
def test_cli_chain(tmp_path, capsys, argv):
    plan = tmp_path / "plan.json"
    plan.write_text(
        '{"stations": ['
        + ", ".join(
            f'{{"id": "{s.id}", "zone": "{s.zone}", "side": "{s.side.value}", "x": {s.x}, "y": {s.y}}}'
            for s in STATIONS
        )
        + "]}"
    )
    assert main(["chain", str(HOUSE), str(plan), *argv]) == 0
    out = capsys.readouterr().out
    parts = 4 if argv else 1
    assert f"survey network: {parts} registration part(s)" in out and "registration chain: worst station" in out


@pytest.mark.slow
@pytest.mark.heavy
def test_assembled_temple_with_doors_is_one_network():
    # baalbek_site_doors.json: the assembled temple (all eleven rooms and the outline placed) with one ASSUMED
    # 3 m door in each matched wall and each collinear contact (scripts/make/make_baalbek_doors.py): one accessible
    # area, so one registration bundle
    site = load_site(INSTANCES / "baalbek_site_doors.json")
    plan = plan_site(site, PlanOptions(method="milp", registration="site", pricing=False))
    assert len(plan.registration) == 1 and set(plan.registration.values()) == {1}
    assert plan.verification.complete
    report = run_network(site, list(plan.stations))
    assert len(report.diagnostics.components) == 1  # one network over the whole temple
    g = report.graph
    # total-station observations only on the proposed control traverse, through the doors
    for u, v, d in g.edges(data=True):
        if g.nodes[u]["kind"] == "station" and g.nodes[v]["kind"] == "station":
            assert d["kinds"] == {"registration"}
        if d["kinds"] & {"traverse"}:
            assert g.nodes[u]["kind"] == g.nodes[v]["kind"] == "control"
    assert sum(n.startswith("TP.") for n in g) == len([o for z in site.zones for o in z.openings])
    assert report.survey is not None and len(report.survey.parts) == 1
    assert report.survey.chain.untied == ()
