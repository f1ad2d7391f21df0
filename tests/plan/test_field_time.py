"""Plans for the hours on site (issue 47): ``--max-point-spacing`` and ``--objective field-time``.

The room: 24 m x 6 m, walls 3 m, Leica P30 (leica-p30.toml: set-up 180 s; scans 20, 80, 331 and 1,242 s at
12.5, 6.3, 3.1 and 1.6 mm @ 10 m), the instrument on the floor (the JSON format's default height 0). At 6 mm
the coarsest setting reaches no piece: its top is 3 m above the instrument, so the vertical spacing is at least
2 x 3 m x 1.25e-3 = 7.5 mm (planner.coverage.spacing); 6.3 mm @ 10 m needs a view with hd + 9 / hd <= 6 / 0.63
= 9.52 m and hd^2 / d <= 9.52 m, which only near views meet.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from planner.cli import main
from planner.core.errors import ExitCode, UsageError
from planner.engine import plan_site
from planner.plan import PlanOptions
from planner.plan.hours.columns import setting_columns, useful_settings
from planner.plan.hours.field_time import field_properties
from planner.plan.problem import resolve
from planner.plan.run import build_problem
from planner.solve.milp import MilpOptions

SETUP_S = 180.0
SCAN_S = {"12.5 mm @ 10 m": 20.0, "6.3 mm @ 10 m": 80.0, "3.1 mm @ 10 m": 331.0, "1.6 mm @ 10 m": 1242.0}


def _room(tmp_path: Path, dx: float = 0.0, dy: float = 0.0) -> Path:
    zone = {
        "id": "R",
        "scan_side": "inside",
        "coordinates": [[dx, dy], [dx + 24, dy], [dx + 24, dy + 6], [dx, dy + 6]],
        "height_m": 3.0,
    }
    path = tmp_path / f"room_{dx:g}_{dy:g}.json"
    path.write_text(json.dumps({"name": "room", "instrument": "leica-p30", "zones": [zone]}))
    return path


def _plan(args: list[str], out: Path) -> dict:
    assert main(["plan", *args, "--quiet", "--out", str(out)]) == ExitCode.OK
    return json.loads((out / "plan.json").read_text())


def _setup_scan(plan: dict) -> float:
    return sum(SETUP_S + SCAN_S[s["setting"]] for s in plan["stations"])


@pytest.fixture(scope="module")
def plans(tmp_path_factory) -> dict[str, dict]:
    tmp = tmp_path_factory.mktemp("hours")
    room = _room(tmp)
    return {
        "stations": _plan([str(room), "--max-point-spacing", "0.006"], tmp / "s"),
        "field-time": _plan([str(room), "--max-point-spacing", "0.006", "--objective", "field-time"], tmp / "f"),
    }


def test_each_station_has_a_setting_and_the_time_adds_up(plans):
    for objective, plan in plans.items():
        h = plan["hours"]
        assert h["objective"] == objective
        assert [s["setting"] for s in plan["stations"]] == h["settings"]
        # set-up + scan, summed station by station from the model's table
        assert h["setup_scan_s"] == pytest.approx(_setup_scan(plan))
        assert h["setup_s"] == pytest.approx(SETUP_S * len(plan["stations"]))


def test_the_field_time_plan_is_proven_within_1_percent_and_no_slower(plans):
    ft, fewest = plans["field-time"]["hours"], plans["stations"]["hours"]
    bound = ft["setup_scan_bound"]
    assert bound["scope"] == "pool" and bound["gap"] <= 0.01
    assert bound["bound_s"] <= ft["setup_scan_s"] + 1e-6
    # the fewest-stations plan is one of the plans the field-time MILP chose among
    assert ft["setup_scan_s"] <= fewest["setup_scan_s"] + 1e-6
    assert len(plans["field-time"]["stations"]) >= len(plans["stations"]["stations"])


def test_every_plan_meets_the_spacing_in_verification(plans):
    for plan in plans.values():
        assert plan["verification"]["percent"] == 100.0
        spacing = plan["hours"]["spacing"]
        assert spacing["complete"] and spacing["percent"] == 100.0
        assert spacing["worst_m"] <= 0.006 * (1 + 1e-9)
        assert plan["registration"]["connected"]


def test_the_trade_off_table_keeps_the_plan_of_least_total(plans):
    t = plans["field-time"]["hours"]["tradeoff"]
    rows = {r["label"]: r for r in t["rows"]}
    # 12.5 mm @ 10 m cannot give the 3 m tops 6 mm (7.5 mm at best): listed, without a plan
    assert rows["one setting: 12.5 mm @ 10 m"]["stations"] is None
    assert rows["one setting: 12.5 mm @ 10 m"]["note"] == "does not meet the spacing"
    timed = [r for r in t["rows"] if r["total_s"] is not None]
    kept = rows[t["kept"]]
    assert kept["total_s"] == min(r["total_s"] for r in timed)
    for r in timed:  # each total is its parts
        assert r["total_s"] == pytest.approx(r["setup_s"] + r["scan_s"] + r["walking_s"] + r["targets_s"])
    best = min(r["total_s"] for r in timed if r["label"].startswith("one setting"))
    assert t["gain_s"] == pytest.approx(best - kept["total_s"]) and t["gain_s"] >= 0


def test_a_spacing_no_setting_reaches_is_refused_before_any_solver(tmp_path, capsys):
    room = _room(tmp_path)
    code = main(["plan", str(room), "--max-point-spacing", "0.0005", "--quiet"])
    assert code == ExitCode.INFEASIBLE
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and str(room) in err
    assert "at a point spacing of at most 0.5 mm, even at the finest setting '1.6 mm @ 10 m'" in err
    assert "(finest " in err  # each piece with the finest spacing it gets


def _room_pool(tmp_path):
    """The 24 x 6 m room's coverage at a 6 mm spacing and its instrument's field table (the P30's)."""
    problem = resolve(__import__("planner").load_site(str(_room(tmp_path))), PlanOptions(max_point_spacing_m=0.006))
    return build_problem(problem), field_properties(problem.site)


def test_columns_keep_a_finer_setting_only_where_it_covers_more(tmp_path):
    cov, props = _room_pool(tmp_path)
    cols = setting_columns(cov, props, 0.006)
    names = [n for n, _, _ in props.by_step()]
    covering = np.diff(cols.matrix.indptr) > 0
    assert "12.5 mm @ 10 m" not in {cols.names[s] for s in cols.setting[covering]}  # no piece at 7.5 mm or finer
    # every candidate has one pair at the cheapest setting: where it meets the spacing on no piece there, a relay
    # covering nothing (registration is judged on what stations see; a relay need not pay for a finer setting)
    relays = cols.candidate[~covering]
    assert len(set(relays.tolist())) == len(relays)
    assert {cols.names[s] for s in cols.setting[~covering]} <= {"12.5 mm @ 10 m"}
    cheapest = cols.names.index("12.5 mm @ 10 m")
    assert sorted(cols.candidate[cols.setting == cheapest].tolist()) == list(range(len(cov.candidates)))
    assert np.allclose(cols.cost_s, [SETUP_S + SCAN_S[names[s]] for s in cols.setting])
    count = np.diff(cols.matrix.indptr)
    for c in np.unique(cols.candidate):
        mine = np.flatnonzero(cols.candidate == c)
        mine = mine[np.argsort(cols.setting[mine], kind="stable")]  # coarse to fine
        assert all(np.diff(count[mine]) > 0)  # each finer pair covers more


def test_a_setting_no_coarser_and_no_dearer_than_another_is_dropped():
    # (name, step rad, scan s), coarsest first: "b" is finer than "a" and no dearer, so "a" is useless; "d" ties
    # "c" exactly (same step, same time) and is listed after it; "e" is finer and dearer than all: kept
    settings = (("a", 2e-3, 100.0), ("b", 1e-3, 100.0), ("c", 5e-4, 300.0), ("d", 5e-4, 300.0), ("e", 2e-4, 900.0))
    assert [n for n, _, _ in useful_settings(settings)] == ["b", "c", "e"]
    kept = useful_settings(settings)
    assert all(t1 < t2 for (_, _, t1), (_, _, t2) in zip(kept, kept[1:]))  # finer always dearer


def test_moving_the_room_changes_no_count_or_time(tmp_path):
    o = PlanOptions(max_point_spacing_m=0.006, objective="field-time")
    from planner.plan.run import plan_single

    here = plan_single(resolve(__import__("planner").load_site(str(_room(tmp_path))), o))
    there = plan_single(resolve(__import__("planner").load_site(str(_room(tmp_path, 1000.0, -2000.0))), o))
    assert len(here.stations) == len(there.stations)
    assert here.hours is not None and there.hours is not None
    assert here.hours.setup_scan_s == pytest.approx(there.hours.setup_scan_s)


def test_same_command_same_plan(tmp_path):
    room = _room(tmp_path)
    o = PlanOptions(max_point_spacing_m=0.006, objective="field-time")
    a, b = plan_site(room, o), plan_site(room, o)
    assert [(s.id, s.x, s.y) for s in a.stations] == [(s.id, s.x, s.y) for s in b.stations]
    assert a.hours is not None and b.hours is not None and a.hours.settings == b.hours.settings


def test_without_the_flags_the_plan_and_its_file_are_unchanged(tmp_path):
    room = _room(tmp_path)
    plain = _plan([str(room)], tmp_path / "p")
    explicit = _plan([str(room), "--objective", "stations"], tmp_path / "e")
    assert "hours" not in plain and all("setting" not in s for s in plain["stations"])
    assert [(s["id"], s["x"], s["y"]) for s in plain["stations"]] == [
        (s["id"], s["x"], s["y"]) for s in explicit["stations"]
    ]


def test_the_field_sheet_times_each_station_at_its_own_setting(plans, tmp_path):
    plan = plans["field-time"]
    path = tmp_path / "plan.json"
    path.write_text(json.dumps(plan))
    assert main(["field", str(path), "--out", str(tmp_path / "sheet"), "--quiet"]) == ExitCode.OK
    sheet = json.loads((tmp_path / "sheet" / "field.json").read_text())
    by_id = {s["id"]: s["setting"] for s in plan["stations"]}
    assert {row["station"]: row["scan setting"] for row in sheet["setups"]} == by_id
    # each setup's minutes: set-up + its own scan (+ walk + targets)
    for row in sheet["setups"]:
        assert row["minutes"] >= round((SETUP_S + SCAN_S[by_id[row["station"]]]) / 60, 1) - 0.05


@pytest.mark.parametrize(
    ("options", "field"),
    [
        ({"objective": "hours"}, "objective"),
        ({"objective": "field-time", "method": "greedy"}, "method"),
        ({"max_point_spacing_m": 0.006, "surfaces": ("walls", "floors")}, "surfaces"),
        ({"max_point_spacing_m": 0.0}, "max_point_spacing_m"),
        # a station at two settings would count twice for k = 2; views adding information is not modelled
        ({"max_point_spacing_m": 0.006, "milp": MilpOptions(k=2)}, "k"),
        ({"objective": "field-time", "milp": MilpOptions(precision="combined")}, "precision"),
    ],
)
def test_options_that_cannot_go_together_are_refused_by_name(options, field):
    with pytest.raises(UsageError) as err:
        PlanOptions(**options)
    assert err.value.field == field


def test_the_command_line_refuses_a_bad_objective_with_exit_2(tmp_path, capsys):
    assert main(["plan", str(_room(tmp_path)), "--objective", "hours"]) == ExitCode.USAGE
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "--objective: invalid choice: 'hours'" in err


def test_the_report_shows_the_hours_and_the_trade_off(tmp_path):
    room = _room(tmp_path)
    args = ["plan", str(room), "--max-point-spacing", "0.006", "--objective", "field-time", "--quiet"]
    assert main([*args, "--out", str(tmp_path), "--report", str(tmp_path)]) == ExitCode.OK
    page = (tmp_path / "report.html").read_text()
    assert "<h2>Hours on site</h2>" in page and "<h3>Trade-off: stations and hours</h3>" in page
    section = page.split("<h2>Hours on site</h2>")[1]
    assert "at most 6 mm on every wall" in section and "does not meet the spacing" in section
    assert section.count("<tr>") >= 6 and 'src="data:image/png;base64,' in section  # the table and the figure


def test_a_plan_without_settings_has_no_hours_section(polygon_b_report):
    # polygon B planned without a spacing or an objective, with its report (the session's, tests/conftest.py)
    assert "hours" not in json.loads((polygon_b_report / "plan.json").read_text())
    assert "Hours on site" not in (polygon_b_report / "report.html").read_text()


def test_planner_verify_checks_the_spacing_at_each_station_s_setting(plans, tmp_path, capsys):
    room = _room(tmp_path)
    path = tmp_path / "plan.json"
    path.write_text(json.dumps(plans["field-time"]))
    assert main(["verify", str(room), str(path), "--max-point-spacing", "0.006"]) == ExitCode.OK
    assert "100.000 % of" in capsys.readouterr().out
    # every station at the coarsest setting: the 3 m tops cannot get 6 mm (7.5 mm at best), exit 4
    coarse = json.loads(path.read_text())
    for s in coarse["stations"]:
        s["setting"] = "12.5 mm @ 10 m"
    path.write_text(json.dumps(coarse))
    assert main(["verify", str(room), str(path), "--max-point-spacing", "0.006"]) == ExitCode.INFEASIBLE
    out = capsys.readouterr().out
    assert "points over" in out


def test_the_trade_off_counts_sessions_of_the_field_sheet_s_length(tmp_path):
    """With --set field-session=1h each timed plan's setups are packed into 1-hour sessions in visiting order, so
    a plan needs at least ceil(total / 1 h) of them (a setup never splits)."""
    room = _room(tmp_path)
    args = [str(room), "--max-point-spacing", "0.006", "--objective", "field-time", "--set", "field-session=1h"]
    plan = _plan(args, tmp_path / "s")
    timed = [r for r in plan["hours"]["tradeoff"]["rows"] if r["total_s"] is not None]
    assert timed
    for r in timed:
        assert isinstance(r["sessions"], int) and r["sessions"] >= math.ceil(r["total_s"] / 3600 - 1e-9)


def test_the_walking_part_states_its_own_bound(plans):
    """The MILP bounds set-up and scan; the route of each timed plan comes with the field sheet's lower bound."""
    for r in plans["field-time"]["hours"]["tradeoff"]["rows"]:
        if r["total_s"] is None:
            continue
        assert r["route_bound_m"] <= r["route_m"] + 1e-6 and r["route_bound_method"]
        assert r["walking_s"] == pytest.approx(r["route_m"] / 0.8, rel=0.01, abs=1.0)  # 0.8 m/s (leica-p30.toml)


def test_the_walk_search_keeps_every_rule_and_never_lengthens_the_total(plans):
    """Whatever the search moved, the kept plan covers, meets the spacing, is connected (above) and its set-up
    + scan is no dearer than the MILP's optimum (no move costs more): the bound still holds."""
    t = plans["field-time"]["hours"]["tradeoff"]
    rows = {r["label"]: r for r in t["rows"]}
    ft = rows["field time"]
    kept = rows[t["kept"]]
    assert kept["total_s"] <= ft["total_s"] + 1e-6
    if t["kept"].startswith("field time,"):  # moved for the walk
        assert kept["setup_s"] + kept["scan_s"] <= ft["setup_s"] + ft["scan_s"] + 1e-6
        assert kept["route_m"] < ft["route_m"]


@pytest.mark.slow
def test_building27_walk_search_moves_stations_and_shortens_the_route(tmp_path):
    """building27 at 6 mm (docs/field-time.md): the search moves stations of the field-time plan, the route
    gets shorter, set-up + scan stays at the MILP's optimum, and the moved plan verifies."""
    site = Path(__file__).resolve().parents[2] / "instances" / "building27.json"
    plan = plan_site(site, PlanOptions(max_point_spacing_m=0.006, objective="field-time"))
    assert plan.hours is not None and plan.hours.tradeoff is not None
    t = plan.hours.tradeoff
    moved = [r for r in t.rows if r.label.startswith("field time,")]
    assert moved and t.kept == moved[0].label
    ft = t.row("field time")
    assert moved[0].route_m < ft.route_m and moved[0].total_s < ft.total_s
    assert plan.hours.setup_scan_s == pytest.approx(plan.hours.timing["bound_s"])
    assert plan.verification.percent == 100.0 and plan.connected
    assert plan.hours.spacing is not None and plan.hours.spacing.complete


def _p30_without(tmp_path: Path, field: bool = True, finest_first: bool = False) -> Path:
    """The P30 model file, its settings listed finest first, or without its [field] table."""
    text = (Path(__file__).resolve().parents[2] / "models" / "leica-p30.toml").read_text()
    head, _, table = text.partition("[field]")
    if not field:
        text = head
    elif finest_first:
        rows = [line for line in table.splitlines() if line.startswith('"')]
        table = table.replace("\n".join(rows), "\n".join(reversed(rows)))
        text = head + "[field]" + table
    path = tmp_path / "p30.toml"
    path.write_text(text)
    return path


def test_without_a_spacing_field_time_takes_the_cheapest_setting_whatever_the_file_order(tmp_path):
    """Without a spacing every setting sees the same pieces, so each station scans at the cheapest (12.5 mm @ 10 m,
    20 s) even when the table lists the finest first."""
    model = _p30_without(tmp_path, finest_first=True)
    plan = _plan([str(_room(tmp_path)), "--instrument", str(model), "--objective", "field-time"], tmp_path / "o")
    assert {s["setting"] for s in plan["stations"]} == {"12.5 mm @ 10 m"}
    assert plan["hours"]["objective"] == "field-time"


def test_an_instrument_without_a_settings_table_is_refused_for_a_spacing(tmp_path, capsys):
    model = _p30_without(tmp_path, field=False)
    args = ["plan", str(_room(tmp_path)), "--instrument", str(model), "--max-point-spacing", "0.006", "--quiet"]
    assert main(args) == ExitCode.INVALID_INPUT
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "has no [field] table of scan settings" in err


def test_a_field_time_milp_without_a_plan_leaves_a_row_saying_so(tmp_path, monkeypatch):
    """The field-time MILP stopped before any plan (as a wall-clock cap may stop it): no crash, the row says so,
    and the plan kept is the best one timed."""
    import planner.plan.hours.field_time as ft
    from planner.solve.result import SolveResult, Status

    real = ft.solve

    def no_plan(inst, options):  # the field-time MILP (costs in seconds, above 1): no solution
        if inst.cost.max() > 1 and inst.by_candidate.shape[1] > 0 and inst.relation is not None:
            return SolveResult(method="milp", status=Status.NO_SOLUTION, selected=(), objective=None)
        return real(inst, options)

    monkeypatch.setattr(ft, "solve", no_plan)
    plan = plan_site(_room(tmp_path), PlanOptions(max_point_spacing_m=0.006, objective="field-time"))
    assert plan.hours is not None and plan.hours.tradeoff is not None
    row = plan.hours.tradeoff.row("field time")
    assert row.stations is None and row.note == "no plan (no_solution)"
    assert plan.stations and plan.hours.tradeoff.kept != "field time"
    assert any("found no plan" in line for line in plan.log)


def test_settings_of_the_fewest_stations_fall_back_to_the_finest_when_their_milp_finds_none(tmp_path, monkeypatch):
    # the settings MILP (the second solve of a stations plan with a spacing) ends with no answer: every chosen
    # station keeps the finest setting it was chosen at, set-up + scan counted for that (no traceback)
    import planner.plan.hours.field_time as ft
    from planner.solve.result import SolveResult, Status

    real = ft.solve
    calls = []

    def second_fails(inst, options):
        calls.append(1)
        if len(calls) == 1:
            return real(inst, options)
        return SolveResult(method="milp", status=Status.NO_SOLUTION, selected=(), objective=None)

    monkeypatch.setattr(ft, "solve", second_fails)
    plan = plan_site(__import__("planner").load_site(str(_room(tmp_path))), PlanOptions(max_point_spacing_m=0.006))
    info = plan.result.info
    n = len(plan.result.selected)
    assert n > 0 and info["settings"] == ["1.6 mm @ 10 m"] * n
    assert info["field_time"]["fallback"] == "1.6 mm @ 10 m"
    assert info["field_time"]["objective_s"] == pytest.approx(n * (SETUP_S + SCAN_S["1.6 mm @ 10 m"]))


def test_the_columns_with_fewer_relays_are_a_subset_of_all(tmp_path):
    # the field-time MILP may take its plan from the model with a relay only where a candidate has no other pair:
    # its columns are some of the whole model's, so the whole model's bound holds for that plan too
    cov, props = _room_pool(tmp_path)
    every = setting_columns(cov, props, 0.006)
    few = setting_columns(cov, props, 0.006, all_relays=False)
    pairs = set(zip(every.candidate.tolist(), every.setting.tolist()))
    assert set(zip(few.candidate.tolist(), few.setting.tolist())) <= pairs
    assert len(few.candidate) <= len(every.candidate) and few.names == every.names
    covering = np.diff(few.matrix.indptr) > 0
    assert set(few.candidate[~covering].tolist()).isdisjoint(few.candidate[covering].tolist())
