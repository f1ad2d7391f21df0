"""The README's main job, run as a newcomer runs it: the planner command of its first Quick-start line
(the one after the ``main-job`` marker), with ``out/...`` moved into a temporary folder.

It plans the assembled Baalbek site (one frame, with doors) as one network, and its report opens with the
whole site and carries the interactive map; neither the report nor the field sheet loads anything from the
network; the printable field sheet is written beside them; every station has one number (its place in the walking
order) and one label in every page and file of the run (tests/report/test_station_identity.py)."""

from __future__ import annotations

import json
import re
import shlex
from pathlib import Path

import pytest

from planner.cli import main
from tests.report.test_station_identity import check_station_identity

ROOT = Path(__file__).resolve().parent.parent

#: an address a page would fetch: src/href/url() to http(s) or protocol-relative
FETCH = re.compile(r"""(?:src|href)\s*=\s*["']?\s*(?:https?:)?//|url\(\s*["']?\s*(?:https?:)?//""", re.IGNORECASE)


def main_job_args() -> list[str]:
    """The ``planner ...`` arguments of the README's main-job line (after the install's ``&&``)."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    block = text.split("<!-- main-job", 1)[1].split("```sh", 1)[1].split("```", 1)[0]
    command = next(part.strip() for part in block.strip().split("&&") if part.strip().startswith("planner "))
    return shlex.split(command)[1:]


def test_the_main_job_is_the_assembled_temple_with_its_report_and_field_sheet() -> None:
    args = main_job_args()
    assert args[:2] == ["plan", "instances/baalbek_site_doors.json"]
    for flag in ("--network", "--report", "--field", "--out", "--export"):
        assert flag in args


@pytest.mark.slow
@pytest.mark.heavy
def test_the_main_job_runs_and_its_pages_open_with_the_whole_site(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(ROOT)  # the README's paths are relative to the checkout
    args = [str(tmp_path / a[4:]) if a.startswith("out/") else a for a in main_job_args()]
    assert main([*args, "--quiet"]) == 0
    out = tmp_path / "baalbek"
    plan = json.loads((out / "plan.json").read_text())
    ids = [s["id"] for s in plan["stations"]]
    report = (out / "report.html").read_text()
    # the first section after the title is the whole site, then the map; the per-zone plans come later
    assert re.findall(r"<h2>([^<]+)</h2>", report)[:2] == ["Site plan", "Site map"]
    assert report.index("the whole site: stations numbered in walking order") < report.index("<h2>Plans</h2>")
    # the map holds one marker per station of the plan (each station's marker carries its id)
    assert sorted(re.findall(r'<g class="sm-st sm-mk"[^>]*\bdata-id="([^"]+)"', report)) == sorted(ids)
    field = (out / "field.html").read_text()
    for page in (report, field):
        assert not FETCH.search(page), FETCH.search(page)
    assert (out / "field.pdf").read_bytes().startswith(b"%PDF")
    order = json.loads((out / "field.json").read_text())["order"]
    assert sorted(order) == sorted(ids)  # the walking order visits every station once
    # one number and one label per station everywhere: the site plan, the map, the tables, the sheet, the exports
    assert check_station_identity(out) == "walking order"
    assert [s["id"] for s in sorted(plan["stations"], key=lambda s: s["number"])] == order
