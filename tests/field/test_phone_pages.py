"""field.html and report.html on a phone and a tablet: Chromium driven over WebDriver (tests/browser.py: Phone)
emulating a 390 x 844 CSS px touch screen at 3 device px per CSS px, and a 768 x 1024 one at 2. Each page lays out
at the screen's width and at full scale (no 980 px desktop layout shrunk to fit), the page itself never scrolls
sideways (wide tables scroll inside their own box or turn into cards), and at the site map's "fit" zoom a finger's
tap on a station's marker selects that station, also where markers crowd: the three stations closest to another on
screen, each tapped at its marker's centre and a few pixels off it towards its neighbour (where the topmost hit area
used to win, the neighbour's). A screenshot of each page is kept in the test's folder."""

from __future__ import annotations

from pathlib import Path

import pytest

import planner
from planner.field.run import field_plan
from planner.field.sheet import write_sheet
from tests.browser import Phone, chromedriver
from tests.conftest import INSTANCES

PNG = b"\x89PNG\r\n\x1a\n"
PHONE, TABLET = (390, 844, 3.0), (768, 1024, 2.0)  # CSS px wide and high, device px per CSS px

pytestmark = [
    pytest.mark.slow,
    pytest.mark.heavy,  # a headless browser at phone and tablet sizes: run with -m heavy
    pytest.mark.skipif(
        chromedriver() is None, reason="no Chromium or chromedriver here; the parse tests cover the pages"
    ),
]

# the layout: the layout viewport's width, the pinch-zoom scale, the page's width and the widest element
LAYOUT = """
var de = document.documentElement, w = de.clientWidth, wide = '';
document.querySelectorAll('body *').forEach(function (e) {
  var r = e.getBoundingClientRect();
  if (!wide && r.right > w + 1) {
    var box = e.parentElement, clipped = false;
    for (; box && box !== document.body; box = box.parentElement) {
      var o = getComputedStyle(box).overflowX;
      if (o === 'auto' || o === 'scroll' || o === 'hidden') { clipped = true; break; }
    }
    if (!clipped) wide = e.tagName.toLowerCase() + (e.id ? '#' + e.id : '') + ' ' + Math.round(r.right) + ' px';
  }
});
return {inner: window.innerWidth, scale: window.visualViewport.scale, scroll: de.scrollWidth, wide: wide};
"""

# the screen centres of the current frame's station markers at "fit" (the origin of each marker's own frame:
# a marker is drawn translated to its station), the map scrolled into the middle of the screen
CENTRES = """
var root = document.querySelector('.smap');
if (arguments[0]) root.querySelector('button[data-zoom="fit"]').click();
root.querySelector('svg.sm-svg').scrollIntoView({block: 'center'});
var out = {};
root.querySelectorAll('.sm-st').forEach(function (g) {
  var fr = g.closest('.sm-fr');
  if (fr && fr.style.display === 'none') return;
  var m = g.getScreenCTM();
  if (m) out[g.getAttribute('data-id')] = [m.e, m.f];
});
return out;
"""

SELECTED = """
var s = document.querySelector('.smap .sm-st.sm-sel');
return s ? s.getAttribute('data-id') : null;
"""


@pytest.fixture(scope="module")
def pages(tmp_path_factory) -> Path:
    """house_doors planned by greedy: its field sheet and its report (which links to the sheet), in one folder."""
    out = tmp_path_factory.mktemp("phone")
    plan = planner.plan_site(planner.load_site(INSTANCES / "house_doors.json"), planner.PlanOptions(method="greedy"))
    write_sheet(field_plan(plan.problem.sight, plan.stations), out)
    planner.write_report(planner.outcome_from_plan(plan), out, field=out)
    return out


def crowded(centres: dict[str, list[float]], n: int = 3) -> list[tuple[str, float, float]]:
    """The ``n`` stations whose markers are closest to another marker on screen (the taps most easily missed),
    each with the unit vector towards that nearest marker."""
    out = []
    for i, (x, y) in centres.items():
        d, j = min((((x - a) ** 2 + (y - b) ** 2) ** 0.5, j) for j, (a, b) in centres.items() if j != i)
        out.append((d, i, (centres[j][0] - x) / d, (centres[j][1] - y) / d))
    return [(i, ux, uy) for _, i, ux, uy in sorted(out)[:n]]


def taps(phone: Phone, centres: dict[str, list[float]], size: tuple[int, int]) -> dict[tuple[str, int], str | None]:
    """Tap each crowded station at its marker's centre and 6 px off it towards its nearest neighbour (a finger
    is not exact; the neighbour is still further off): the station selected after each tap."""
    picked = {}
    for sid, ux, uy in crowded(centres):
        for off in (0, 6):
            x, y = phone.run(CENTRES, False)[sid]  # a selection may scroll the page: measure again
            x, y = x + off * ux, y + off * uy
            assert 0 < x < size[0] and 0 < y < size[1], (sid, x, y)
            phone.tap(x, y)
            picked[sid, off] = phone.run(SELECTED)
    return picked


@pytest.mark.parametrize("screen", [PHONE, TABLET], ids=["phone", "tablet"])
@pytest.mark.parametrize("name", ["field.html", "report.html"])
def test_page_fits_the_screen_and_a_tap_selects_the_station_tapped(pages, name, screen, tmp_path):
    width, height, ratio = screen
    with Phone(width, height, ratio) as phone:
        phone.get(pages / name)
        lay = phone.run(LAYOUT)
        assert lay["inner"] == width  # laid out at the screen's width, not a desktop width shrunk to fit
        assert lay["scale"] == 1  # text at full scale
        assert lay["scroll"] <= width, lay["wide"]  # the page never scrolls sideways
        centres = phone.run(CENTRES, True)  # at "fit"
        assert len(centres) >= 4
        picked = taps(phone, centres, (width, height))
        assert picked == {(sid, off): sid for sid, off in picked}
        png = phone.screenshot()
    shot = tmp_path / f"{name}.png"
    shot.write_bytes(png)
    assert shot.stat().st_size > 1000 and shot.read_bytes()[:8] == PNG
