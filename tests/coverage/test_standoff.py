"""Stand-off: no station or proposed control point closer than min_standoff_m to a wall or obstacle."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import shapely

from planner.coverage.matrix import station_places
from planner.coverage.sight import Sight
from planner.engine import plan_site
from planner.io import load_site
from planner.network.check import run_network
from planner.plan import PlanOptions
from planner.plan.verify import verify_stations
from planner.site import ScanSide
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import SITE_FRAME, Site, Zone
from tests.conftest import INSTANCES


def _room(standoff: float) -> Site:
    z = Zone("R", ScanSide.INSIDE, ((0, 0), (20, 0), (20, 20), (0, 20)), (3.0,) * 4)
    site = Site("room", (z,), instrument="dissertation-tables")
    return replace(site, parameters=replace(site.parameters, min_standoff_m=standoff))


def test_station_places_refuses_a_point_inside_the_standoff_with_the_reason():
    site = _room(0.4)
    xy = np.array([[10.0, 0.022], [10.0, 0.39], [10.0, 0.41], [10.0, 10.0]])
    places = station_places(site, xy, [SITE_FRAME] * 4)
    assert places.reason[0] == "0.022 m from a wall of zone R (stand-off 0.4 m)"
    assert "stand-off" in places.reason[1]
    assert places.reason[2] == "" and places.reason[3] == ""
    # stand-off 0 keeps the old rule: only a point on the wall line stands nowhere
    assert station_places(_room(0.0), xy, [SITE_FRAME] * 4).reason[0] == ""


def test_verify_flags_a_station_2_cm_from_a_wall():
    site = _room(0.4)
    near = Candidate("S1", "R", ScanSide.INSIDE, SITE_FRAME, 10.0, 0.02, CandidateKind.GRID)
    report = verify_stations(Sight.of_site(site), [near], 0.5)
    assert report.misplaced == (("S1", "0.020 m from a wall of zone R (stand-off 0.4 m)"),)
    assert not report.complete


def _clearance(site: Site, xy: tuple[float, float], frame: str) -> float:
    """Distance to the nearest wall of a zone drawn in ``frame`` or (site frame) obstacle edge."""
    edges = [z.polygon.boundary for z in site.zones if z.frame == frame]
    edges += [shapely.Polygon(o.vertices).boundary for o in site.obstacles] if frame == SITE_FRAME else []
    return min(shapely.distance(e, shapely.Point(xy)) for e in edges)


@pytest.mark.parametrize("standoff", [0.4, pytest.param(1.5, marks=pytest.mark.slow)])
def test_no_station_or_proposed_control_point_within_the_standoff(standoff):
    site = load_site(INSTANCES / "courtyard.json")  # three zones and a column (obstacle)
    site = replace(site, control_points=(), parameters=replace(site.parameters, min_standoff_m=standoff))
    plan = plan_site(site, PlanOptions(method="greedy"))
    assert plan.verification.complete
    assert all(_clearance(site, s.xy, s.frame) >= standoff for s in plan.stations)
    network = run_network(site, list(plan.stations))
    proposed = [c for c in network.control if c.proposed]
    assert proposed and all(_clearance(site, (c.x, c.y), c.frame) >= standoff for c in proposed)
