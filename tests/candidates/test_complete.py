"""Complete candidates: no coverable piece refused, narrow rooms planned, refusals with reasons.

The corridor: 200 m x 8 m, walls 3 m, theta_max 68 deg. From its centre line (4 m off each wall) a station sees 4 tan 68
= 9.90 m either way along both walls, a window of 19.80 m holding 19 whole 1-m pieces; ceil(200 / 19) = 11 windows, so
11 stations on the centre line (at x = 9.5 + 19 k, k = 0..9, and one in [190.1, 198.4] for the last pieces and the end
wall). The landed planner refused it (212 pieces "seen by no candidate": the 10-m grid's rows missed it).

The 8 x 4 m room at theta_max 45 deg: a station at (2, 2) is 2 m from three walls and sees 2 tan 45 = 2 m either way, so
it covers the left 4 x 4 square; (6, 2) the right one: 2 stations. The landed plane bound said 3 (the weight on the
45-deg diagonals, where regions only touch, was missed).
"""

from __future__ import annotations

import numpy as np
import pytest

from planner.candidates.axis import maximal_cells, medial_axis
from planner.core.errors import InfeasibleError
from planner.engine import plan_site
from planner.plan import PlanOptions, build_problem
from planner.site.model import Obstacle, ScanSide, Site, Zone
from planner.site.params import Parameters
from planner.solve.milp import MilpOptions

PLAIN = PlanOptions(method="milp", milp=MilpOptions(overlap=None))


def box_zone(w: float, h: float, height: float = 3.0, side: ScanSide = ScanSide.INSIDE) -> Zone:
    return Zone("R", side, ((0.0, 0.0), (w, 0.0), (w, h), (0.0, h)), (height,) * 4)


@pytest.mark.slow  # tests/bounds/test_plane.py's rectangles and combs are the quick proofs over the plane
def test_corridor_plans_eleven_stations_proven_over_the_plane() -> None:
    site = Site("corridor", (box_zone(200.0, 8.0),), Parameters(theta_max_deg=68.0, overlap=0.0))
    plan = plan_site(site, PLAIN)
    assert len(plan.stations) == 11  # ceil(200 / 19), see the module docstring
    assert plan.result.info["bound_scope"] == "plane" and plan.result.info["plane_bound"] == 11
    assert plan.verification.percent == pytest.approx(100.0)


def test_room_8_by_4_at_45_deg_gets_two_stations_with_a_plane_certificate() -> None:
    site = Site("room", (box_zone(8.0, 4.0),), Parameters(theta_max_deg=45.0, overlap=0.0))
    plan = plan_site(site, PlanOptions(method="milp", precision=False, milp=MilpOptions(overlap=None)))
    assert len(plan.stations) == 2
    assert plan.result.info["bound_scope"] == "plane" and plan.result.info["plane_bound"] == 2
    assert plan.verification.percent == pytest.approx(100.0)


@pytest.mark.parametrize("width", [pytest.param(1.5, marks=pytest.mark.slow), 2.3, 4.0, 7.7])
def test_narrow_rooms_at_any_angle_are_never_refused(width: float) -> None:
    # a 60 m room of each width, turned 17 deg off the frame's axes: a grid's rows miss such rooms
    c, s = np.cos(np.radians(17.0)), np.sin(np.radians(17.0))
    xy = np.array([(0.0, 0.0), (60.0, 0.0), (60.0, width), (0.0, width)]) @ np.array([[c, s], [-s, c]])
    zone = Zone("N", ScanSide.INSIDE, tuple(map(tuple, xy)), (3.0,) * 4)
    problem = build_problem(Site("narrow", (zone,), Parameters(theta_max_deg=70.0, overlap=0.0)), PLAIN)
    assert problem.uncoverable().size == 0


def test_medial_axis_of_a_rectangle_is_its_centre_line() -> None:
    import shapely

    lines = medial_axis(shapely.box(0.0, 0.0, 30.0, 6.0))
    xy = np.vstack(
        [
            shapely.get_coordinates(shapely.line_interpolate_point(g, np.linspace(0, 1, 101), normalized=True))
            for g in lines
        ]
    )
    mid = xy[(xy[:, 0] > 3.5) & (xy[:, 0] < 26.5)]  # away from the corner branches (they reach x = 3)
    assert len(mid) > 0 and np.allclose(mid[:, 1], 3.0, atol=1e-9)


def test_maximal_cells_of_intervals() -> None:
    # [0, 2] and [1, 3] share [1, 2] (one maximal cell, middle 1.5); [5, 5] touches alone (cell at 5); [6, 8] holds
    # [6.5, 7] (nested: the cell of both is [6.5, 7], middle 6.75)
    lo = np.array([0.0, 1.0, 5.0, 6.0, 6.5])
    hi = np.array([2.0, 3.0, 5.0, 8.0, 7.0])
    assert maximal_cells(lo, hi).tolist() == pytest.approx([1.5, 5.0, 6.75])


@pytest.mark.parametrize(
    ("site", "reason"),
    [
        # walls 5 m high, S_max 4 m: no height reaches the top (s <= dz)
        (Site("high", (box_zone(10.0, 6.0, 5.0),), Parameters(max_slant_range_m=4.0, overlap=0.0)), "beyond range"),
        # 0.6 m wide: every point is within the 0.4-m stand-off of a wall
        (Site("slot", (box_zone(10.0, 0.6),), Parameters(overlap=0.0)), "no place to stand"),
        # a screen 0.2 m in front of the outside face from x = 2 to 8: behind it from everywhere
        (
            Site(
                "screen",
                (box_zone(10.0, 6.0, side=ScanSide.OUTSIDE),),
                Parameters(overlap=0.0),
                obstacles=(Obstacle("screen", ((2.0, -0.3), (8.0, -0.3), (8.0, -0.2), (2.0, -0.2)), 5.0),),
            ),
            "hidden behind",
        ),
    ],
)
def test_refusal_names_why_the_region_is_empty(site: Site, reason: str) -> None:
    with pytest.raises(InfeasibleError, match="seen from no position") as err:
        build_problem(site, PlanOptions(method="milp", precision=False))
    assert reason in str(err.value)


def test_a_piece_missed_by_the_pool_gets_a_candidate_from_its_region() -> None:
    # a 40 x 3 m wing off a 20 x 20 hall (an L): the wing's far end is seen only from inside the wing
    zone = Zone("L", ScanSide.INSIDE, ((0, 0), (20, 0), (20, 17), (60, 17), (60, 20), (0, 20)), (3.0,) * 6)
    site = Site("wing", (zone,), Parameters(theta_max_deg=75.0, overlap=0.0))
    problem = build_problem(site, PlanOptions(method="milp", regions=True))
    assert problem.uncoverable().size == 0
