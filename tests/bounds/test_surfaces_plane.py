"""The plane bound over walls and floors together (planner.bounds.surfaces_plane, planner.plan.surfaces_bound).

- The result it marks: ``plane_bound`` = ceil(k x Farley's bound), scope ``plane, walls and floors`` (with ``, k =
  K``), optimal only when the plan meets it; where it is not formed, ``plane_off`` says why.
- The 4.3 x 3.3 m room (IH 1.5 m, the P30's 35 deg cone): the bound over its pool with the region candidates is 2,
  priced to convergence; no position (random, and the pool's) weighs more than the heaviest weight w* that Farley's
  bound divides by.
- The issue's case through the command (``--surfaces walls,floors --instrument-height 1.5 --no-overlap``): 2 stations,
  plane bound 2, scope ``plane, walls and floors`` in plan.json and the summary.
- Property (slow, hypothesis, few examples): on small random rectangles and L rooms with floors, the bound is never
  above the exact optimum over a 0.1-m grid of positions (CP-SAT over the grid with the planner's own sight tests, its
  stations verified by the planner's verify), and the plan over the pool with the region candidates has no more
  stations than that optimum or its scope is the pool.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from planner.bounds.surfaces_plane import SurfacePlaneBound, surfaces_plane_bound
from planner.cli.main import main
from planner.coverage.matrix import CoverageProblem, build_coverage
from planner.plan import PlanOptions
from planner.plan.methods import with_columns
from planner.plan.problem import Problem, resolve
from planner.plan.run import site_candidates
from planner.plan.surfaces import SurfaceCover, surface_cover
from planner.plan.surfaces_bound import scope_of, with_surfaces_bound
from planner.plan.verify import verify_stations
from planner.plan.verify_surfaces import verify_surfaces
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Site, Zone
from planner.site.params import Parameters
from planner.solve.instance import cover_instance
from planner.solve.milp import MilpOptions, solve
from planner.solve.result import SolveResult, Status
from tests.bounds.plane_cases import _place, outline, positions

FEW = settings(
    deadline=None,
    derandomize=True,
    database=None,
    max_examples=8,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)
FLOORS = PlanOptions(precision=False, surfaces=("walls", "floors"), milp=MilpOptions(overlap=None))


def _room(kind: str, w: float, h: float, theta: float, angle: float) -> Site:
    xy = outline(kind, w, h, 0.5, 0.5)
    zone = Zone("R", ScanSide.INSIDE, _place(xy, angle, (0.0, 0.0)), (3.0,) * len(xy))
    params = Parameters(theta_max_deg=theta, overlap=0.0, instrument_height_m=1.5)
    return Site(f"{kind} {w:.1f} x {h:.1f}", (zone,), parameters=params)


def _result(objective: float) -> SolveResult:
    info = {"plane_off": "surfaces beyond walls"}
    return SolveResult(
        method="milp", status=Status.FEASIBLE, selected=(0, 1), objective=objective, bound=1.0, info=info
    )


@pytest.mark.parametrize(
    ("objective", "scope", "status"), [(2.0, "plane", Status.OPTIMAL), (3.0, "pool", Status.FEASIBLE)]
)
def test_the_bound_marks_the_result(objective, scope, status):
    report = SurfacePlaneBound("plane, walls and floors", lp_bound=1.6, plane_lp_bound=1.58, heaviest_weight=1.0)
    out = with_surfaces_bound(_result(objective), report)
    assert out.info["plane_bound"] == 2 and out.info["pool_bound"] == 1.0 and "plane_off" not in out.info
    assert out.info["bound_scope"] == scope and out.status is status
    assert out.info["plane_bound_scope"] == out.info["certificate"]["scope"] == "plane, walls and floors"
    k2 = with_surfaces_bound(
        _result(objective), SurfacePlaneBound("plane, walls and floors, k = 2", plane_lp_bound=1.58), 2
    )
    assert k2.info["plane_bound"] == 4 and k2.info["certificate"]["k"] == 2


def test_where_the_bound_is_not_formed_the_result_says_why():
    report = SurfacePlaneBound("plane, walls and floors", note="10,785 wall pieces and patches, more than the 3,000")
    out = with_surfaces_bound(_result(3.0), report)
    assert "plane_bound" not in out.info and out.status is Status.FEASIBLE
    assert out.info["plane_off"].startswith("surfaces beyond walls: the bound over walls and floors: 10,785")
    assert report.bound() is None and "not formed" in report.summary()


def test_scope_words():
    problem = resolve(_room("rect", 4.3, 3.3, 68.0, 0.0), FLOORS)
    assert problem.surfaces is not None
    assert scope_of(problem.surfaces) == "plane, walls and floors"
    assert scope_of(problem.surfaces, 2) == "plane, walls and floors, k = 2"
    ceilings = PlanOptions(surfaces=("walls", "floors", "ceilings"))
    assert scope_of(resolve(_room("rect", 4.3, 3.3, 68.0, 0.0), ceilings).surfaces) == "plane, walls and floors"  # type: ignore[arg-type]


def _pool(problem: Problem) -> tuple[CoverageProblem, SurfaceCover]:
    """The run's pool with the region candidates, its wall coverage and its patch columns."""
    site, setup = problem.site, problem.surfaces
    assert setup is not None
    spaces: dict = {}
    cache: dict = {}
    cands = site_candidates(problem, problem.targets, spaces, cache)  # the region candidates among them
    walls = build_coverage(site, cands, problem.targets, problem.limits)
    return walls, surface_cover(site, setup, list(walls.candidates), walls.excluded)


def _bound(problem: Problem) -> tuple[SurfacePlaneBound, CoverageProblem, SurfaceCover]:
    walls, cover = _pool(problem)
    setup = problem.surfaces
    assert setup is not None
    report = surfaces_plane_bound(
        problem.site, walls, setup.patches, cover.seen, cover.matrix, setup.limits, scope=scope_of(setup)
    )
    return report, walls, cover


@pytest.mark.slow
def test_the_4_3_x_3_3_room_is_bounded_by_2_and_no_position_weighs_more_than_w_star():
    problem = resolve(_room("rect", 4.3, 3.3, 68.0, 20.0), FLOORS)
    report, walls, cover = _bound(problem)
    assert report.bound() == 2 and report.converged and report.heaviest_weight <= 1.0 + 1e-3, report.summary()
    # every position's weight (its real coverage of pieces and patches, times the duals) is at most w*
    y = np.asarray(report.duals)
    rng = np.random.default_rng(3)
    zone = problem.site.zones[0]
    lo, hi = np.min(zone.xy, axis=0), np.max(zone.xy, axis=0)
    pts = lo + rng.random((3000, 2)) * (hi - lo)
    cands = [
        Candidate(f"Q{k}", "R", ScanSide.INSIDE, "site", float(a), float(b), CandidateKind.GRID)
        for k, (a, b) in enumerate(pts)
    ]
    sub = build_coverage(problem.site, cands, problem.targets, problem.limits)
    setup = problem.surfaces
    assert setup is not None
    patches = surface_cover(problem.site, setup, cands, sub.excluded)
    full = sp.lil_matrix((len(cands), len(setup.patches)), dtype=bool)
    full[:, patches.seen] = patches.matrix
    cols = sp.hstack([sub.by_candidate, full.tocsr()[:, cover.seen]], format="csr")
    weights = np.asarray(cols.astype(float) @ y).ravel()
    assert weights.max() <= report.heaviest_weight + 1e-9
    pool = np.asarray(sp.hstack([walls.by_candidate, cover.matrix], format="csr").astype(float) @ y).ravel()
    assert pool.max() <= report.heaviest_weight + 1e-9


@pytest.mark.slow
def test_the_issue_case_plans_2_stations_with_a_bound_over_walls_and_floors(tmp_path, capsys):
    zone = {"id": "R", "scan_side": "inside", "coordinates": [[0, 0], [4.3, 0], [4.3, 3.3], [0, 3.3]], "height_m": 3.0}
    site = tmp_path / "room.json"
    site.write_text(json.dumps({"name": "room", "instrument": "leica-p30", "zones": [zone]}))
    args = ["plan", str(site), "--surfaces", "walls,floors", "--instrument-height", "1.5", "--no-overlap"]
    assert main([*args, "--quiet", "--out", str(tmp_path / "o")]) == 0
    text = capsys.readouterr().out
    plan = json.loads((tmp_path / "o" / "plan.json").read_text())
    assert len(plan["stations"]) == 2 and plan["plane_bound"] == 2 and plan["bound_scope"] == "plane"
    assert plan["certificate"]["scope"] == "plane, walls and floors"
    assert plan["surfaces"]["verification"]["complete"]
    assert "bound scope: plane, walls and floors" in text
    assert "over every position in the plane, walls and floors" in text


def grid_optimum(site: Site, options: PlanOptions, step: float) -> float:
    """The exact minimum of stations on a ``step`` grid inside the room that cover every wall piece and floor patch
    (CP-SAT), its stations verified by the planner's verify; inf where a piece or patch no grid position sees."""
    problem = resolve(site, options)
    setup = problem.surfaces
    assert setup is not None
    grid = positions(site.zones[0], step)
    walls = build_coverage(site, grid, problem.targets, problem.limits)
    cover = surface_cover(site, setup, grid, walls.excluded)
    if cover.unseen.size or np.any(walls.by_target.getnnz(axis=1) == 0):
        return math.inf
    result = solve(with_columns(cover_instance(walls), cover.matrix), MilpOptions(overlap=None, time_limit_s=120.0))
    assert result.status is Status.OPTIMAL
    chosen = [grid[i] for i in result.selected]
    assert verify_stations(problem.sight, chosen, options.verify_spacing_m).complete
    assert verify_surfaces(site, setup, cover, chosen, options.verify_spacing_m).complete
    return float(result.objective)


@pytest.mark.slow
@settings(FEW)
@given(
    kind=st.sampled_from(["rect", "rect", "L"]),
    w=st.floats(2.5, 6.0),
    h=st.floats(2.5, 6.0),
    theta=st.floats(60.0, 80.0),
    angle=st.floats(0.0, 90.0),
)
def test_the_bound_and_the_plan_against_the_grid_optimum(kind, w, h, theta, angle):
    if kind != "rect":
        w, h = max(w, 5.0), max(h, 5.0)
    site = _room(kind, w, h, theta, angle)
    optimum = grid_optimum(site, FLOORS, 0.1)
    event(f"grid optimum {optimum:g}")
    if not math.isfinite(optimum):
        return
    problem = resolve(site, FLOORS)
    report, walls, cover = _bound(problem)
    bound = report.bound()
    assert bound is not None and bound <= optimum, (report.summary(), optimum)  # holds over every position
    plan = solve(with_columns(cover_instance(walls), cover.matrix), MilpOptions(overlap=None, time_limit_s=120.0))
    assert plan.objective is not None
    scope = with_surfaces_bound(plan, report).info["bound_scope"]
    assert plan.objective <= optimum or scope == "pool", (plan.objective, optimum, report.summary())
    event(f"plan {'=' if plan.objective == optimum else '<' if plan.objective < optimum else '>'} grid, scope {scope}")
