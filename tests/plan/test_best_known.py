"""The best plans known (docs/benchmarks/best_known.json) and the gap line of planner.plan.best_known: a gap only
against an entry of the same problem and pool (issue 44)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from planner.plan.best_known import BEST_KNOWN, CONNECTED, PLAIN, best_known, problem_kind

ROOT = Path(BEST_KNOWN).resolve().parents[2]
POOL = {"fingerprint": "abc123def456", "candidates": 12476, "targets": 7688, "pairs": 1277751}


def _file(tmp_path, *rows):
    path = tmp_path / "best_known.json"
    path.write_text(json.dumps({"about": "test", "plans": list(rows)}))
    return path


def _row(instance="plant_16ha", problem=CONNECTED, registration="site", overlap=0.3, stations=103, pool=POOL, **more):
    return {
        "instance": instance,
        "problem": problem,
        "registration": registration,
        "overlap": overlap,
        "stations": stations,
        "pool": pool,
        "measured": "2026-11-26",
        "command": "planner plan instances/plant_16ha.json --out DIR",
        **more,
    }


def test_entries_have_a_command_a_count_and_a_pool():
    rows = json.loads(BEST_KNOWN.read_text())["plans"]
    assert rows and all(
        r["command"] and r["stations"] > 0 and r["problem"] in (CONNECTED, PLAIN) and "pool" in r for r in rows
    )
    for r in rows:  # null (an older pool, never matched) or the pool as plan.json records it
        assert r["pool"] is None or set(r["pool"]) == set(POOL) and len(r["pool"]["fingerprint"]) == 12


def test_the_problem_is_the_plain_cover_without_a_rule():
    assert problem_kind(False) == PLAIN and problem_kind(True) == CONNECTED


def test_the_gap_only_on_the_same_pool(tmp_path):
    path = _file(tmp_path, _row(), _row(registration="zone", stations=96))
    known = best_known("plant_16ha", CONNECTED, "site", 0.3, POOL["fingerprint"], path)
    assert known is not None and known.same_pool and known.stations == 103 and known.pool == POOL
    # gap as the bound's: (plan - best) / plan = (105 - 103) / 105 = 1.9 %
    assert "this plan 105, gap to it 1.9 %" in known.line(105)
    assert known.to_dict(105)["same_pool"] and abs(known.to_dict(105)["gap"] - 2 / 105) < 1e-12
    other = best_known("plant_16ha", CONNECTED, "site", 0.3, "0123456789ab", path)
    assert other is not None and not other.same_pool and other.gap(105) is None
    line = other.line(105)
    assert "on another pool (fingerprint abc123def456; this plan's 0123456789ab), no gap printed" in line
    assert "gap to it" not in line
    assert other.to_dict(105)["same_pool"] is False and other.to_dict(105)["gap"] is None
    unknown = best_known("plant_16ha", CONNECTED, "site", 0.3, None, path)  # a plan whose pool was not recorded
    assert unknown is not None and not unknown.same_pool and "this plan's pool not recorded" in unknown.line(105)


def test_an_entry_of_an_older_pool_never_matches(tmp_path):
    path = _file(tmp_path, _row(pool=None))
    known = best_known("plant_16ha", CONNECTED, "site", 0.3, POOL["fingerprint"], path)
    assert known is not None and not known.same_pool
    assert "its pool not recorded" in known.line(105) and "gap to it" not in known.line(105)


def test_the_same_pool_is_preferred_and_the_best_of_the_others_shown(tmp_path):
    old = _row(stations=95, pool=None)
    path = _file(tmp_path, old, _row(stations=99, pool={**POOL, "fingerprint": "ffffffffffff"}), _row())
    assert best_known("plant_16ha", CONNECTED, "site", 0.3, POOL["fingerprint"], path).stations == 103
    assert best_known("plant_16ha", CONNECTED, "site", 0.3, "000000000000", path).stations == 95


def test_lookup_matches_instance_problem_mode_and_overlap(tmp_path):
    plain = _row("plant_4ha", PLAIN, None, 0.0, 26)
    path = _file(tmp_path, _row(), _row(registration="zone", stations=96), plain)
    fp = POOL["fingerprint"]
    zone = best_known("plant_16ha", CONNECTED, "zone", 0.3, fp, path)  # each registration mode its own entry
    assert zone is not None and zone.stations == 96 and zone.registration == "zone"
    assert best_known("plant_4ha", CONNECTED, "site", 0.3, fp, path) is None  # no connected entry there
    assert best_known("plant_16ha", CONNECTED, "site", 0.5, fp, path) is None  # another overlap share
    assert best_known("plant_16ha", PLAIN, None, 0.0, fp, path) is None  # a connected entry is not a plain cover
    found = best_known("plant_4ha", PLAIN, "zone", 0.3, fp, path)  # a plain cover: any mode, overlap 0
    assert found is not None and found.same_pool and found.stations == 26 and found.problem == PLAIN


def test_no_file_no_entry(tmp_path):
    assert best_known("plant_16ha", CONNECTED, "site", 0.3, None, tmp_path / "none.json") is None
    (tmp_path / "bad.json").write_text("{")
    assert best_known("plant_16ha", CONNECTED, "site", 0.3, None, tmp_path / "bad.json") is None


def _named_entries() -> list[dict]:
    """The entries naming their plan file (docs/benchmarks/plans/)."""
    named = [e for e in json.loads(Path(BEST_KNOWN).read_text())["plans"] if e.get("plan")]
    assert named, "the 16-ha connected entry names its plan file"
    return named


def test_each_plan_file_of_the_best_known_holds_its_count_on_its_pool():
    # the file has the entry's stations on the entry's pool (the slow twin below re-checks the cover from the site)
    for entry in _named_entries():
        data = json.loads((ROOT / entry["plan"]).read_text())
        assert len(data["stations"]) == entry["stations"]
        assert data["pool"] == entry["pool"]
        assert (ROOT / "instances" / f"{entry['instance']}.json").is_file()


@pytest.mark.slow
def test_each_plan_file_of_the_best_known_holds_its_count_and_is_a_connected_cover():
    # an entry naming its plan file: the file has the entry's stations on the entry's pool, and re-checked here from
    # the site alone: every wall point at 0.1 m seen, one registration part per group (the 16-ha site: 15 s)
    from planner import load_site
    from planner.io.plan_json import read_plan_stations
    from planner.plan import PlanOptions
    from planner.plan.problem import resolve
    from planner.plan.verify import verify_stations

    for entry in _named_entries():
        data = json.loads((ROOT / entry["plan"]).read_text())
        assert len(data["stations"]) == entry["stations"]
        assert data["pool"] == entry["pool"]
        problem = resolve(load_site(str(ROOT / "instances" / f"{entry['instance']}.json")), PlanOptions())
        stations = read_plan_stations(ROOT / entry["plan"], problem.site)
        assert verify_stations(problem.sight, stations, 0.1).complete
        cov = problem.sight.coverage(stations, problem.targets)
        parts, _ = problem.registration.check(cov, tuple(range(len(stations))))
        assert entry["registration"] == problem.registration.mode == "site"
        assert list(parts.values()) == [1]
