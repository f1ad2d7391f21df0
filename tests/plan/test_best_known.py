"""The best plans known (docs/benchmarks/best_known.json) and the gap line of planner.plan.best_known."""

from __future__ import annotations

import json

from planner.plan.best_known import BEST_KNOWN, best_known


def test_entries_have_a_command_and_a_count():
    rows = json.loads(BEST_KNOWN.read_text())["plans"]
    assert rows and all(
        r["command"] and r["stations"] > 0 and r["problem"] in ("connected", "plain cover") for r in rows
    )


def test_lookup_matches_instance_problem_mode_and_overlap():
    known = best_known("plant_16ha", "site", 0.3)
    assert known is not None and known.stations == 103 and known.problem == "connected"
    zone = best_known("plant_16ha", "zone", 0.3)  # the plain command's registration on the plant: its own entry
    assert zone is not None and zone.stations == 96 and zone.registration == "zone"
    assert best_known("plant_4ha", "zone", 0.3) is None  # no entry for that mode: nothing to compare
    assert best_known("plant_16ha", "site", 0.5) is None  # another overlap share
    plain = best_known("plant_4ha", None, 0.0)
    assert plain is not None and plain.stations == 27 and plain.proven_optimal
    # gap as the bound's: (plan - best) / plan = (105 - 103) / 105 = 1.9 %
    assert "this plan 105, gap to it 1.9 %" in known.line(105)


def test_no_file_no_entry(tmp_path):
    assert best_known("plant_16ha", "site", 0.3, tmp_path / "none.json") is None
    (tmp_path / "bad.json").write_text("{")
    assert best_known("plant_16ha", "site", 0.3, tmp_path / "bad.json") is None
