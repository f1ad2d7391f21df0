"""field.html's edit mode on a phone: Chromium over WebDriver (tests/browser.py: Phone, 390 x 844 CSS px, touch)
opens the field sheet of house_doors (planned by greedy with ``planner plan --field``), a finger taps "edit", taps one
station and marks it done, another and marks it blocked (radius blank: its tripod disc), a third and marks it moved
(then taps the map 12 px east of its marker: done there), sets the crew at a fourth with the crew tool, types the
hours left, and taps "Save edits.json". The file the browser downloads (the page's Blob through an ``a[download]``)
parses, has the format ``planner-edits/1``, names the stations by the numbers plan.json and the sheet give them,
and puts the moved station where the finger was, in the site frame, to the centimetre the map is written in (the
inverse of the frame's screen matrix, checked against the station's own coordinates). A closed area drawn by three
taps (after a self-crossing outline refused), then undone from the list, comes and goes in what the page would save; the edits outlive a reload. The
re-plan's reader (planner.io.edits, where it is there) takes the file; where ``planner replan`` exists, it
accepts the saved file (exit 0). Without a browser: the edit mode is in the map only where asked (field.html's),
never in report.html's, and the page stays free of any address."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

from planner.cli.main import main
from tests.browser import Phone, chromedriver
from tests.conftest import INSTANCES

URL = re.compile(r"https?://", re.IGNORECASE)

MAP = "#field-map"

# the screen centre of each station's marker (its group is drawn translated to the station), the map in the middle of
# the screen, the shown frame's screen matrix (a, d: CSS px per metre, y turned down; e, f: where the origin is) and
# the map's centre on screen
CENTRES = """
var root = document.querySelector('#field-map');
root.querySelector('svg.sm-svg').scrollIntoView({block: 'center'});
var out = {}, m = root.smapGroup().getScreenCTM();
root.querySelectorAll('.sm-st').forEach(function (g) {
  var fr = g.closest('.sm-fr');
  if (fr && fr.style.display === 'none') return;
  var c = g.getScreenCTM();
  out[g.getAttribute('data-id')] = [c.e, c.f];
});
var r = root.querySelector('svg.sm-svg').getBoundingClientRect();
return {at: out, m: [m.a, m.b, m.c, m.d, m.e, m.f], mid: [r.left + r.width / 2, r.top + r.height / 2]};
"""


@pytest.fixture(scope="module")
def sheet(tmp_path_factory) -> Path:
    """house_doors planned by greedy with its field sheet, plan.json beside field.html (the cheapest bundled site
    whose plan the re-plan takes)."""
    out = tmp_path_factory.mktemp("edit")
    assert (
        main(
            ["plan", str(INSTANCES / "house_doors.json"), "--method", "greedy", "--out", str(out), "--field", str(out)]
        )
        == 0
    )
    return out


def _tap_station(phone: Phone, sid: str) -> None:
    """Tap station ``sid``'s marker (measured again: a tap may scroll the page)."""
    phone.tap(*phone.run(CENTRES)["at"][sid])


def _replan() -> bool:
    """Whether ``planner replan`` is a command here (its help exits 0; an unknown command is a usage error)."""
    try:
        return main(["replan", "--help"]) == 0
    except SystemExit as stop:
        return stop.code == 0


@pytest.mark.slow
@pytest.mark.skipif(chromedriver() is None, reason="no Chromium or chromedriver here; edit mode needs a browser")
def test_edit_mode_saves_edits_that_name_the_stations_tapped(sheet, tmp_path, capsys):
    plan = json.loads((sheet / "plan.json").read_text())
    number = {s["id"]: s["number"] for s in plan["stations"]}
    xy = {s["id"]: (s["x"], s["y"]) for s in plan["stations"]}
    downloads = tmp_path / "downloads"
    downloads.mkdir()
    with Phone(downloads=downloads) as phone:
        phone.get(sheet / "field.html")
        phone.run(
            "window.__errors = []; window.addEventListener('error', function (e) { window.__errors.push(String(e.message)); });"
        )
        assert phone.run("return document.querySelector('#field-map .sm-ed').hidden") is True  # off at first
        phone.tap_element(f"{MAP} [data-act=edit]")
        assert phone.run("return document.querySelector('#field-map').classList.contains('sm-editing')")
        assert phone.run("return document.documentElement.scrollWidth") <= 390  # the panel never widens the page
        view = phone.run(CENTRES)
        # four stations, the farthest apart on screen first (an unambiguous tap each)
        at = view["at"]
        apart = sorted(at, key=lambda i: -min(math.dist(at[i], at[j]) for j in at if j != i))
        done, blocked, moved, crew = apart[:4]

        _tap_station(phone, done)
        assert phone.run(f"return document.querySelector('{MAP} .sm-ed-name').textContent") == f"station {number[done]}"
        phone.tap_element(f"{MAP} [data-act=done]")
        _tap_station(phone, blocked)
        phone.tap_element(f"{MAP} [data-act=blocked]")
        _tap_station(phone, moved)
        phone.tap_element(f"{MAP} [data-act=moved]")
        view = phone.run(CENTRES)
        x, y = view["at"][moved]
        tapped = (round(x + 12), round(y))
        phone.tap(*tapped)
        phone.tap_element(f"{MAP} [data-tool=crew]")
        _tap_station(phone, crew)
        phone.run(
            "var h = document.querySelector('#field-map .sm-ed-hours'); h.value = '3.5';"
            "h.dispatchEvent(new Event('change', {bubbles: true}));"
        )
        items = phone.run(
            f"return [].map.call(document.querySelectorAll('{MAP} .sm-ed-list li'), e => e.firstChild.textContent)"
        )
        assert len(items) == 4, items

        # an outline that crosses itself (a bow tie) is refused at "finish", as the re-plan would refuse it
        phone.tap_element(f"{MAP} [data-tool=closed]")
        cx, cy = phone.run(CENTRES)["mid"]
        for dx, dy in ((-40, -40), (40, 40), (40, -40), (-40, 40)):
            phone.tap(cx + dx, cy + dy)
        phone.tap_element(f"{MAP} [data-act=finish]")
        assert "crosses" in phone.run(f"return document.querySelector('{MAP} .sm-ed-hint').textContent")
        assert "areas" not in phone.run(f"return document.querySelector('{MAP}').smapEdits()")
        phone.tap_element(f"{MAP} [data-act=cancel]")
        # a closed area of three taps, in the list and in what would be saved, then undone from the list
        cx, cy = phone.run(CENTRES)["mid"]
        for dx, dy in ((-40, -40), (40, -40), (0, 30)):
            phone.tap(cx + dx, cy + dy)
        phone.tap_element(f"{MAP} [data-act=finish]")
        drawn = phone.run(f"return document.querySelector('{MAP}').smapEdits()")
        assert [a["kind"] for a in drawn["areas"]] == ["closed"] and len(drawn["areas"][0]["polygon"]) == 3
        phone.tap_element(f"{MAP} .sm-ed-list li:last-child button[data-undo]")
        assert "areas" not in phone.run(f"return document.querySelector('{MAP}').smapEdits()")

        phone.run(
            "window.__saved = null; var make = URL.createObjectURL;"
            "URL.createObjectURL = function (b) { b.text().then(function (t) { window.__saved = t; }); return make.call(URL, b); };"
        )
        phone.tap_element(f"{MAP} [data-act=save]")
        saved = phone.wait_for("return window.__saved")
        errors = phone.run("return window.__errors || []")
        # the page keeps its edits through a reload (a phone's browser may drop a page in the background)
        phone.get(sheet / "field.html")
        kept = phone.run(f"return document.querySelector('{MAP}').smapEdits()")
    assert saved is not None and errors == []
    edits = json.loads(saved)
    assert kept == edits
    # the file the browser downloaded is the same text, where this Chromium saves downloads headless
    files = list(downloads.glob("edits*.json"))
    if files:
        assert files[0].read_text() == saved

    assert set(edits) == {"format", "plan", "stations", "crew", "time_left_h"}
    assert edits["format"] == "planner-edits/1" and edits["plan"] == {"instance": plan["instance"]}
    st = edits["stations"]
    assert st[:2] == [{"station": number[done], "status": "done"}, {"station": number[blocked], "status": "blocked"}]
    assert {k: v for k, v in st[2].items() if k not in ("x", "y")} == {"station": number[moved], "status": "done"}
    assert edits["crew"] == {"station": number[crew]} and edits["time_left_h"] == 3.5
    # the moved station: where the finger was, through the frame's screen matrix, to the centimetre
    a, _, _, d, e, f = view["m"]
    assert st[2]["x"] == pytest.approx((tapped[0] - e) / a, abs=0.0051)
    assert st[2]["y"] == pytest.approx(-(tapped[1] - f) / d, abs=0.0051)
    # and 12 px east of the station's own coordinates (within a pixel and the map's centimetres)
    px = 1 / a  # metres per CSS px
    assert abs(st[2]["x"] - (xy[moved][0] + 12 * px)) <= px + 0.01 and abs(st[2]["y"] - xy[moved][1]) <= px + 0.01

    saved_file = tmp_path / "edits.json"
    saved_file.write_text(saved)
    try:
        from planner.io.edits import read_edits
    except ImportError:
        read_edits = None
    if read_edits is not None:  # the re-plan's own reader takes it, stations resolved by number
        zones = tuple(z["id"] for z in plan["zones"])
        read = read_edits(saved_file, plan, zones)
        got = {e.station.id: (e.status, e.moved) for e in read.stations}
        assert got == {done: ("done", False), blocked: ("blocked", False), moved: ("done", True)}
        assert read.crew_station is not None and read.crew_station.id == crew and read.time_left_h == 3.5
        area_file = tmp_path / "area.json"
        area_file.write_text(json.dumps(drawn))
        assert [a.kind for a in read_edits(area_file, plan, zones).areas] == ["closed"]
    if not _replan():
        pytest.skip("planner replan is not a command here yet: the saved file was checked against the format only")
    capsys.readouterr()
    code = main(["replan", str(sheet / "plan.json"), str(saved_file), "--out", str(tmp_path / "replan")])
    said = capsys.readouterr()
    assert code == 0, f"planner replan exit {code} on the saved edits {edits}: {said.err.strip()[-500:]}"


def test_edit_mode_only_where_asked_and_self_contained():
    """The edit mode is in the map only with ``edit`` (the field sheet's): the toggle, the hidden panel with the format,
    the site frame, the plan's name and a zone to close, and its script; no address either way. report.html's map
    (``edit`` off) has none of it."""
    from planner.figures.webmap import MapStation, SiteMap, render_site_map

    m = SiteMap(
        title="yard <1>",
        frames=("site",),
        walls=(),
        stations=(MapStation("S1", "site", 1.0, 2.0, label="1", number=1, name="S1"),),
        zones=("Z1", "Z2"),
    )
    on, off = render_site_map(m, edit=True), render_site_map(m)
    assert on.count('class="sm-edit"') == 1 and '<div class="sm-ed" hidden' in on
    assert 'data-format="planner-edits/1"' in on and 'data-site-frame="site"' in on
    assert 'data-instance="yard &lt;1&gt;"' in on and '<option value="Z2">' in on and "smapEdits" in on
    assert "sm-ed" not in off and 'class="sm-edit"' not in off and "smapEdits" not in off and "smapTap" in off
    assert not URL.search(on) and not URL.search(off)


@pytest.mark.slow  # a plan
def test_field_sheet_has_the_edit_mode(sheet):
    """field.html (planner plan --field) carries the edit mode once, and still fetches nothing."""
    field = (sheet / "field.html").read_text()
    assert field.count('class="sm-edit"') == 1 and 'class="sm-ed"' in field and not URL.search(field)
