"""field.html renders in headless Chromium, as the report does (tests/report/test_report.py): a plan of
house_doors with its field sheet, the page's own script marking every image decoded, one table row per setup."""

from __future__ import annotations

import json
import re
import subprocess

import pytest

from planner.cli import main
from tests.conftest import INSTANCES
from tests.report.test_report import _chromium


@pytest.fixture(scope="module")
def sheet(tmp_path_factory):
    out = tmp_path_factory.mktemp("field")
    code = main(
        [
            "plan",
            str(INSTANCES / "house_doors.json"),
            "--method",
            "greedy",
            "--out",
            str(out),
            "--field",
            str(out),
            "--set",
            "field-mode=registration",
            "--quiet",
        ]
    )
    assert code == 0
    return out


@pytest.mark.skipif(_chromium() is None, reason="no Chromium here; test_sheet_files parses field.html")
def test_field_sheet_renders_in_headless_chromium(sheet):
    cmd = [
        _chromium(),
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--virtual-time-budget=10000",
        "--dump-dom",
        (sheet / "field.html").as_uri(),
    ]
    dom = subprocess.run(cmd, check=False, capture_output=True, text=True, timeout=120).stdout
    # the sheet's own script writes how many images decoded once the page has loaded: the one plan figure
    assert 'data-images-ok="1/1"' in dom
    order = json.loads((sheet / "field.json").read_text())["order"]
    setups = dom.split("<h2>Setups</h2>", 1)[1].split("</table>", 1)[0]
    # one row per setup, in visiting order, after the header row; the totals row last
    ids = re.findall(r"<tr><td class=\"\">(\d+)</td><td class=\"l\">([^<]+)</td>", setups)
    assert [sid for _, sid in ids] == order
    assert [int(k) for k, _ in ids] == list(range(1, len(order) + 1))
    assert f"total: {len(order)} setups" in setups
