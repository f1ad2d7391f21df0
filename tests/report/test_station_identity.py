"""One identity for every station: each station has ONE number and ONE label (its id) in every figure, map, table
and file of a run (:class:`~planner.plan.plan_dict.StationNumbering`): walking order where a field sheet is made,
else plan order, said in each legend.

:func:`station_identity` reads what one run wrote (report.html, field.html, field.json, field.csv, field.geojson,
stations.csv, plan.geojson, plan.dxf, plan.json, network.json, those present) and returns, per place, each label's
number; :func:`check_station_identity` asserts they all agree with plan.json. The README's main job runs it too
(tests/test_readme.py, slow tier)."""

from __future__ import annotations

import csv
import io
import json
import re
from html.parser import HTMLParser
from pathlib import Path

import ezdxf
import pytest

from planner.cli import main
from planner.io.dxf_entities import APPID
from planner.plan.plan_dict import PLAN_ORDER, WALKING_ORDER, StationNumbering
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide
from tests.conftest import INSTANCES


class _Page(HTMLParser):
    """What a page says of its stations: every element's ``data-station-number`` and ``data-station-label``, the
    text each map marker draws, the 3-D view's scene, and its tables as rows of cell texts."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.tagged: list[tuple[str, str, str]] = []  # (where, label, number)
        self.markers: list[tuple[str, str]] = []  # (data-id, the number drawn)
        self.tables: list[list[list[str]]] = []
        self.body: dict[str, str] = {}
        self.scene = ""
        self._marker: str | None = None
        self._text = False
        self._cell: list[str] | None = None
        self._json = False

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = {k: v or "" for k, v in attrs}
        if tag == "body":
            self.body = a
        if "data-station-number" in a or "data-station-label" in a:
            where = f"{tag}.{a.get('class', '')}".strip(".")
            self.tagged.append((where, a.get("data-station-label", ""), a.get("data-station-number", "")))
        if tag == "g" and "sm-st" in a.get("class", "").split():
            self._marker = a.get("data-id", "")
        if tag == "text" and self._marker is not None:
            self._text = True
        if tag == "table":
            self.tables.append([])
        if tag == "tr" and self.tables:
            self.tables[-1].append([])
        if tag in ("td", "th"):
            self._cell = []
        if tag == "script" and a.get("class") == "v3-data":
            self._json = True

    def handle_endtag(self, tag: str) -> None:
        if tag == "text" and self._marker is not None:  # a station marker draws one text, its number
            self._text, self._marker = False, None
        if tag in ("td", "th") and self._cell is not None and self.tables and self.tables[-1]:
            self.tables[-1][-1].append("".join(self._cell).strip())
            self._cell = None
        if tag == "script":
            self._json = False

    def handle_data(self, data: str) -> None:
        if self._text and self._marker is not None:
            self.markers.append((self._marker, data.strip()))
        if self._cell is not None:
            self._cell.append(data)
        if self._json:
            self.scene += data


def _page(path: Path) -> _Page:
    p = _Page()
    p.feed(path.read_text(encoding="utf-8"))
    return p


def _numbers(pairs: list[tuple[str, object]], where: str) -> dict[str, int]:
    """label -> number, each label once."""
    out: dict[str, int] = {}
    for label, number in pairs:
        assert label not in out, f"{where}: station {label} listed twice"
        out[str(label)] = int(str(number))
    return out


def _setup_table(page: _Page, where: str) -> dict[str, int]:
    """The table whose header starts "no.", "station" (the station table, the setup table): label -> number."""
    for t in page.tables:
        if t and t[0][:2] in (["no.", "id"], ["no.", "station"]):
            return _numbers([(r[1], r[0]) for r in t[1:] if len(r) > 1 and r[0].isdigit()], where)  # not the totals
    raise AssertionError(f"{where}: no table of numbered stations")


def _html(path: Path, name: str) -> dict[str, dict[str, int]]:
    page = _page(path)
    out: dict[str, dict[str, int]] = {}
    for kind in sorted({w for w, _, _ in page.tagged}):
        out[f"{name} {kind}"] = _numbers([(lb, n) for w, lb, n in page.tagged if w == kind], f"{name} {kind}")
    labels = {lb for _w, lb, _n in page.tagged}
    assert page.markers, f"{name}: no station marker on the map"
    out[f"{name} map numbers drawn"] = _numbers(page.markers, f"{name} map")
    out[f"{name} table"] = _setup_table(page, name)
    if page.scene:
        scene = json.loads(page.scene)
        out[f"{name} 3-D view"] = _numbers([(s[0], s[1]) for s in scene["stations"]], f"{name} 3-D view")
    assert labels, f"{name}: no data-station-label"
    return out


def _geojson(path: Path) -> dict[str, int]:
    feats = json.loads(path.read_text())["features"]
    st = [f["properties"] for f in feats if f["properties"].get("role") == "station"]
    assert all(p["label"] == p["id"] for p in st)
    return _numbers([(p["label"], p["number"]) for p in st], path.name)


def _csv(text: str, label: str, number: str | None) -> list[dict[str, str]]:
    rows = list(csv.DictReader(io.StringIO("\n".join(ln for ln in text.splitlines() if not ln.startswith("#")))))
    assert rows and label in rows[0] and (number is None or number in rows[0])
    return rows


def station_identity(folder: Path) -> dict[str, dict[str, int]]:
    """Per place in the files of one run in ``folder`` (those present), each station label's number."""
    out: dict[str, dict[str, int]] = {}
    plan = json.loads((folder / "plan.json").read_text())
    assert all(s["label"] == s["id"] for s in plan["stations"])
    out["plan.json"] = _numbers([(s["label"], s["number"]) for s in plan["stations"]], "plan.json")
    if (folder / "report.html").is_file():
        out |= _html(folder / "report.html", "report.html")
    if (folder / "field.html").is_file():
        out |= _html(folder / "field.html", "field.html")
    if (folder / "field.json").is_file():
        sheet = json.loads((folder / "field.json").read_text())
        out["field.json setups"] = _numbers([(s["station"], s["no."]) for s in sheet["setups"]], "field.json")
        out["field.json numbering"] = {sid: k for k, sid in enumerate(sheet["numbering"]["labels"], 1)}
    if (folder / "field.csv").is_file():
        rows = _csv((folder / "field.csv").read_text(), "station", "no.")
        out["field.csv"] = _numbers([(r["station"], r["no."]) for r in rows], "field.csv")
    if (folder / "stations.csv").is_file():  # row k is station no. k
        rows = _csv((folder / "stations.csv").read_text(), "ID", None)
        out["stations.csv"] = _numbers([(r["ID"], k) for k, r in enumerate(rows, 1)], "stations.csv")
    for name in ("plan.geojson", "field.geojson"):
        if (folder / name).is_file():
            out[name] = _geojson(folder / name)
    if (folder / "plan.dxf").is_file():
        msp = ezdxf.readfile(folder / "plan.dxf").modelspace()
        points = [p for p in msp.query('POINT[layer=="STATIONS"]') if p.has_xdata(APPID)]
        tags = [dict(str(v).split("=", 1) for _c, v in p.get_xdata(APPID)) for p in points]
        out["plan.dxf"] = _numbers([(t["label"], t["number"]) for t in tags], "plan.dxf")
        numbers = {t.dxf.text for t in msp.query('TEXT[layer=="NUMBERS"]')}
        assert numbers == {str(n) for n in out["plan.dxf"].values()}
    return out


def check_station_identity(folder: Path) -> str:
    """Assert that every place of :func:`station_identity` numbers every station of plan.json as plan.json does, and
    that network.json (where present) names stations by those labels; return the numbering basis."""
    places = station_identity(folder)
    want = places["plan.json"]
    assert sorted(want.values()) == list(range(1, len(want) + 1))
    for where, got in places.items():
        assert got == want, f"{where}: {sorted(set(got.items()) ^ set(want.items()))[:6]}"
    plan = json.loads((folder / "plan.json").read_text())
    basis = plan["numbering"]["basis"]
    if (folder / "network.json").is_file():
        net = json.loads((folder / "network.json").read_text())
        stations = {n["id"] for n in net["nodes"] if n.get("kind") == "station"}
        assert stations == set(want), "network.json names other stations than plan.json"
    if (folder / "report.html").is_file():
        report = (folder / "report.html").read_text()
        assert _page(folder / "report.html").body.get("data-station-numbering") == basis
        assert f"stations numbered in {basis}" in report.lower()
    return basis


def test_the_numbering_is_one_decision() -> None:
    st = [Candidate(f"S{k}", "Z", ScanSide.INSIDE, "site", float(k), 0.0, CandidateKind.GRID) for k in range(1, 5)]
    plain = StationNumbering.plan_order(st)
    assert plain.numbers == {"S1": 1, "S2": 2, "S3": 3, "S4": 4} and plain.basis == PLAN_ORDER
    assert "plan order" in plain.legend
    walk = StationNumbering.walking(st, ["S3", "S1"])  # those the walk leaves out follow in plan order
    assert walk.ids == ("S3", "S1", "S2", "S4") and walk.basis == WALKING_ORDER and "walking order" in walk.legend
    assert walk.label("S3") == "S3" and walk.number("S3") == 1 and walk.number("nowhere") == 0
    assert [s.id for s in walk.ordered(st)] == ["S3", "S1", "S2", "S4"]
    with pytest.raises(ValueError, match="does not have: X"):
        StationNumbering.walking(st, ["X"])
    # plan.json records it and gives it back; a field order wins where a sheet was made
    data = walk.record({"stations": [{"id": s.id} for s in st]})
    assert [r["number"] for r in data["stations"]] == [2, 3, 1, 4]
    assert StationNumbering.recorded(data, st) == walk
    assert StationNumbering.recorded({"stations": [{"id": s.id} for s in st]}, st) == plain
    assert StationNumbering.decide(data, st, ["S4", "S3", "S2", "S1"]).ids == ("S4", "S3", "S2", "S1")
    assert StationNumbering.decide(data, st, None) == walk


def test_a_plan_file_with_bad_numbers_is_refused_with_one_line(tmp_path: Path) -> None:
    from planner.core.errors import InputError
    from planner.io.plan_json import check_plan_meta

    rows = [{"id": "A", "number": 1, "label": "A"}, {"id": "B", "number": 1, "label": "B"}]
    with pytest.raises(InputError, match=r"stations\[2\].*number = 1: must be an integer in 1..2"):
        check_plan_meta({"numbering": {"basis": WALKING_ORDER}, "stations": rows}, "p.json")
    rows[1] = {"id": "B", "number": 2, "label": "B"}
    with pytest.raises(InputError, match="numbering.basis"):
        check_plan_meta({"numbering": {"basis": "alphabetical"}, "stations": rows}, "p.json")
    assert check_plan_meta({"numbering": {"basis": WALKING_ORDER}, "stations": rows}, "p.json")


def _run(out: Path, *extra: str) -> None:
    args = ["plan", str(INSTANCES / "house_doors.json"), "--method", "greedy", "--out", str(out), *extra]
    assert main([*args, "--quiet"]) == 0


@pytest.mark.slow
def test_every_file_of_a_run_with_a_field_sheet_numbers_each_station_alike(tmp_path: Path) -> None:
    out = tmp_path / "house"
    _run(out, "--network", "--export", "dxf,geojson,csv", "--report", str(out), "--field", str(out))
    assert check_station_identity(out) == WALKING_ORDER
    order = json.loads((out / "field.json").read_text())["order"]
    plan = json.loads((out / "plan.json").read_text())
    assert [s["id"] for s in sorted(plan["stations"], key=lambda s: s["number"])] == order
    # planner report PLAN.json and planner field PLAN.json reproduce the numbers plan.json records
    again = tmp_path / "again"
    assert main(["report", str(out / "plan.json"), "--out", str(again), "--export", "csv", "--quiet"]) == 0
    assert main(["field", str(out / "plan.json"), "--out", str(again), "--quiet"]) == 0
    rows = _csv((again / "stations.csv").read_text(), "ID", None)
    assert [r["ID"] for r in rows] == order
    assert json.loads((again / "field.json").read_text())["order"] == order


@pytest.mark.slow
def test_without_a_field_sheet_the_numbering_is_plan_order_and_the_legend_says_so(tmp_path: Path) -> None:
    out = tmp_path / "house"
    _run(out, "--export", "geojson,csv", "--report", str(out))
    assert check_station_identity(out) == PLAN_ORDER
    plan = json.loads((out / "plan.json").read_text())
    assert [s["number"] for s in plan["stations"]] == list(range(1, len(plan["stations"]) + 1))
    report = (out / "report.html").read_text()
    assert "Stations numbered in plan order (no field sheet was made)" in report
    assert re.search(r"the whole site: stations numbered in plan order", report)
