"""The interactive site map of report.html: the fragment parsed (no address, one element per station, each
station's covered pieces), its runs checked by hand on a square room, and the map run in headless Chromium
(a click on a station highlights what it covers, a checkbox hides its layer, pan and zoom move the view, a
phone-width screenshot)."""

from __future__ import annotations

import json
import re
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

import planner
from planner.figures.webmap import MapLine, MapLink, MapPoint, MapStation, Run, SiteMap, render_site_map
from planner.figures.webmap.build import field_layers
from planner.report.site_map import outcome_site_map, site_map_html
from tests.browser import body_attributes, chromium, dump_dom, probe
from tests.conftest import square_rows

URL = re.compile(r"https?://", re.IGNORECASE)


class Fragment(HTMLParser):
    """Stations (data-id -> attributes), covered runs per station, layer groups, checkboxes, every src/href."""

    def __init__(self) -> None:
        super().__init__()
        self.stations: dict[str, dict[str, str]] = {}
        self.runs: dict[str, list[int]] = {}
        self.layers: list[str] = []
        self.boxes: dict[str, bool] = {}
        self.addresses: list[str] = []
        self.frames: list[tuple[str, bool]] = []
        self._cv: str | None = None

    def handle_starttag(self, tag, attrs):
        a = {k: v or "" for k, v in attrs}
        cls = a.get("class", "").split()
        self.addresses += [a[k] for k in ("src", "href") if k in a]
        if "sm-st" in cls:
            assert a["data-id"] not in self.stations
            self.stations[a["data-id"]] = a
        if "sm-cv" in cls:
            self._cv = a["data-st"]
            self.runs[self._cv] = []
        if tag == "line" and self._cv is not None:
            self.runs[self._cv].append(int(a["data-n"]))
        if "sm-L" in cls:
            self.layers.append(a["data-layer"])
        if "sm-fr" in cls:
            self.frames.append((a["data-frame"], "display:none" not in a.get("style", "")))
        if tag == "input" and "data-layer" in a:
            self.boxes[a["data-layer"]] = "checked" in a

    def handle_endtag(self, tag):
        if tag == "g" and self._cv is not None:
            self._cv = None


def parse(fragment: str) -> Fragment:
    p = Fragment()
    p.feed(fragment)
    return p


@pytest.fixture(scope="module")
def polygon_b(tmp_path_factory, polygon_b_greedy):
    """Polygon B planned by greedy (the session's plan), its plan.json and its map fragment."""
    out = tmp_path_factory.mktemp("pb")
    plan = polygon_b_greedy[1]
    planner.write_plan(plan, out)
    o = planner.outcome_from_plan(plan)
    return json.loads((out / "plan.json").read_text()), o, site_map_html(o)


def test_fragment_holds_every_station_of_the_plan_and_no_address(polygon_b):
    meta, o, fragment = polygon_b
    assert not URL.search(fragment)  # self-contained: no library, font or image fetched
    p = parse(fragment)
    assert all(a.startswith("#") for a in p.addresses)
    ids = [s["id"] for s in meta["stations"]]
    assert list(p.stations) == ids  # one element per station, in the plan's order
    for k, s in enumerate(meta["stations"], 1):
        el = p.stations[s["id"]]
        assert (float(el["data-x"]), float(el["data-y"])) == (round(s["x"], 2), round(s["y"], 2))
        assert el["data-zone"] == s["zone"] and el["data-row"] == f"station-{k}"
    # each station's covered pieces, merged into runs: the pieces add up to the station's row of the coverage
    m = o.coverage.problem.by_candidate
    for i, s in enumerate(o.stations):
        pieces = m.indptr[i + 1] - m.indptr[i]
        assert sum(p.runs.get(s.id, [])) == pieces == int(p.stations[s.id]["data-n"])
        assert len(p.runs.get(s.id, [])) == int(p.stations[s.id]["data-runs"]) <= max(pieces, 1)
        assert float(p.stations[s.id]["data-m"]) == pytest.approx(o.coverage.per_station[i].covered_m, abs=0.06)
    assert sum(map(len, p.runs.values())) < sum(map(sum, p.runs.values())) / 10  # runs, not pieces
    assert p.layers == ["walls", "coverage", "links", "stations"] and p.frames == [("B", True)]


def test_links_are_the_plans_registration_relation(polygon_b):
    meta, o, _ = polygon_b
    m = outcome_site_map(o)
    assert o.registration.mode == meta["resolved"]["registration"]
    g = o.registration.relation(o.stations, o.coverage.problem)
    assert {frozenset((lk.a, lk.b)) for lk in m.links} == {
        frozenset((o.stations[u].id, o.stations[v].id)) for u, v in g.edges()
    }
    assert all(lk.shared_m is not None and lk.shared_m > 0 for lk in m.links)  # one zone: links share wall


def test_square_room_one_run_per_wall(write_csv):
    """A 10 m square room on 1 m pieces, one station: 40 pieces in 4 runs, each a whole wall, corner to corner."""
    site = planner.load_site(write_csv(square_rows()))
    plan = planner.plan_site(site, planner.PlanOptions(method="greedy"))
    o = planner.outcome_from_plan(plan)
    m = outcome_site_map(o)
    assert len(m.stations) == 1 and m.stations[0].pieces == 40 and m.stations[0].covered_m == pytest.approx(40)
    runs = m.stations[0].runs
    assert [r.pieces for r in runs] == [10, 10, 10, 10]
    corners = np.asarray(site.zones[0].vertices)
    for k, r in enumerate(runs):
        np.testing.assert_allclose([r.a, r.b], [corners[k], corners[(k + 1) % 4]], atol=1e-9)
    assert [w.kind for w in m.walls] == ["wall"] and m.frames == (site.zones[0].frame,)


def _tiny(frames: tuple[str, ...] = ("a", "b")) -> SiteMap:
    run = Run((0.0, 0.0), (10.0, 0.0), 10, 10.0, "Z/inside/wall 1 0.00-10.00 m")
    return SiteMap(
        title="tiny <site>",
        frames=frames,
        walls=(MapLine("Z#0", "a", "wall", ((0, 0), (10, 0), (10, 10.004), (0, 10)), True, "Z"),),
        stations=(
            MapStation("S1", "a", 5.123456, 5.0, "1", runs=(run,)),
            MapStation("S2", "a", 6.0, 4.0, "2"),
            MapStation('T"1', "b", -1.0, -2.0, "3"),
        ),
        links=(MapLink("S1", "S2", 3.0, 0.3), MapLink("S1", 'T"1', 0.0)),
        control=(MapPoint("C1", "b", 1.0, 1.0, "proposed"),),
        traverse=(MapLine("C1-C2", "b", "traverse", ((1, 1), (2, 2))),),
    )


def test_render_by_hand_frames_layers_and_centimetres():
    fragment = render_site_map(_tiny(), dom_id="m1")
    p = parse(fragment)
    assert p.frames == [("a", True), ("b", False)]  # the frame with most stations shown first, one at a time
    assert '<option value="a" selected>a (2 stations)</option>' in fragment
    boxes = {"walls": True, "coverage": True, "links": True, "traverse": False, "control": True, "stations": True}
    assert p.boxes == boxes and set(p.layers) == set(boxes)  # a box for each layer drawn, traverse off at first
    assert p.stations["S1"]["data-x"] == "5.12" and 'points="0,0 10,0 10,-10 0,-10"' in fragment  # cm, y down
    assert p.runs == {"S1": [10]} and 'id="m1-st-1"' in fragment and "tiny &lt;site&gt;" in fragment
    assert 'data-a="S1" data-b="S2" data-s="3.0"' in fragment
    assert 'data-b="T&quot;1"' not in fragment  # a link across frames is not drawn
    assert not URL.search(fragment)


def test_field_layers_from_field_json():
    sheet = {
        "order": ["S2", "S1", "X"],
        "start": "S2",
        "start_xy": [6.0, 4.0],
        "legs": [[[6.0, 4.0]], [[6.0, 4.0], [5.5, 4.5], [5.0, 5.0]], [[5, 5], [9, 9]]],
        "targets": [{"id": "T1", "kind": "sphere", "x": 5.5, "y": 4.0, "where": "tripod", "seen_by": ["S1", "S2"]}],
    }
    route, start, targets, visits = field_layers(sheet, {"S1": "a", "S2": "a"})
    assert [len(r.points) for r in route] == [3] and route[0].frame == "a"  # one-point legs and unknown stations
    assert start is not None and (start.x, start.y) == (6.0, 4.0)
    assert [(t.id, t.frame, t.kind) for t in targets] == [("T1", "a", "sphere")]
    assert visits == {"S2": 1, "S1": 2, "X": 3}


# --- in a browser -------------------------------------------------------------------------------------------

PROBE = probe(
    """
    var svg = document.querySelector('.smap svg');
    var st = document.querySelector('.sm-st[data-id="__ID__"]');
    st.dispatchEvent(new MouseEvent('click', {bubbles: true, cancelable: true, view: window}));
    var hl = document.querySelectorAll('.sm-cv line.hl'), n = 0;
    for (var i = 0; i < hl.length; i++) n += +hl[i].getAttribute('data-n');
    b.setAttribute('data-hl-runs', hl.length);
    b.setAttribute('data-hl-pieces', n);
    b.setAttribute('data-hl-links', document.querySelectorAll('.sm-lk.hl').length);
    b.setAttribute('data-panel', document.querySelector('.sm-panel').textContent);
    b.setAttribute('data-row', (document.querySelector('tr.sm-row') || {id: ''}).id);
    var w0 = svg.viewBox.baseVal.width;
    document.querySelector('button[data-zoom=in]').click();
    b.setAttribute('data-zoom', (svg.viewBox.baseVal.width / w0).toFixed(3));
    var r = svg.getBoundingClientRect(), x0 = svg.viewBox.baseVal.x, cx = r.left + 10, cy = r.top + 10;
    function pe(type, x) { svg.dispatchEvent(new PointerEvent(type, {bubbles: true, pointerId: 7, clientX: x, clientY: cy})); }
    pe('pointerdown', cx); pe('pointermove', cx + 60); pe('pointerup', cx + 60);
    b.setAttribute('data-pan', svg.viewBox.baseVal.x < x0 ? 'moved' : 'still');
    var shown = document.querySelectorAll('.sm-L[data-layer="__LAYER__"]'), before = 0, after = 0;
    for (var j = 0; j < shown.length; j++) before += getComputedStyle(shown[j]).display !== 'none';
    document.querySelector('input[data-layer="__LAYER__"]').click();
    for (var j = 0; j < shown.length; j++) after += getComputedStyle(shown[j]).display !== 'none';
    b.setAttribute('data-layer-shown', before + '->' + after);
"""
)


@pytest.fixture(scope="module")
def house(tmp_path_factory, house_doors_greedy):
    """report.html of house_doors (greedy, the session's plan) with its field sheet: walls, coverage, links, route,
    targets."""
    from planner.field.run import field_plan
    from planner.field.sheet import write_sheet

    out = tmp_path_factory.mktemp("house")
    plan = house_doors_greedy[1]
    write_sheet(field_plan(plan.problem.sight, plan.stations), out)
    o = planner.outcome_from_plan(plan)
    return o, planner.write_report(o, out, field=out)


@pytest.mark.slow
@pytest.mark.skipif(chromium() is None, reason="no Chromium here; the parse tests check the fragment")
def test_click_on_a_station_highlights_its_wall_links_and_row(house, tmp_path):
    o, report = house
    html = report.read_text()
    p = parse(html)
    assert {"route", "targets", "links", "coverage"} <= set(p.layers)
    first = o.stations[0]
    page = tmp_path / "probe.html"
    page.write_text(
        html.replace("</body>", PROBE.replace("__ID__", first.id).replace("__LAYER__", "walls") + "</body>")
    )
    b = body_attributes(dump_dom(page))
    assert json.loads(b["data-errors"]) == []
    m = o.coverage.problem.by_candidate
    assert int(b["data-hl-pieces"]) == m.indptr[1] - m.indptr[0] > 0  # every piece it covers, from the matrix
    assert int(b["data-hl-runs"]) == len(p.runs[first.id])
    assert int(b["data-hl-links"]) == sum(1 for lk in outcome_site_map(o).links if first.id in (lk.a, lk.b))
    assert first.id in b["data-panel"] and "covers" in b["data-panel"]
    assert b["data-row"] == "station-1" and b["data-images-ok"].split("/")[0] == b["data-images-ok"].split("/")[1]
    assert float(b["data-zoom"]) == pytest.approx(1 / 1.5, abs=1e-3) and b["data-pan"] == "moved"
    assert b["data-layer-shown"] == "1->0"  # the walls checkbox hides the walls group


@pytest.mark.slow
@pytest.mark.skipif(chromium() is None, reason="no Chromium here; the parse tests check the fragment")
def test_phone_width_screenshot(house, tmp_path: Path):
    _, report = house
    png = tmp_path / "phone.png"
    cmd = [chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--window-size=390,844"]
    subprocess.run([*cmd, f"--screenshot={png}", report.as_uri()], capture_output=True, timeout=120)
    assert png.is_file() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 15_000
