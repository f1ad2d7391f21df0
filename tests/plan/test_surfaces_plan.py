"""Floors and ceilings planned by the pipeline (issue 46, ``--surfaces walls,floors``): a plain room's floor
found covered by an independent check written here, walls-only plans unchanged, the refusals, ceilings, and a
moved room planned alike.

The room: 10 m x 6 m, walls 3 m, as a table CSV (vertex 1 at (0, 0), side 1 along +x, counter-clockwise, so the
floor is [0, 10] x [0, 6]). The default instrument is the Leica P30: blind cone 35 deg round the nadir. With the
instrument 1.5 m above the floor, a floor point at horizontal distance d is seen when its ray's angle from the
nadir, atan(d / 1.5), is at least 35 deg (d >= 1.5 tan 35 deg = 1.050 m) and at most theta_max = 68 deg
(d <= 1.5 tan 68 deg = 3.713 m); the slant range, at most hypot(3.713, 1.5) = 4.0 m, is far below S_max.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from planner.cli import main
from planner.core.errors import ExitCode, UsageError
from planner.io.load import load_site
from planner.plan import PlanOptions
from planner.plan.problem import resolve
from planner.plan.surfaces import surface_cover
from planner.plan.verify_surfaces import verify_surfaces
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide

HEADER = "zone,scan_side,index,side_length_m,wall_height_m,interior_angle_deg,vertex_height_m"
IH = 1.5


def _room_csv(tmp_path: Path) -> Path:
    rows = [f"R,inside,{i},{length},3,90,3" for i, length in enumerate((10, 6, 10, 6), 1)]
    path = tmp_path / "room.csv"
    path.write_text("\n".join([HEADER, *rows]) + "\n")
    return path


def _room_json(tmp_path: Path, dx: float = 0.0, dy: float = 0.0, ceiling: float | None = None) -> Path:
    zone = {
        "id": "R",
        "scan_side": "inside",
        "coordinates": [[dx, dy], [dx + 10, dy], [dx + 10, dy + 6], [dx, dy + 6]],
        "height_m": 3.0,
        **({"ceiling_height_m": ceiling} if ceiling is not None else {}),
    }
    path = tmp_path / f"room_{dx:g}_{dy:g}.json"
    path.write_text(json.dumps({"name": "room", "instrument": "leica-p30", "zones": [zone]}))
    return path


def _plan(args: list[str], out: Path) -> dict:
    assert main(["plan", *args, "--quiet", "--out", str(out)]) == ExitCode.OK
    return json.loads((out / "plan.json").read_text())


def _stations(plan: dict) -> list[tuple[str, float, float]]:
    return [(s["id"], s["x"], s["y"]) for s in plan["stations"]]


def test_room_floor_planned_and_found_covered_by_an_independent_check(tmp_path, capsys):
    room = _room_csv(tmp_path)
    plan = _plan([str(room), "--surfaces", "walls,floors", "--instrument-height", "1.5"], tmp_path / "f")
    assert plan["parameters"]["instrument"] == "leica-p30"  # the model with the 35 deg blind cone
    # every floor point of a 0.1 m grid (cell centres: 100 x 60 = 6,000 points) within 68 deg of the normal and
    # outside the 35 deg cone of some station: 1.050 m <= d <= 3.713 m (a convex room: nothing hides a point)
    g = np.arange(0.05, 10.0, 0.1)
    px, py = np.meshgrid(g, np.arange(0.05, 6.0, 0.1))
    pts = np.column_stack([px.ravel(), py.ravel()])
    assert len(pts) == 6000
    st = np.array([[x, y] for _, x, y in _stations(plan)])
    d = np.hypot(pts[:, None, 0] - st[None, :, 0], pts[:, None, 1] - st[None, :, 1])
    angle = np.degrees(np.arctan2(d, IH))
    seen = (angle <= 68.0) & (angle >= 35.0)
    assert seen.any(axis=1).all(), pts[~seen.any(axis=1)][:5]
    # each station may stand anywhere in its tripod disc: all moved together to a point of their rims (8
    # directions), the floor is still covered
    radius = np.array([s["tripod_radius_m"] for s in plan["stations"]])
    for a in np.linspace(0.0, 2 * math.pi, 8, endpoint=False):
        moved = st + 0.999 * radius[:, None] * np.array([math.cos(a), math.sin(a)])
        dm = np.hypot(pts[:, None, 0] - moved[None, :, 0], pts[:, None, 1] - moved[None, :, 1])
        am = np.degrees(np.arctan2(dm, IH))
        assert ((am <= 68.0) & (am >= 35.0)).any(axis=1).all(), a
    # the package's own verification agrees, and the summary says what the bound holds over
    v = plan["surfaces"]["verification"]
    assert v["complete"] and v["zones"] == [
        {
            "zone": "R",
            "type": "floor",
            "points": 6000,
            "covered": 6000,
            "left_out": 0,
            "percent": 100.0,
            "spacing_m": 0.1,
        }
    ]
    assert plan["surfaces"]["types"] == ["walls", "floors"] and plan["surfaces"]["patches"] == 60  # 10 x 6 at 1 m
    assert plan["surfaces"]["unseen_patches"]["count"] == 0
    out = capsys.readouterr().out
    if plan["plane_bound"] is None:  # the run without the bound over walls and floors
        assert plan["bound_scope"] == "pool" and "bound over the pool (surfaces beyond walls" in out
    else:  # the bound over walls and floors together, and what it holds over
        assert plan["certificate"]["scope"] == "plane, walls and floors" and 2 <= plan["plane_bound"] <= len(
            plan["stations"]
        )
        assert "over every position in the plane, walls and floors" in out
    assert "R     floor     6,000    6,000         0    100.000" in out
    # (b) at least as many stations as the walls-only plan (one station sees all four walls of the room)
    walls = _plan([str(room)], tmp_path / "w")
    assert len(plan["stations"]) >= len(walls["stations"]) >= 1
    # one station cannot cover the floor: its blind disc (pi 1.05^2 = 3.46 m2) is floor it does not see
    assert len(plan["stations"]) > 1


def test_walls_only_plan_json_unchanged_by_the_surfaces_key(tmp_path):
    room = _room_csv(tmp_path)
    plain = _plan([str(room)], tmp_path / "a")
    walls = _plan([str(room), "--surfaces", "walls"], tmp_path / "b")
    assert "surfaces" not in plain and "surfaces" not in walls
    assert _stations(plain) == _stations(walls)
    timing = {"time_s", "log", "solver", "presolve", "source", "source_resolved"}
    assert {k: v for k, v in plain.items() if k not in timing} == {k: v for k, v in walls.items() if k not in timing}


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--surfaces", "floors"], ["--surfaces", "must include walls"]),
        (["--surfaces", "walls,roofs"], ["--surfaces", "unknown surface 'roofs'"]),
        (["--set", "theta-max-floor=95"], ["--set theta-max-floor", "<= 90"]),
        # the site's instrument height is 0 and the ScanStation 2 model gives no 3-D height
        (
            ["--surfaces", "walls,floors", "--instrument", "leica-scanstation-2"],
            ["--instrument-height", "instrument_height_3d_m"],
        ),
        (["--surfaces", "walls,floors", "--method", "closed-form"], ["--method", "walls only"]),
        (["--surfaces", "walls,floors", "--recentre"], ["--recentre", "walls only"]),
    ],
)
def test_bad_surface_options_are_one_line_usage_errors(tmp_path, capsys, args, words):
    room = _room_csv(tmp_path)
    assert main(["plan", str(room), "--quiet", *args]) == ExitCode.USAGE
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    for w in words:
        assert w in err, err


def test_library_options_refuse_surfaces_without_walls():
    with pytest.raises(UsageError, match="must include walls"):
        PlanOptions(surfaces=("floors",))
    with pytest.raises(UsageError, match="unknown surface"):
        PlanOptions(surfaces=("walls", "roof"))
    assert not PlanOptions().beyond_walls and PlanOptions(surfaces=("walls", "ceilings")).beyond_walls


def test_ceilings_planned_and_verified(tmp_path):
    # ceiling at 3 m, instrument at 1.5 m: dz = +1.5 m, the same 3.713 m reach as the floor; the P30 has no
    # zenith cone, so the ceiling straight above a station is seen
    path = _room_json(tmp_path, ceiling=3.0)
    plan = _plan([str(path), "--surfaces", "walls,floors,ceilings", "--instrument-height", "1.5"], tmp_path / "c")
    rows = {r["type"]: r for r in plan["surfaces"]["verification"]["zones"]}
    assert set(rows) == {"floor", "ceiling"}
    assert rows["floor"]["percent"] == rows["ceiling"]["percent"] == 100.0
    assert rows["ceiling"]["points"] == 6000 and plan["surfaces"]["patches"] == 120  # 60 floor + 60 ceiling


def test_moving_the_room_changes_no_station_count(tmp_path):
    here = _plan([str(_room_json(tmp_path)), "--surfaces", "walls,floors"], tmp_path / "a")
    moved = _plan([str(_room_json(tmp_path, 1234.5, -678.25)), "--surfaces", "walls,floors"], tmp_path / "b")
    # the instance's instrument height is 0: the P30's instrument_height_3d_m, 1.5 m, is taken
    assert here["surfaces"]["instrument_height_m"] == moved["surfaces"]["instrument_height_m"] == 1.5
    assert len(here["stations"]) == len(moved["stations"])
    assert here["surfaces"]["verification"]["complete"] and moved["surfaces"]["verification"]["complete"]


def test_verification_finds_a_floor_one_station_leaves_uncovered(tmp_path):
    site = load_site(_room_csv(tmp_path))
    problem = resolve(site, PlanOptions(surfaces=("walls", "floors")))
    setup = problem.surfaces
    assert setup is not None and setup.limits.instrument_height_m == 1.5  # the P30's own 3-D height
    one = Candidate("c", "R", ScanSide.INSIDE, site.zones[0].frame, 5.0, 3.0, CandidateKind.GRID)
    cover = surface_cover(site, setup, [one])
    report = verify_surfaces(site, setup, cover, [one], 0.1)
    (row,) = report.rows
    # seen: the ring 1.050 m <= d <= 3.713 m round (5, 3), clipped by the room's 6 m depth (y in [0, 6] reaches
    # 3 m either side): about pi (3.713^2 - 1.05^2) less the parts beyond y = 0 and y = 6, well under 60 m2
    ring = math.pi * (3.713**2 - 1.05**2)
    assert 0 < row.covered < row.points == 6000 and row.covered * 0.01 < ring
    assert not report.complete and "INCOMPLETE" in report.lines()[0]
    # the candidate sees whole patches only: one at the room's corner, 5.8 m away, is not among them
    assert cover.unseen.size > 0 and cover.matrix.shape == (1, cover.seen.size)


def _l_room(tmp_path: Path) -> Path:
    # an L: the 12 x 5 m bar and the 5 x 5 m arm above its left end (85 m2), a 0.6 m column at (2, 2) that
    # reaches the 2.8 m ceiling: floor and ceiling are each 85 - 0.36 = 84.64 m2, 8,464 points at 0.1 m
    zone = {
        "id": "L",
        "scan_side": "inside",
        "coordinates": [[0, 0], [12, 0], [12, 5], [5, 5], [5, 10], [0, 10]],
        "height_m": 3.0,
        "ceiling_height_m": 2.8,
        "holes": [{"coordinates": [[2, 2], [2.6, 2], [2.6, 2.6], [2, 2.6]], "height_m": 2.8}],
    }
    path = tmp_path / "l.json"
    path.write_text(json.dumps({"name": "lroom", "instrument": "leica-p30", "zones": [zone]}))
    return path


def test_l_room_with_a_column_planned_with_floor_and_ceiling(tmp_path):
    plan = _plan([str(_l_room(tmp_path)), "--surfaces", "walls,floors,ceilings"], tmp_path / "l")
    rows = {r["type"]: r for r in plan["surfaces"]["verification"]["zones"]}
    assert rows["floor"]["points"] == rows["ceiling"]["points"] == 8464
    assert plan["surfaces"]["verification"]["complete"]


def test_verification_sees_no_floor_round_the_inner_corner(tmp_path):
    # one station at (6, 4), 1 m right of and below the L's inner corner (5, 5). The floor point (4, 6.5) is
    # 3.20 m away (within 1.050..3.713 m) but the segment to it crosses x = 5 at y = 5.25, outside the L: hidden.
    # A point (x, y) of the arm (x < 5, y > 5) is hidden when that crossing, y' = 4 + (y - 4) / (6 - x), is above
    # 5, i.e. x + y > 10 (on the line, the segment grazes the corner: seen). The column's nearest corner (2.6, 2.6)
    # is 3.68 m away, so its shadow within the 3.713 m reach is a sliver: the verification counts the ring's points
    # less the hidden ones, and at most a few fewer
    site = load_site(_l_room(tmp_path))
    problem = resolve(site, PlanOptions(surfaces=("walls", "floors")))
    assert problem.surfaces is not None
    one = Candidate("c", "L", ScanSide.INSIDE, site.zones[0].frame, 6.0, 4.0, CandidateKind.GRID)
    report = verify_surfaces(site, problem.surfaces, None, [one], 0.1)  # the points alone (no pool's patches)
    g = np.arange(0.05, 12.0, 0.1)
    px, py = np.meshgrid(g, np.arange(0.05, 10.0, 0.1))
    x, y = px.ravel(), py.ravel()
    floor = ((y < 5) | (x < 5)) & ~((x > 2) & (x < 2.6) & (y > 2) & (y < 2.6))
    d = np.hypot(x - 6.0, y - 4.0)
    ring = floor & (d >= 1.5 * math.tan(math.radians(35))) & (d <= 1.5 * math.tan(math.radians(68)))
    behind = ring & (x < 5) & (y > 5) & (x + y > 10 + 1e-6)  # round the corner, hidden from (6, 4)
    assert behind.sum() > 0
    (row,) = report.rows
    assert row.points == int(floor.sum()) == 8464
    assert int(ring.sum()) - int(behind.sum()) - 10 <= row.covered <= int(ring.sum()) - int(behind.sum())


@pytest.mark.parametrize("extra", [["--method", "greedy"], ["--method", "greedy", "--no-overlap"], ["--no-overlap"]])
def test_every_method_but_the_closed_form_covers_the_floor(tmp_path, extra):
    # the connected greedy, the plain greedy and the plain MILP cover the patch columns too: the 10 x 6 m floor
    # verifies at 100 % (6,000 points), and no plan has fewer stations than the walls alone need (1)
    room = _room_csv(tmp_path)
    plan = _plan([str(room), "--surfaces", "walls,floors", *extra], tmp_path / "m")
    assert plan["surfaces"]["verification"]["complete"] and len(plan["stations"]) > 1


def test_verify_command_checks_floors_when_asked(tmp_path, capsys):
    # the floors plan verifies (exit 0); the walls-only plan's one station leaves the floor beyond 3.713 m and
    # inside its 1.050 m blind disc unseen: incomplete, exit 4 (INFEASIBLE), as a wall left uncovered
    room = _room_csv(tmp_path)
    _plan([str(room), "--surfaces", "walls,floors"], tmp_path / "f")
    _plan([str(room)], tmp_path / "w")
    capsys.readouterr()
    floors = ["--surfaces", "walls,floors"]
    assert main(["verify", str(room), str(tmp_path / "f" / "plan.json"), *floors]) == ExitCode.OK
    assert "(complete)" in capsys.readouterr().out
    assert main(["verify", str(room), str(tmp_path / "w" / "plan.json"), *floors]) == ExitCode.INFEASIBLE
    assert "(INCOMPLETE)" in capsys.readouterr().out
    assert main(["verify", str(room), str(tmp_path / "w" / "plan.json")]) == ExitCode.OK  # walls alone: complete


def test_a_floor_no_station_can_see_is_reported_and_left_out(tmp_path, capsys):
    # theta-max-floor 30 deg is inside the P30's 35 deg blind cone: every ray near enough the normal is blind, so
    # no candidate sees any of the 60 patches (60 m2); they are left out of the cover and reported, the walls are
    # planned as ever (one station) and the floor's verification says 0 % and INCOMPLETE
    room = _room_csv(tmp_path)
    plan = _plan([str(room), "--surfaces", "walls,floors", "--set", "theta-max-floor=30"], tmp_path / "t")
    assert plan["surfaces"]["unseen_patches"] == {"count": 60, "area_m2": 60.0, "zones": ["R/floor"]}
    assert plan["surfaces"]["theta_max_floor_deg"] == 30.0 and len(plan["stations"]) == 1
    v = plan["surfaces"]["verification"]
    assert not v["complete"] and v["zones"][0]["covered"] == 0
    out = capsys.readouterr().out
    assert (
        "60 patch(es) (60.00 m2) seen by no candidate, left out (NOT covered): R/floor" in out and "(INCOMPLETE)" in out
    )
