"""Openings: gaps in walls (no targets, sight passes), accessible areas, links and site-wide registration."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.candidates.pool import PoolOptions
from planner.cli import main
from planner.coverage.links import opening_links
from planner.coverage.matrix import blockers_for
from planner.coverage.openings import accessible_areas, seen_through, space_of, wall_gaps
from planner.coverage.targets import make_targets
from planner.coverage.visibility import sight_clear
from planner.engine import plan_site
from planner.io.load import load_site
from planner.plan import PlanOptions
from planner.site import ScanSide
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import Opening
from planner.solve.milp import MilpOptions
from tests.conftest import INSTANCES

HOUSE = INSTANCES / "house_doors.json"


def station(x: float, y: float, zone: str, side: ScanSide = ScanSide.INSIDE) -> Candidate:
    return Candidate(f"{zone}@{x},{y}", zone, side, "site", x, y, CandidateKind.GRID)


def test_opening_pieces_are_no_targets():
    site = load_site(HOUSE)
    t = make_targets(site, 1.0)
    r1 = site.zones.index(site.zone("R1"))
    on = t.zone == r1
    # R1 is 10 x 8 m = 36 m of wall; its front door (1.5 m) and the door to R2 (1.5 m) leave 33 m
    assert (t.s1_m - t.s0_m)[on].sum() == pytest.approx(33.0)
    # no piece of R1's wall 2 overlaps the door at 3.0..4.5 m
    w2 = on & (t.wall == 2)
    assert not np.any((t.s0_m[w2] < 4.5 - 1e-9) & (t.s1_m[w2] > 3.0 + 1e-9))


def test_a_door_given_once_opens_both_faces_of_its_wall():
    site = load_site(HOUSE)
    r2 = site.zones.index(site.zone("R2"))
    # R1's wall 2 runs (10,0)->(10,8), its door at 3.0..4.5 m; R2's wall 4 runs (10,8)->(10,0): 3.5..5.0 m along it
    gaps = wall_gaps(site, r2, site.zone("R2").walls[3])
    assert gaps[0] == pytest.approx((3.5, 5.0))
    # the outline's front wall (0,0)->(30,0) takes R1's front door at 4.0..5.5 m
    house = site.zones.index(site.zone("house"))
    assert wall_gaps(site, house, site.zone("house").walls[0]) == [pytest.approx((4.0, 5.5))]


def test_sight_passes_through_a_door_and_not_through_the_wall():
    site = load_site(HOUSE)
    b = blockers_for(site, "site")
    c = np.array([[5.0, 4.0], [5.0, 6.5]])
    p = np.array([[15.0, 3.5], [15.0, 6.5]])  # the first line crosses x = 10 at y = 3.75 (door 3.0..4.5)
    assert sight_clear(c, p, p, np.full(2, -2), b).tolist() == [True, False]


def test_accessible_areas_follow_doors_not_windows():
    site = load_site(HOUSE)
    areas = accessible_areas(site)
    assert len(set(areas.values())) == 1  # the three rooms and the ground outside: one area
    # without the front door the ground outside is an area of its own; the back window joins nothing
    r1 = site.zone("R1")
    shut = replace(site, zones=tuple(replace(z, openings=z.openings[1:]) if z.id == "R1" else z for z in site.zones))
    areas = accessible_areas(shut)
    assert len(set(areas.values())) == 2
    assert areas[space_of(r1, ScanSide.INSIDE)] != areas[("out", "site")]


def test_links_are_pairs_that_see_each_other_through_an_opening():
    site = load_site(HOUSE)
    cands = [
        station(5, 4, "R1"),
        station(15, 3.5, "R2"),
        station(15, 7.5, "R2"),
        station(4.5, -10, "house", ScanSide.OUTSIDE),
    ]
    xy = np.array([c.xy for c in cands])
    links = opening_links(
        site, xy, [c.frame for c in cands], [space_of(site.zone(c.zone), c.side) for c in cands], 50.0
    )
    pairs = {tuple(sorted(p)) for p in zip(*links.nonzero())}
    # R1(5,4)-R2(15,3.5) crosses the R1-R2 door; R1(5,4)-outside(4.5,-10) crosses the front door (x 4.0..5.5);
    # R1(5,4)-R2(15,7.5) meets x = 10 at y = 5.75, beside the door (3.0..4.5): wall
    assert pairs == {(0, 1), (0, 3)}


@pytest.mark.slow
def test_house_plans_as_one_registration_network_through_its_doors():
    site = load_site(HOUSE)
    options = PlanOptions(method="milp", pool=PoolOptions(grid_spacing_m=2.0))
    plan = plan_site(site, options)  # site registration is the default: the instance has openings
    assert len(plan.registration) == 1 and list(plan.registration.values()) == [1]
    assert plan.verification.complete
    zone_plan = plan_site(site, replace(options, registration="zone"))
    assert len(zone_plan.registration) == 4 and set(zone_plan.registration.values()) == {1}
    # neither registration mode bounds the other (site: one network through the doors; zone: each room connected on its
    # own), but both plans are covers, so neither is below the plain cover's optimum
    plain = plan_site(site, replace(options, milp=MilpOptions(overlap=None)))
    assert plain.result.status.value == "optimal"
    assert min(len(plan.stations), len(zone_plan.stations)) >= plain.result.objective
    assert zone_plan.verification.complete


@pytest.mark.slow
@pytest.mark.heavy
def test_assembled_temple_one_bundle_per_accessible_area():
    # Baalbek as assembled: 8 rooms and the outline in the site frame, Z1, Z5, Z6 in their own frames; table 4.3 gives
    # no doors, so every room is an accessible area of its own and the ground outside one more
    site = load_site(INSTANCES / "baalbek_site.json")
    assert len(set(accessible_areas(site).values())) == 12
    plan = plan_site(site, PlanOptions(method="milp", registration="site"))
    assert len(plan.registration) == 12 and set(plan.registration.values()) == {1}
    assert plan.verification.complete


def test_overlap_zero_turns_registration_off(capsys, tmp_path):
    code = main(["plan", str(HOUSE), "--overlap", "0", "--grid-spacing", "4", "--quiet"])
    out = capsys.readouterr().out
    assert code == 0 and "registration: not required (overlap 0)" in out


def test_json_window_does_not_join_but_lets_sight_through(tmp_path):
    data = json.loads(HOUSE.read_text())
    site = load_site(HOUSE)
    r3 = site.zone("R3")
    assert r3.openings == (Opening(3, 4.0, 5.0, "window", "back window"),)
    # R3's wall 3 runs (30,8)->(20,8): the window spans x 26..25; a line from inside R3 to outside through it
    b = blockers_for(site, "site")
    c, p = np.array([[25.5, 4.0]]), np.array([[25.5, 15.0]])
    assert sight_clear(c, p, p, np.full(1, -2), b).tolist() == [True]
    assert data["openings"][3]["kind"] == "window"


@pytest.mark.parametrize("name", [pytest.param("baalbek_site.json", marks=pytest.mark.slow), "house_doors.json"])
def test_zone_side_blockers_give_the_pairs_of_the_full_blocker_set(name, monkeypatch):
    # the per-zone-side blocker subsets must keep the junction cuts of placed zones (no cut end comes back as a vertex)
    # and every blocker for a zone with a gap, even one made by a neighbour's door
    import planner.coverage.matrix as matrix
    from planner.plan import build_problem

    site = load_site(INSTANCES / name)
    options = PlanOptions(method="milp", regions=False, pool=PoolOptions(grid_spacing_m=10.0))
    fast = build_problem(site, options).by_candidate
    monkeypatch.setattr(matrix.ZoneSideBlockers, "of", lambda self, zi, inside: self.all)
    full = build_problem(site, options).by_candidate
    assert fast.nnz == full.nnz and (fast != full).nnz == 0


def _crossing_oracle(region, a: float, b: float, q: np.ndarray, reach_m: float) -> bool:
    """Whether some point of the convex ``region`` sees ``q`` through the opening [a, b] of the x-axis, found apart
    from :func:`seen_through`: the part of the region across the axis from q, the points where its vertices' segments
    to q cross the axis (their extremes bound the crossings of the whole part, which is convex), overlapping [a, b]."""
    if abs(q[1]) < 1e-9 or np.hypot(q[0] - (a + b) / 2, q[1]) > reach_m:
        return False
    box = shapely.box(-1e3, -1e3 if q[1] > 0 else 0.0, 1e3, 0.0 if q[1] > 0 else 1e3)
    part = shapely.intersection(region, box)
    if part.is_empty:
        return False
    v = shapely.get_coordinates(part)
    x = v[:, 0] + (q[0] - v[:, 0]) * (0.0 - v[:, 1]) / (q[1] - v[:, 1])
    return bool(x.min() <= b and x.max() >= a)


@settings(max_examples=60, deadline=None)
@given(
    pts=st.lists(st.tuples(st.floats(-15, 15), st.floats(-20, 6)), min_size=3, max_size=7, unique=True),
    a=st.floats(-3, 0),
    width=st.floats(0.5, 4),
    reach=st.floats(10, 60),
    seed=st.integers(0, 2**16),
)
def test_seen_through_is_every_position_a_point_of_the_region_sees_through_the_opening(pts, a, width, reach, seed):
    # a convex region (it may straddle the opening's line) and a door [a, a + width] on the x-axis; random positions
    # away from the boundary of the answer are in it exactly when the crossing oracle says some point sees them
    region = shapely.convex_hull(shapely.MultiPoint([(round(x, 3), round(y, 3)) for x, y in pts]))  # mm, no denormals
    if region.area < 1e-3:
        return
    b = a + width
    got = seen_through(region, np.array([[a, 0.0], [b, 0.0]]), reach)
    rng = np.random.default_rng(seed)
    q = rng.uniform([-70, -70], [70, 70], size=(300, 2))
    edge = got.boundary if not got.is_empty else None
    for p in q:
        if edge is not None and shapely.distance(edge, shapely.Point(*p)) < 1e-6:
            continue
        if abs(np.hypot(p[0] - (a + b) / 2, p[1]) - reach) < 2e-3 * reach:  # the disc: a circumscribed polygon
            continue
        assert bool(shapely.contains_xy(got, *p)) == _crossing_oracle(region, a, b, p, reach), p
