"""The "3-D view" section of report.html (:mod:`planner.report.view3d_section`): the house of two storeys read
from IFC with ``--storey all`` (both storeys in the scene, each station's covered pieces from the coverage
matrix, no address), the note on a site too large, the instrument height from the plan's surfaces, and the
view run in headless Chromium (the canvas drawn, a station picked from the list or clicked changes what is
highlighted, the storey filter and a drag work, nothing fetched)."""

from __future__ import annotations

import json
import re
from dataclasses import replace

import pytest

import planner
from planner.io.ifc_in import IfcOptions
from planner.report import view3d_section as section
from planner.report.view3d_section import MAX_WALL_PIECES, outcome_scene, view3d_section
from tests.browser import body_attributes, chromium, dump_dom, probe
from tests.conftest import INSTANCES
from tests.figures.test_view3d import room_rows
from tests.report.test_site_map import parse

URL = re.compile(r"https?://", re.IGNORECASE)


def scene_data(page: str) -> dict:
    """The 3-D view's scene JSON of a page."""
    return json.loads(page.split('class="v3-data">', 1)[1].split("</script>", 1)[0])


@pytest.fixture(scope="module")
def house2(tmp_path_factory):
    """instances/house2.ifc read with --storey all, planned by greedy, and its report.html."""
    out = tmp_path_factory.mktemp("house2")
    site = planner.load_site(INSTANCES / "house2.ifc", ifc=IfcOptions(storey="all"))
    o = planner.outcome_from_plan(planner.plan_site(site, planner.PlanOptions(method="greedy")))
    return o, planner.write_report(o, out)


@pytest.mark.slow
def test_house2_report_shows_both_storeys_and_every_stations_cover(house2):
    o, report = house2
    page = report.read_text()
    assert page.index("<h2>Site map</h2>") < page.index("<h2>3-D view</h2>") < page.index("<h2>Inputs and")
    d = scene_data(page)
    assert [v[0] for v in d["views"]] == ["all storeys", "Ground floor (0 m)", "Upper floor (3 m)"]
    assert {z[1] for z in d["zones"]} == {"Ground floor", "Upper floor"}
    assert {w[6] for w in d["walls"]} == {0, 3}  # walls stand on both storeys' floors
    assert len(d["walls"]) == sum(len(z.walls) for z in o.site.zones)
    kinds = {(s[1], s[2]) for s in d["surfaces"]}
    assert {("f", 0), ("c", 2.7), ("f", 3), ("c", 5.5)} <= kinds  # floors and ceilings at their levels
    m = o.coverage.problem.by_candidate
    assert [s[0] for s in d["stations"]] == [s.id for s in o.stations]
    for i, s in enumerate(d["stations"]):
        assert sum(c[3] for c in s[7]) == m.indptr[i + 1] - m.indptr[i] > 0  # its covered pieces
        assert s[6] == s[5] == {"Ground floor": 0, "Upper floor": 3}[o.stations[i].frame]  # IH 0
    assert sum(c[3] for c in d["covered"]) == int((o.coverage.count > 0).sum())
    section_html = page.split("<h2>3-D view</h2>", 1)[1].split("<h2>", 1)[0]
    assert not URL.search(section_html)
    assert not [a for a in parse(page).addresses if URL.match(a)]  # the whole report fetches nothing


def test_a_site_over_the_limit_gets_a_note(write_csv, monkeypatch):
    site = planner.load_site(write_csv(room_rows()))
    o = planner.outcome_from_plan(planner.plan_site(site, planner.PlanOptions(method="greedy")))
    assert "<canvas" in view3d_section(o) and MAX_WALL_PIECES == 20_000
    monkeypatch.setattr(section, "MAX_WALL_PIECES", 31)  # the room has 32 pieces
    note = view3d_section(o)
    assert "<canvas" not in note and "32 wall pieces, more than the 31" in note and note.count("<p>") == 1
    # stations stand at the plan's surfaces instrument height where plan.json has one
    meta = {**o.meta, "surfaces": {"types": ["walls", "floors"], "instrument_height_m": 1.45}}
    assert outcome_scene(replace(o, meta=meta)).stations[0].z_m == pytest.approx(1.45)
    assert outcome_scene(o).stations[0].z_m == 0.0


PROBE = probe(
    """
    var root = document.getElementById('view-3d'), cv = root.querySelector('canvas');
    var info = root.querySelector('.v3-info'), r = cv.getBoundingClientRect();
    var img = cv.getContext('2d').getImageData(0, 0, cv.width, cv.height).data, ink = 0;
    for (var i = 0; i < img.length; i += 4 * 5) {
      if (Math.abs(img[i] - 251) + Math.abs(img[i + 1] - 251) + Math.abs(img[i + 2] - 248) > 30) ink++;
    }
    b.setAttribute('data-ink', ink);
    b.setAttribute('data-drawn', cv.getAttribute('data-drawn'));
    b.setAttribute('data-all', info.getAttribute('data-pieces'));
    var sel = root.querySelector('.v3-station');
    sel.value = '0'; sel.dispatchEvent(new Event('change'));
    b.setAttribute('data-picked', info.getAttribute('data-station') + ' ' + info.getAttribute('data-pieces'));
    var p = root.v3dPlaced().filter(function (q) { return q[0] === 1; })[0];
    var at = { clientX: r.left + p[1], clientY: r.top + p[2], pointerId: 1, bubbles: true };
    cv.dispatchEvent(new PointerEvent('pointerdown', at)); cv.dispatchEvent(new PointerEvent('pointerup', at));
    b.setAttribute('data-clicked', info.getAttribute('data-station') + ' ' + info.getAttribute('data-pieces'));
    var vs = root.querySelector('.v3-view');
    b.setAttribute('data-views', Array.prototype.map.call(vs.options, function (o) { return o.textContent; }).join('|'));
    vs.value = '2'; vs.dispatchEvent(new Event('change'));
    b.setAttribute('data-drawn-upper', cv.getAttribute('data-drawn'));
    var yaw = root.v3dState.yaw;
    cv.dispatchEvent(new PointerEvent('pointerdown', { clientX: r.left + 100, clientY: r.top + 100, pointerId: 2 }));
    cv.dispatchEvent(new PointerEvent('pointermove', { clientX: r.left + 160, clientY: r.top + 120, pointerId: 2 }));
    cv.dispatchEvent(new PointerEvent('pointerup', { clientX: r.left + 160, clientY: r.top + 120, pointerId: 2 }));
    b.setAttribute('data-yaw', yaw + ' ' + root.v3dState.yaw);
    b.setAttribute('data-fetched', performance.getEntriesByType('resource').length);
"""
)


@pytest.mark.slow
@pytest.mark.skipif(chromium() is None, reason="no Chromium here; the parse tests check the fragment")
def test_view_draws_and_a_station_picked_changes_the_highlight(house2, tmp_path):
    o, report = house2
    page = tmp_path / "probe.html"
    page.write_text(report.read_text().replace("</body>", PROBE + "</body>"))
    b = body_attributes(dump_dom(page))
    assert json.loads(b["data-errors"]) == []
    assert int(b["data-ink"]) > 2000  # the canvas is drawn, not blank
    d = scene_data(report.read_text())
    assert int(b["data-drawn"]) == len(d["walls"]) + len(d["surfaces"]) + len(d["covered"]) + len(o.stations)
    m = o.coverage.problem.by_candidate
    assert int(b["data-all"]) == int((o.coverage.count > 0).sum())
    assert b["data-picked"] == f"{o.stations[0].id} {m.indptr[1] - m.indptr[0]}"  # picked from the list
    assert b["data-clicked"] == f"{o.stations[1].id} {m.indptr[2] - m.indptr[1]}"  # a click on its marker
    assert b["data-all"] != b["data-picked"].split()[1]
    assert b["data-views"] == "all storeys|Ground floor (0 m)|Upper floor (3 m)"
    assert 0 < int(b["data-drawn-upper"]) < int(b["data-drawn"])  # the upper storey alone
    yaw0, yaw1 = map(float, b["data-yaw"].split())
    assert yaw1 == pytest.approx(yaw0 - 60 * 0.4)  # a drag rotates
    assert b["data-fetched"] == "0"  # no resource fetched
