"""The HTML report: written by ``plan --report`` and by ``report PLAN.json``, self-contained, with every
figure decodable; rendered in headless Chromium where one is installed (.ci/run installs it)."""

from __future__ import annotations

import base64
import io
import re
import subprocess
from html.parser import HTMLParser

import matplotlib.image
import pytest

from planner.cli import main
from tests.browser import chromium

PNG = b"\x89PNG\r\n\x1a\n"


class Images(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.src: list[str] = []
        self.links: list[str] = []
        self.text: list[str] = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.src.append(a.get("src", ""))
        if tag in ("link", "script") and (a.get("href") or a.get("src")):
            self.links.append(a.get("href") or a.get("src"))

    def handle_data(self, data):
        self.text.append(data)


@pytest.fixture(scope="module")
def report(polygon_b_report):
    # polygon B on 2-m wall pieces: every section and figure of the report at half the 1-m coverage's cost
    return polygon_b_report / "report.html"


def test_report_is_self_contained_and_every_image_decodes(report):
    p = Images()
    p.feed(report.read_text())
    assert not p.links  # no external CSS, script or font
    # the site-wide plan first, then polygon B's two plan figures (scanned on both sides) and the network figure
    assert len(p.src) == 4
    for src in p.src:
        assert src.startswith("data:image/png;base64,")
        raw = base64.b64decode(src.split(",", 1)[1], validate=True)
        assert raw.startswith(PNG)
        img = matplotlib.image.imread(io.BytesIO(raw), format="png")
        assert img.shape[0] > 200 and img.shape[1] > 200
    text = " ".join(p.text)
    for heading in (
        "Inputs and parameters",
        "Zones and closure",
        "Stations",
        "Comparison of methods",
        "Network and accuracy check",
        "Verification",
    ):
        assert heading in text
    assert "closed-form" in text and "greedy" in text and "milp" in text
    # the report opens with the whole site: its first heading after the title is the site plan, then the map
    page = report.read_text()
    first = re.findall(r"<h2>([^<]+)</h2>", page)[:2]
    assert first == ["Site plan", "Site map"]
    assert page.index("the whole site: stations numbered") < page.index("plan B")


@pytest.mark.slow
def test_report_from_plan_json_lists_the_same_stations(report, tmp_path, capsys):
    plan_json = report.parent / "plan.json"
    capsys.readouterr()
    assert main(["report", str(plan_json), "--out", str(tmp_path), "--no-network", "--quiet"]) == 0
    ids_a = re.findall(r"<td class=\"l\">(B-[^<]+)</td>", report.read_text())
    ids_b = re.findall(r"<td class=\"l\">(B-[^<]+)</td>", (tmp_path / "report.html").read_text())
    assert ids_a and ids_a == ids_b
    assert "The network check was not run." in (tmp_path / "report.html").read_text()


@pytest.mark.slow  # a headless browser; the parse test above is its quick twin
@pytest.mark.skipif(chromium() is None, reason="no Chromium here; the parse test above checks the images")
def test_report_renders_in_headless_chromium(report):
    cmd = [
        chromium(),
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--virtual-time-budget=10000",
        "--dump-dom",
        report.as_uri(),
    ]
    dom = subprocess.run(cmd, capture_output=True, text=True, timeout=120).stdout
    # the report's own script writes how many images decoded once the page has loaded
    assert 'data-images-ok="4/4"' in dom  # the site plan, two plan figures, the network figure


def test_report_says_what_its_numbers_mean(report):
    import json

    text = report.read_text()
    meta = json.loads((report.parent / "plan.json").read_text())
    # the bound with its scope (and the plane bound beside a pool bound), as plan.json has them
    scope = meta["bound_scope"]
    plane = f"; plane {meta['plane_bound']:g}" if scope == "pool" and meta.get("plane_bound") is not None else ""
    assert f"bound {meta['bound']:g} ({scope}{plane})" in text
    # the pieces' length from the plan (not a fixed "1 m"), the gap in per cent, and what the times measure
    assert f"covered on {meta['parameters']['target_spacing_m']} m pieces" in text
    assert f"{meta['gap']:.1%}" in text and "Solver s: the solver alone" in text and "bound (scope)" in text


@pytest.mark.parametrize(
    "key, value, words",
    [
        # 1e-7 m pieces: polygon B's 1,533 m of wall (both sides) is ~1.5e10 pieces, terabytes of coverage
        ("parameters.target_spacing_m", 1e-7, "would not fit in memory"),
        # the command line samples at 1 mm .. 10 m; an edited plan may not ask for 1 nm
        ("parameters.verify_spacing_m", 1e-9, "must be a number of metres in [0.001, 10]"),
        # the site file's path must be text (a TypeError deep in pathlib before)
        ("source", 5, "must be a file path (text) or null"),
    ],
)
def test_report_refuses_an_edited_plans_spacing_naming_the_plan(report, tmp_path, capsys, key, value, words):
    import json

    data = json.loads((report.parent / "plan.json").read_text())  # polygon B's plan, made once for the module
    *outer, last = key.split(".")
    (data[outer[0]] if outer else data)[last] = value
    edited = tmp_path / "edited.json"
    edited.write_text(json.dumps(data))
    capsys.readouterr()
    assert main(["report", str(edited), "--no-network", "--out", str(tmp_path / "r")]) == 3
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and str(edited) in err and f"{key} = " in err and words in err


def test_the_accuracy_table_appears_once_and_no_text_block_runs_off_the_page(report):
    page = report.read_text()
    # one accuracy table (header "worst e mm"); the network's other lines are a wrapping list, not a <pre> block
    assert len(re.findall(r"<th[^>]*>worst e mm</th>", page)) == 1
    assert "<pre>" not in page and '<ul class="notes">' in page
    notes = page.split('<ul class="notes">', 1)[1].split("</ul>", 1)[0]
    assert "network:" in notes and "accuracy check at" not in notes


def test_on_a_phone_wide_tables_scroll_in_their_own_box(report):
    # a 390 px wide screen: every table sits in a box that scrolls sideways (the page itself never does), figures
    # shrink to the screen, and a narrow-screen rule tightens the margins (tests/field/test_phone_pages.py measures
    # it in Chromium)
    page = report.read_text()
    assert page.count("<table") == page.count('<div class="scroll"><table') > 0
    css = page.split("<style>", 1)[1].split("</style>", 1)[0]
    assert ".scroll{overflow-x:auto" in css and "img{max-width:100%" in css and "@media (max-width:600px)" in css
