"""Progress: a bar on a terminal, whole lines now and then when standard error is not a terminal (from
``LINES_AFTER_S`` into the run), nothing with --quiet; the library itself never prints."""

from __future__ import annotations

import io
import threading

import pytest

import planner
from planner.cli import main
from planner.core import progress
from tests.conftest import INSTANCES


class FakeTTY(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_bar_draws_in_place_and_closes_once():
    out = io.StringIO()
    bar = progress.Bar(out, width=10)
    bar("coverage build", 1, 4)
    bar("coverage build", 4, 4)
    bar("coverage build", 4, 4)  # closing twice draws once
    text = out.getvalue()
    assert "[##........]  25 %" in text  # 1/4 of 10 cells = 2.5, rounded half to even: 2 cells
    assert text.count("\n") == 1 and "[##########] 100 %" in text


def test_ticking_reports_elapsed_time_against_the_limit():
    seen: list[tuple[str, float, float]] = []
    ticked = threading.Event()

    def sink(s: str, d: float, t: float) -> None:
        seen.append((s, d, t))
        ticked.set()

    previous = progress.set_sink(sink)
    try:
        with progress.ticking("solving", 10.0, every_s=0.01):
            assert ticked.wait(30)  # the background thread reports while the body runs (no sleep to race)
    finally:
        progress.set_sink(previous)
    assert len(seen) >= 2 and all(s == "solving" and t == 10.0 for s, _, t in seen)
    assert all(0 <= d <= 10.0 for _, d, _ in seen[:-1])
    assert seen[-1][1] == 10.0  # closed at the end


@pytest.mark.slow
def test_cli_shows_bars_only_on_a_terminal_without_quiet(monkeypatch, tmp_path):
    args = ["plan", str(INSTANCES / "polygon_b.json"), "--method", "greedy"]
    for quiet, expect in ((False, True), (True, False)):
        err = FakeTTY()
        monkeypatch.setattr("sys.stderr", err)
        assert main(args + (["--quiet"] if quiet else [])) == 0
        assert ("coverage build" in err.getvalue()) is expect
    err = io.StringIO()  # not a terminal: a short run writes nothing ...
    monkeypatch.setattr("sys.stderr", err)
    assert main(args) == 0
    assert err.getvalue() == ""
    monkeypatch.setattr(progress, "LINES_AFTER_S", 0.0)  # ... a long one (here: from the start) whole lines
    err = io.StringIO()
    monkeypatch.setattr("sys.stderr", err)
    assert main(args) == 0
    lines = err.getvalue().splitlines()
    assert lines and all(line.startswith("progress: ") and "\r" not in line for line in lines)
    assert any("coverage build" in line for line in lines)
    err = io.StringIO()
    monkeypatch.setattr("sys.stderr", err)
    assert main(args + ["--quiet"]) == 0
    assert err.getvalue() == ""


def test_lines_stay_silent_for_the_first_seconds_then_write_one_now_and_then():
    now = [0.0]
    out = io.StringIO()
    lines = progress.Lines(out, every_s=30.0, clock=lambda: now[0], after_s=30.0)
    for k in range(120):  # 120 reports over 119 s: silent before 30 s, then a line at 30, 60 and 90 s
        now[0] = float(k)
        lines("solving (cp-sat)", k, 0.0)
        if k == 10:
            lines.note("an early phase ended")  # before after_s: not shown
    lines.note("bound 21 over the pool")
    text = out.getvalue().splitlines()
    assert text == [
        "progress: solving (cp-sat) running (30 s)",
        "progress: solving (cp-sat) running (60 s)",
        "progress: solving (cp-sat) running (90 s)",
        "progress: bound 21 over the pool (119 s)",
    ]
    assert isinstance(progress.sink_for(io.StringIO()), progress.Lines)
    assert progress.sink_for(io.StringIO()).after_s == progress.LINES_AFTER_S > 0  # type: ignore[union-attr]


@pytest.mark.slow
def test_library_prints_nothing(capsys):
    site = planner.load_site(INSTANCES / "polygon_b.json")
    plan = planner.plan_site(site, planner.PlanOptions(method="milp", tripod=True))
    planner.run_network(site, list(plan.stations))
    out, err = capsys.readouterr()
    assert out == "" and err == ""


def test_a_note_is_a_line_of_its_own_and_logged(caplog):
    # a note ends the bar's line ("\r" first) and stands on its own line; the library also logs it at INFO
    out = io.StringIO()
    bar = progress.Bar(out, width=10)
    previous = progress.set_sink(bar)
    try:
        bar("tiles", 1, 4)
        with caplog.at_level("INFO", logger="planner.core.progress"):
            progress.note("tile 1/4 (row 0, col 0): 3 stations, tile bound 3, optimal")
    finally:
        progress.set_sink(previous)
    text = out.getvalue()
    assert "\rtile 1/4 (row 0, col 0): 3 stations, tile bound 3, optimal" in text and text.endswith("\n")
    assert caplog.messages == ["tile 1/4 (row 0, col 0): 3 stations, tile bound 3, optimal"]
    progress.note("no sink: only logged")  # a sink of None shows nothing and raises nothing
