"""field.pdf (issue 45 step 6): the plan on page 1 (A4 landscape, A3 when large), the setup table on A4 pages with
whole rows and the header on each, totals at the end; the page text readable (uncompressed) and the bytes the same
for the same sheet."""

from __future__ import annotations

import math
import re

import pytest

from planner.field import pdf
from planner.field.run import FieldOptions, field_plan
from planner.field.sheet import write_sheet
from planner.io import load_site
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide
from tests.conftest import INSTANCES

A4_PT = (595.3, 841.7)  # A4 portrait in pt; A3 landscape is 841.7 high
# the house stands on x 0..30, y 0..8: 64 stations on the open ground in front of it
GRID = [(-20.0 + 4.4 * i, -20.0 + 5.0 * j) for j in range(4) for i in range(16)]


@pytest.fixture(scope="module")
def few():
    house = load_site(INSTANCES / "house_doors.json")
    stations = [
        Candidate(f"F{k}", "house", ScanSide.OUTSIDE, "site", x, y, CandidateKind.GRID)
        for k, (x, y) in enumerate(GRID[:5])
    ]
    return field_plan(house, stations)


@pytest.fixture(scope="module")
def many():
    site = load_site(INSTANCES / "house_doors.json")
    stations = [
        Candidate(f"F{k:02d}", "house", ScanSide.OUTSIDE, "site", x, y, CandidateKind.GRID)
        for k, (x, y) in enumerate(GRID)
    ]
    return field_plan(site, stations, FieldOptions(solution_limit=20))


def pdf_text(data: bytes) -> str:
    """The text shown on the pages of an uncompressed PDF: the strings of every TJ array (matplotlib splits a
    text at its kerning pairs) and Tj operator, joined, one shown text a line."""
    out = []
    for arr in re.findall(rb"\[(.*?)\]\s*TJ", data, flags=re.S):
        out.append(b"".join(re.findall(rb"\(((?:\\.|[^\\)])*)\)", arr, flags=re.S)))
    out += re.findall(rb"\(((?:\\.|[^\\)])*)\)\s*Tj", data)
    return b"\n".join(re.sub(rb"\\(.)", rb"\1", s) for s in out).decode("latin-1")


def _pages(data: bytes) -> list[tuple[float, float]]:
    """The media box (width, height in pt) of every page, in order."""
    return [(float(w), float(h)) for w, h in re.findall(rb"/MediaBox \[\s*0 0 ([\d.]+) ([\d.]+)\s*\]", data)]


def test_rows_per_page_from_the_page_height():
    # A4 landscape 8.27 in high, 0.5 in margins: 7.27 in = 523.4 pt of 8-pt lines 1.5 apart (12 pt): 43 lines,
    # less the title and a blank line, the header row and the 6 lines kept for the totals: 34 rows
    assert pdf.rows_per_page() == math.floor((8.27 - 1.0) * 72 / 12) - 2 - 1 - 6 == 34


def test_rows_break_between_pages(few, tmp_path, monkeypatch):
    # two rows a page: 5 setups take ceil(5 / 2) = 3 table pages after the plan, each with the header
    monkeypatch.setattr(pdf, "rows_per_page", lambda *a, **k: 2)
    pdf.write_pdf(few, tmp_path / "f.pdf")
    data = (tmp_path / "f.pdf").read_bytes()
    assert len(_pages(data)) == math.ceil(5 / 2) + 1 == 4
    text = pdf_text(data)
    ids = [few.stations[k].id for k in few.order]
    chunks = text.split("Field sheet house_doors: setups, page ")[1:]
    assert len(chunks) == 3
    for n, chunk in enumerate(chunks):
        lines = chunk.splitlines()
        assert "station" in lines and "targets seen" in lines  # the header on each page
        assert [i for i in ids if i in lines] == ids[2 * n : 2 * n + 2]  # its two rows, whole and in order
    assert f"total: {len(ids)} setups" in chunks[-1] and "total:" not in chunks[0]


@pytest.mark.slow
def test_pdf_pages_ids_and_paper(many, tmp_path):
    write_sheet(many, tmp_path)
    data = (tmp_path / "field.pdf").read_bytes()
    per = pdf.rows_per_page()
    pages = _pages(data)
    assert len(pages) == math.ceil(len(many.order) / per) + 1 == 3  # 64 rows, 34 a page: 2 table pages + the plan
    assert pages[0] == pytest.approx((A4_PT[1] * 2**0.5, A4_PT[1]), abs=1)  # the plan: A3 landscape (64 > 40 setups)
    assert all(p == pytest.approx((A4_PT[1], A4_PT[0]), abs=1) for p in pages[1:])  # the table: A4 landscape
    text = pdf_text(data)
    for k in many.order:
        assert many.stations[k].id in text.splitlines()  # each setup's id, whole
    assert text.count("station") >= 2  # the header on each table page
    assert f"total: {len(many.order)} setups" in text
    # a row stays whole on its page: the last row of page 2 is setup 34, page 3 starts with setup 35
    page2, page3 = text.split("page 3 of 3")
    assert many.stations[many.order[per - 1]].id in page2 and many.stations[many.order[per]].id in page3


def test_pdf_is_deterministic(few, tmp_path):
    a, b = tmp_path / "a.pdf", tmp_path / "b.pdf"
    pdf.write_pdf(few, a)
    pdf.write_pdf(few, b)
    assert a.read_bytes() == b.read_bytes()
    assert b"CreationDate" not in a.read_bytes()


def test_paper_of_the_plan(few, tmp_path):
    small = few  # the module's five stations in front of the house
    # the house's walls (30 m x 8 m) and five stations: 50 m x 28 m, fits A4 at 1:500 (238 mm x 164 mm drawn)
    assert pdf.map_paper(small)[0] == "A4"
    pdf.write_pdf(small, tmp_path / "s.pdf")
    pages = _pages((tmp_path / "s.pdf").read_bytes())
    assert pages[0] == pytest.approx((A4_PT[1], A4_PT[0]), abs=1) and len(pages) == 2
    site = load_site(INSTANCES / "baalbek_site.json")
    stations = [
        Candidate("Z1-in-C", "Z1", ScanSide.INSIDE, "site", 154.393, 34.865, CandidateKind.GRID),
        Candidate("V1", "outline", ScanSide.OUTSIDE, "site", -36.101, -35.327, CandidateKind.GRID),
    ]
    fp = field_plan(site, stations)
    # the temple and the stations span about 350 m x 210 m: on A4 (238 mm x 164 mm drawn) smaller than 1:500, so A3
    assert pdf.map_paper(fp)[0] == "A3"


def test_a_sheet_on_a4_draws_its_plan_once_for_the_page_and_the_pdf(few, tmp_path, monkeypatch):
    import planner.field.sheet as sheet_module

    assert pdf.map_paper(few)[0] == "A4"
    sizes: list[tuple[float, float]] = []
    real = sheet_module.figure
    monkeypatch.setattr(sheet_module, "figure", lambda fp, size: sizes.append(size) or real(fp, size))
    write_sheet(few, tmp_path / "a")
    assert sizes == [pdf.A4]  # one figure, for the paper; field.html's image is that figure's
    monkeypatch.undo()
    pdf.write_pdf(few, tmp_path / "b.pdf")  # drawn alone: the same file
    assert (tmp_path / "a" / "field.pdf").read_bytes() == (tmp_path / "b.pdf").read_bytes()
    assert "data:image/png;base64," in (tmp_path / "a" / "field.html").read_text()
