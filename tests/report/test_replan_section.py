"""The "Re-plan" section of report.html (:mod:`planner.report.replan_section`), rendered from a plan.json's data:
stations done, kept, added, dropped (blocked said) and moved by number and label, the walls lost by zone, the rest
with its bound and scope; nothing for a plan that is no re-plan."""

from __future__ import annotations

from planner.report.replan_section import replan_section

META = {
    "stations": [
        {"id": "A-in-G1", "number": 3, "status": "done"},
        {"id": "B-in-G2", "number": 1},
        {"id": "C-in-G5", "number": 2},
    ],
    "replan": {
        "rest": {"stations": 2, "bound": 2, "bound_scope": "pool"},
        "changes": {
            "done": ["A-in-G1"],
            "kept": ["B-in-G2"],
            "added": ["C-in-G5"],
            "dropped": ["C-in-G1", "D-in-G1"],
            "blocked": ["C-in-G1"],
            "moved": [{"station": "A-in-G1", "distance_m": 0.2}],
            "walls_lost_m": {"D/inside": 21.0},
        },
    },
}


def test_the_section_names_every_change():
    html = replan_section(META)
    assert html.startswith("<h2>Re-plan</h2>")
    assert "1: 3 A-in-G1" in html and "1: 1 B-in-G2" in html and "1: 2 C-in-G5" in html
    assert "2: C-in-G1 (blocked), D-in-G1" in html  # dropped: not in this plan, by label
    assert "1: 3 A-in-G1 0.20 m" in html
    assert "21.0 m (D/inside 21.0 m)" in html
    assert "2 stations to go; bound 2 (scope: pool)" in html


def test_the_report_numbering_wins_and_no_replan_no_section():
    html = replan_section(META, {"A-in-G1": 7}.get)  # type: ignore[arg-type]
    assert "7 A-in-G1" in html and "B-in-G2" in html and "1 B-in-G2" not in html
    assert replan_section({"stations": []}) == ""
    assert replan_section({"replan": {"changes": None}}) == ""
