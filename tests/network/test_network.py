"""The station network of a plan: graph, diagnostics, proposed control, accuracy check, CLI."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from planner.cli import main
from planner.instrument.models import load_instrument
from planner.network.check import accuracy_check, registration_sigma_m, run_network
from planner.network.graph import diagnostics, station_network
from planner.site import ScanSide, Site, Zone
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ControlPoint, Obstacle
from tests.conftest import INSTANCES


def room_site(obstacles=()) -> Site:
    z = Zone("R", ScanSide.INSIDE, ((0, 0), (40, 0), (40, 20), (0, 20)), (3.0,) * 4)
    return Site("room", (z,), obstacles=tuple(obstacles), instrument="dissertation-tables")


def st(name: str, x: float, y: float) -> Candidate:
    return Candidate(name, "R", ScanSide.INSIDE, "site", x, y, CandidateKind.GRID)


def test_registration_sigma_of_seed_003():
    # 6.8e-5 * R + 0.0081 m: 8.1 mm at 0 m, 10.14 mm at 30 m
    assert registration_sigma_m(30.0) == pytest.approx(0.01014)


def test_wall_of_obstacle_cuts_sight_and_articulation_point():
    # a column between S1 and S3 hides them from each other; S2 sees both: the chain S1 - S2 - S3
    col = Obstacle("col", ((18, 8), (22, 8), (22, 12), (18, 12)), 3.0)
    site = room_site([col])
    stations = [st("S1", 5, 10), st("S2", 20, 3), st("S3", 35, 10)]
    g = station_network(site, stations, [ControlPoint("C", 2, 10)], [], 1000.0)
    assert not g.has_edge("S1", "S3") and g.has_edge("S1", "S2") and g.has_edge("S2", "S3")
    d = diagnostics(g)
    assert "S2" in d.articulation_points and d.untied_stations == []
    # C (2, 10) sees S1 and S2 but the column hides S3: its shortest way to control runs through S2
    assert d.paths_to_control["S3"][:2] == ["S3", "S2"] and d.paths_to_control["S3"][-1] == "C"


def test_proposed_control_and_check_on_a_room():
    site = room_site()
    stations = [st("S1", 10, 10), st("S2", 30, 10)]
    rep = run_network(site, stations)
    assert len(rep.control) == 3 and all(c.proposed for c in rep.control)
    xy = [(c.x, c.y) for c in rep.control]
    assert min(math.dist(p, q) for i, p in enumerate(xy) for q in xy[i + 1 :]) > 5.0
    assert rep.diagnostics.untied_stations == [] and set(rep.station_sigma_m) == {"S1", "S2"}
    # Topcon OS-105: 2 mm + 2 ppm to prisms, 5"; stations 6-25 m from fixed control: a few mm at most
    assert 0 < max(rep.station_sigma_m.values()) < 0.005
    assert rep.check["pass"] and rep.check["targets"] > 0


def test_accuracy_check_uses_the_adjusted_station_error():
    # e = sqrt(sigma_station^2 + 0.5^2 + 0.5^2 + sigma_meas^2), sigma_meas = 1.2 mm + 10 ppm with 8" over
    # 10-35 m, i.e. 1.3-1.9 mm. With S1 at 9.5 mm the worst piece stays below
    # sqrt(9.5^2 + 0.5 + 1.9^2) = 9.71 mm; S1 alone at 9.9 mm exceeds 10 mm already at 1.3 mm
    # (sqrt(9.9^2 + 0.5 + 1.3^2) = 10.01 mm)
    site = room_site()
    stations = [st("S1", 10, 10), st("S2", 30, 10)]
    check = accuracy_check(
        site,
        stations,
        rep_problem(site, stations),
        {"S1": 0.0095, "S2": 0.0005},
        load_instrument("dissertation-tables"),
    )
    assert check["pass"]
    alone = accuracy_check(
        site, stations[:1], rep_problem(site, stations[:1]), {"S1": 0.0099}, load_instrument("dissertation-tables")
    )
    assert not alone["pass"] and alone["failing_stations"] == ["S1"]
    assert "add a control point near it" in alone["suggestions"][0]


def test_accuracy_check_fails_a_wall_left_unseen():
    # one station in the corner (2, 2) of the 40 x 20 room: at theta_max 68 deg it sees a piece of a long wall
    # only within 2 tan 68 = 4.95 m of its foot, so most of the 120 m of wall is seen by no station: every piece
    # it sees passes, yet the check fails and counts the unseen pieces (it passed on the seen ones before)
    site = room_site()
    stations = [st("S1", 2, 2)]
    problem = rep_problem(site, stations)
    check = accuracy_check(site, stations, problem, {"S1": 0.0005}, load_instrument("dissertation-tables"))
    seen = int((np.diff(problem.by_target.indptr) > 0).sum())
    assert check["failing_targets"] == 0 and 0 < seen < len(problem.targets)
    assert check["unseen_targets"] == len(problem.targets) - seen and not check["pass"]


def rep_problem(site, stations):
    from planner.coverage.matrix import build_coverage
    from planner.coverage.targets import make_targets
    from planner.coverage.visibility import sight_limits
    from planner.site.validate import validate_site

    return build_coverage(site, stations, make_targets(site, 1.0), sight_limits(validate_site(site), False, True))


@pytest.mark.slow
def test_network_cli_writes_ellipses(tmp_path, capsys):
    out = tmp_path / "b"
    assert main(["plan", str(INSTANCES / "polygon_b.json"), "--method", "greedy", "--out", str(out)]) == 0
    assert (
        main(
            [
                "network",
                str(INSTANCES / "polygon_b.json"),
                str(out / "plan.json"),
                "--out",
                str(out),
                "--monte-carlo",
                "100",
            ]
        )
        == 0
    )
    text = capsys.readouterr().out
    assert "accuracy check at 10 mm" in text and "Monte Carlo (100 runs" in text
    # one line per network part, each naming its part and giving the stations' RMS apart from the other points
    mc = [line for line in text.splitlines() if line.startswith("Monte Carlo")]
    assert len(mc) >= 1 and all("station RMS" in line and "adjusted points" in line for line in mc)
    assert len(mc) == 1 or all(f"network part {k} of {len(mc)}" in line for k, line in enumerate(mc, 1))
    data = json.loads((out / "network.json").read_text())
    plan = json.loads((out / "plan.json").read_text())
    for s in plan["stations"]:
        e = data["stations"][s["id"]]
        # 95 % of a 2-D normal: chi2_2(0.95) = -2 ln 0.05, scale sqrt(5.9915) = 2.4477
        assert e["ellipse_a_m"] >= e["ellipse_b_m"] > 0
        assert e["ellipse95_a_m"] == pytest.approx(math.sqrt(-2 * math.log(0.05)) * e["ellipse_a_m"])
    # total-station observations only on the (proposed) control traverse: no sight lines between stations
    kinds = {k for edge in data["edges"] for k in edge["kinds"]}
    assert kinds >= {"tie", "traverse"} and not kinds & {"sight", "delaunay"}


def test_field_observations_are_adjusted(tmp_path):
    # observations generated from the design itself (distances + 1 mm, sigma 2 mm; directions exact, sigma
    # 5"): the directions (5" at 10-20 m is 0.2-0.5 mm) hold the stations at the design, so each of the 4
    # distances keeps its -1 mm residual: vPv = 4 (1/2)^2 = 1 on 8 - 6 = 2 degrees of freedom (two stations
    # and two orientation unknowns), m0 = sqrt(1/2) = 0.707
    from planner.io.network_files import adjust_observations

    site = room_site()
    rep = run_network(site, [st("S1", 10, 10), st("S2", 30, 10)])
    g = rep.graph
    obs = []
    for u, v, d in g.edges(data=True):
        if g.nodes[u]["kind"] == "station":
            az = math.degrees(math.atan2(g.nodes[v]["y"] - g.nodes[u]["y"], g.nodes[v]["x"] - g.nodes[u]["x"]))
            obs += [
                {"kind": "direction", "at": u, "to": v, "value": az, "sigma": 5 / 3600},
                {"kind": "distance", "at": u, "to": v, "value": d["length_m"] + 0.001, "sigma": 0.002},
            ]
    (tmp_path / "obs.json").write_text(json.dumps({"angle_unit": "deg", "length_unit": "m", "observations": obs}))
    text = adjust_observations(rep, str(tmp_path / "obs.json"))
    assert "(pass)" in text and "dof 2" in text
    assert float(re.search(r"m0 ([0-9.]+)", text).group(1)) == pytest.approx(math.sqrt(0.5), abs=0.01)
    for name, x, y in (("S1", 10.0, 10.0), ("S2", 30.0, 10.0)):
        got = re.search(rf"{name}: x ([-0-9.]+) y ([-0-9.]+)", text)
        assert got and abs(float(got.group(1)) - x) < 5e-4 and abs(float(got.group(2)) - y) < 5e-4


def test_monte_carlo_below_100_runs_is_a_usage_error(tmp_path, capsys):
    (tmp_path / "p.json").write_text(
        json.dumps({"stations": [{"id": "S", "zone": "B", "side": "inside", "x": 50, "y": 40}]})
    )
    assert main(["network", str(INSTANCES / "polygon_b.json"), str(tmp_path / "p.json"), "--monte-carlo", "20"]) == 2


def test_station_heights_from_a_control_height():
    # one control point with a height: the stations get height errors from levelling along the traverse
    # legs and through their ties
    site = room_site()
    ctrl = [ControlPoint("C1", 5, 5, z=100.0), ControlPoint("C2", 35, 5), ControlPoint("C3", 20, 18)]
    rep = run_network(site, [st("S1", 10, 10), st("S2", 30, 10)], control=ctrl)
    data = rep.to_dict()["stations"]
    assert set(rep.sigma_h_m) == {"S1", "S2"} and all(0 < v < 0.005 for v in rep.sigma_h_m.values())
    assert data["S1"]["point_error_3d_m"] > data["S1"]["position_error_m"]


@pytest.mark.slow
def test_network_numbers_do_not_depend_on_the_hash_seed(tmp_path):
    # the adjustment's unknowns were ordered by set iteration, so the last digits of the station errors (and
    # the network figure) changed with PYTHONHASHSEED; two processes with different seeds must agree exactly
    import os

    from tests.conftest import INSTANCES
    from tests.io.cli import planner_cli

    assert (
        main(["plan", str(INSTANCES / "polygon_b.json"), "--method", "greedy", "--out", str(tmp_path), "--quiet"]) == 0
    )
    outs = []
    for seed in ("0", "1"):
        out = tmp_path / f"n{seed}"
        args = ("network", str(INSTANCES / "polygon_b.json"), str(tmp_path / "plan.json"), "--out", str(out), "--quiet")
        run = planner_cli(*args, env={**os.environ, "PYTHONHASHSEED": seed})
        assert run.returncode == 0, run.stderr
        outs.append((out / "network.json").read_text())
    assert outs[0] == outs[1]


@pytest.mark.slow
def test_network_json_is_strict_and_names_pieces_of_untied_stations(tmp_path, capsys):
    # The courtyard's court and room stations are tied to no control point, so their pieces have no finite
    # error. network.json must still be strict JSON (no Infinity/NaN tokens: JavaScript's JSON.parse refuses
    # them): those errors are null with "untied": true, counted in "untied_targets", and the overall worst is
    # the worst finite one, said to be so in the summary.
    assert main(["plan", str(INSTANCES / "courtyard.json"), "--network", "--out", str(tmp_path)]) == 0
    text = (tmp_path / "network.json").read_text()

    def refuse(token):
        raise ValueError(token)

    check = json.loads(text, parse_constant=refuse)["accuracy_check"]
    zones = {z["zone"]: z for z in check["zones"]}
    assert zones["court"]["untied"] and zones["court"]["worst_e_m"] is None
    assert not zones["hall"]["untied"] and zones["hall"]["worst_e_m"] == check["worst_e_m"]
    assert check["untied_targets"] > 0 and not check["pass"]
    assert all((t["e_m"] is None) == t["untied"] for t in check["worst_targets"])
    assert f"{check['untied_targets']} pieces seen by untied stations only" in capsys.readouterr().out
