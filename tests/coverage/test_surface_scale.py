"""Floors at scale: the thinned floor grid of a large zone, the k-d tree verification, and progress as lines where
standard error is no terminal (a long run never looks hung)."""

from __future__ import annotations

import io
import json
import time
from pathlib import Path

import numpy as np
import shapely

import planner.plan.surfaces as plan_surfaces
from planner.core import progress
from planner.coverage.surfaces import FLOOR
from planner.io.load import load_site
from planner.plan import PlanOptions
from planner.plan.problem import resolve
from planner.plan.verify_surfaces import EPS_M, _covered, _grid, _seen_by
from planner.site.candidate import CandidateKind

HEADER = "zone,scan_side,index,side_length_m,wall_height_m,interior_angle_deg,vertex_height_m"


def _room(tmp_path: Path) -> Path:
    rows = [f"R,inside,{i},{length},3,90,3" for i, length in enumerate((12, 9, 12, 9), 1)]
    path = tmp_path / "room.csv"
    path.write_text("\n".join([HEADER, *rows]) + "\n")
    return path


def _l_room(tmp_path: Path) -> Path:
    zone = {
        "id": "L",
        "scan_side": "inside",
        "coordinates": [[0, 0], [12, 0], [12, 5], [5, 5], [5, 10], [0, 10]],
        "height_m": 3.0,
        "holes": [{"coordinates": [[2, 2], [2.6, 2], [2.6, 2.6], [2, 2.6]], "height_m": 2.8}],
    }
    path = tmp_path / "l.json"
    path.write_text(json.dumps({"name": "lroom", "instrument": "leica-p30", "zones": [zone]}))
    return path


def test_a_room_grid_is_kept_whole_and_a_thinned_grid_loses_no_patch(tmp_path, monkeypatch):
    site = load_site(_room(tmp_path))
    setup = resolve(site, PlanOptions(surfaces=("walls", "floors"))).surfaces
    assert setup is not None
    whole = plan_surfaces.floor_candidates(site, setup, 0.3)
    assert len(whole) <= plan_surfaces.THIN_ABOVE  # a room: the grid as it was
    dense = plan_surfaces.patch_matrix(site, setup, whole).tocsc()
    monkeypatch.setattr(plan_surfaces, "THIN_ABOVE", 10)
    thin = plan_surfaces.floor_candidates(site, setup, 0.3)
    assert 0 < len(thin) < len(whole)
    assert {c.xy for c in thin} <= {c.xy for c in whole} and all(c.kind is CandidateKind.GRID for c in thin)
    kept = plan_surfaces.patch_matrix(site, setup, thin).tocsc()
    seers, left = np.diff(dense.indptr), np.diff(kept.indptr)
    assert np.all(left >= np.minimum(seers, plan_surfaces.THIN_SEERS))  # every patch keeps its seers, 3 at most
    assert np.array_equal(left > 0, seers > 0)


def test_the_k_d_tree_verification_equals_every_station_against_every_point(tmp_path):
    # the L with a column: stations near the inner corner and the column (plan-view test) and in the open (the
    # reach disc inside the floor: no plan-view test); the tree finds exactly what a test of all points finds
    site = load_site(_l_room(tmp_path))
    setup = resolve(site, PlanOptions(surfaces=("walls", "floors"))).surfaces
    assert setup is not None
    outline = shapely.Polygon(site.zones[0].xy)
    column = shapely.Polygon(site.zones[0].holes[0])
    clear = outline.difference(column).buffer(EPS_M, join_style="mitre")
    pts, _ = _grid(outline.difference(column), 0.1)
    dz = -setup.limits.instrument_height_m
    stations = [np.array(xy) for xy in ((6.0, 4.0), (3.0, 3.5), (9.0, 2.5), (2.5, 8.0), (1.0, 1.0))]
    brute = np.zeros(len(pts), dtype=bool)
    for xy in stations:
        brute |= _seen_by(xy, pts, dz, setup, FLOOR, clear)
    assert 0 < brute.sum() < len(pts)
    assert np.array_equal(_covered(pts, stations, dz, setup, FLOOR, clear), brute)
    # the 12 x 9 m room: the reach disc of (6, 4.5) and (5.5, 4) lies inside the floor (no plan-view test)
    room = load_site(_room(tmp_path))
    floor = shapely.Polygon(room.zones[0].xy)
    pts, _ = _grid(floor, 0.1)
    clear = floor.buffer(EPS_M, join_style="mitre")
    stations = [np.array(xy) for xy in ((6.0, 4.5), (5.5, 4.0), (1.0, 8.0))]
    brute = np.zeros(len(pts), dtype=bool)
    for xy in stations:
        brute |= _seen_by(xy, pts, dz, setup, FLOOR, clear)
    assert np.array_equal(_covered(pts, stations, dz, setup, FLOOR, clear), brute)


def test_progress_lines_at_most_one_every_few_seconds_and_every_note():
    now = [0.0]
    out = io.StringIO()
    lines = progress.Lines(out, every_s=5.0, clock=lambda: now[0])
    for k in range(100):  # 100 reports over 20 s: a line at 0, 5, 10, 15 and 20 s
        now[0] = k * 0.2
        lines("verifying floors", k, 100)
    now[0] = 20.0
    lines("verifying floors", 100, 100)
    lines.note("verifying B/floor: 967,712 points")
    text = out.getvalue().splitlines()
    assert len(text) == 6 and text[0] == "progress: verifying floors 0 % (0 s)"
    assert text[-2] == "progress: verifying floors 100 % (20 s)" and text[-1].startswith("progress: verifying B")


def test_a_terminal_gets_the_bar_anything_else_lines_and_quiet_nothing():
    class Tty(io.StringIO):
        def isatty(self) -> bool:
            return True

    assert isinstance(progress.sink_for(Tty()), progress.Bar)
    assert isinstance(progress.sink_for(io.StringIO()), progress.Lines)
    assert progress.sink_for(io.StringIO(), quiet=True) is None


def test_a_solve_without_a_time_limit_says_it_is_running_and_draws_no_bar():
    out, tty = io.StringIO(), io.StringIO()
    for sink in (progress.Lines(out, every_s=0.0), progress.Bar(tty)):
        previous = progress.set_sink(sink)
        try:
            with progress.ticking("solving (cp-sat)", None, every_s=0.01):
                deadline = time.monotonic() + 30
                while "running" not in out.getvalue() and time.monotonic() < deadline:
                    time.sleep(0.01)
        finally:
            progress.set_sink(previous)
    assert out.getvalue().startswith("progress: solving (cp-sat) running (") and tty.getvalue() == ""
