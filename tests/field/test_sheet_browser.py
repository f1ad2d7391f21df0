"""field.html renders in headless Chromium, as the report does (tests/report/test_report.py): a plan of
house_doors with its field sheet (registration order, with targets), the page's own script marking every image
decoded, one table row per setup; its interactive site map loads without a script error, a tap on a station
highlights the wall it covers (the pieces of the sheet's coverage matrix), its links and its setup-table row, and
a click on a row selects its station; the page fetches nothing (no http(s) address)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

import planner
from planner.field.run import FieldOptions, FieldPlan, field_plan
from planner.field.sheet import write_sheet
from planner.field.site_map import setup_row_id
from tests.browser import body_attributes, chromium, dump_dom, probe
from tests.conftest import INSTANCES

URL = re.compile(r"https?://", re.IGNORECASE)
NO_CHROMIUM = "no Chromium here; test_field and test_walls parse field.html"


@pytest.fixture(scope="module")
def sheet(tmp_path_factory) -> tuple[FieldPlan, Path]:
    """house_doors planned by greedy, its field sheet in registration order (as ``--set field-mode=registration``)
    and the folder it was written to."""
    out = tmp_path_factory.mktemp("field")
    plan = planner.plan_site(planner.load_site(INSTANCES / "house_doors.json"), planner.PlanOptions(method="greedy"))
    fp = field_plan(plan.problem.sight, plan.stations, FieldOptions(mode="registration"))
    write_sheet(fp, out)
    return fp, out


@pytest.mark.slow  # a headless browser; the parse tests of the sheet are quick
@pytest.mark.skipif(chromium() is None, reason=NO_CHROMIUM)
def test_field_sheet_renders_in_headless_chromium(sheet):
    fp, out = sheet
    html = (out / "field.html").read_text()
    assert not URL.search(html)  # self-contained: no script, font or image fetched
    dom = dump_dom(out / "field.html")
    # the sheet's own script writes how many images decoded once the page has loaded: the one plan figure (the
    # site map is inline SVG, no image)
    assert 'data-images-ok="1/1"' in dom
    assert not URL.search(dom)
    order = json.loads((out / "field.json").read_text())["order"]
    assert order == [fp.stations[k].id for k in fp.order]
    # the site map after the summary, before the setup table
    assert dom.index("<h1>") < dom.index("<h2>Site map</h2>") < dom.index('id="field-map"') < dom.index("<h2>Setups")
    setups = dom.split("<h2>Setups</h2>", 1)[1].split("</table>", 1)[0]
    # one row per setup, in visiting order, after the header row, each with its id; the totals row last
    ids = re.findall(r'<tr id="setup-(\d+)"[^>]*><td class="">(\d+)</td><td class="l">([^<]+)</td>', setups)
    assert [sid for *_, sid in ids] == order
    assert [int(k) for k, _, _ in ids] == [int(k) for _, k, _ in ids] == list(range(1, len(order) + 1))
    assert f"total: {len(order)} setups" in setups


PROBE = probe(
    """
    var st = document.querySelector('#field-map .sm-st[data-id="__ID__"]');
    st.dispatchEvent(new MouseEvent('click', {bubbles: true, cancelable: true, view: window}));
    var hl = document.querySelectorAll('#field-map .sm-cv line.hl'), n = 0;
    for (var i = 0; i < hl.length; i++) n += +hl[i].getAttribute('data-n');
    b.setAttribute('data-hl-runs', hl.length);
    b.setAttribute('data-hl-pieces', n);
    b.setAttribute('data-hl-links', document.querySelectorAll('#field-map .sm-lk.hl').length);
    b.setAttribute('data-panel', document.querySelector('#field-map .sm-panel').textContent);
    var rows = document.querySelectorAll('tr.sm-row'), ids = [];
    for (var j = 0; j < rows.length; j++) ids.push(rows[j].id);
    b.setAttribute('data-rows', ids.join(' '));
    document.getElementById('__ROW__').click();
    b.setAttribute('data-row-selects', (document.querySelector('#field-map .sm-st.sm-sel') || {id: ''}).getAttribute('data-id'));
"""
)


@pytest.mark.slow
@pytest.mark.skipif(chromium() is None, reason=NO_CHROMIUM)
def test_tap_on_a_station_highlights_its_wall_links_and_setup_row(sheet, tmp_path):
    fp, out = sheet
    assert fp.coverage is not None
    by_station = fp.coverage.by_candidate
    # the first setup that covers wall, and the setup after it (whose row is clicked)
    n, k = next((n, k) for n, k in enumerate(fp.order, 1) if by_station.indptr[k + 1] > by_station.indptr[k])
    station, other = fp.stations[k], fp.stations[fp.order[n % len(fp.order)]]
    html = (out / "field.html").read_text()
    script = PROBE.replace("__ID__", station.id).replace("__ROW__", setup_row_id(n % len(fp.order) + 1))
    page = tmp_path / "probe.html"
    page.write_text(html.replace("</body>", script + "</body>"))
    b = body_attributes(dump_dom(page))
    assert json.loads(b["data-errors"]) == []  # no script error, no console error
    pieces = int(by_station.indptr[k + 1] - by_station.indptr[k])
    assert int(b["data-hl-pieces"]) == pieces > 0  # every piece it covers, from the sheet's coverage matrix
    assert 0 < int(b["data-hl-runs"]) <= pieces  # drawn as runs of consecutive pieces
    assert int(b["data-hl-links"]) == sum(1 for lk in fp.links if station.id in (lk.a, lk.b))
    assert station.id in b["data-panel"] and "covers" in b["data-panel"] and "setup table" in b["data-panel"]
    assert f"field visit no. {n}" in b["data-panel"]
    assert b["data-rows"] == setup_row_id(n)  # its row, and only its row, marked
    assert b["data-row-selects"] == other.id  # a click on the next row shows that setup's station
