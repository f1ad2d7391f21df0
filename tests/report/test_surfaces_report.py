"""Floors and ceilings in report.html (issue 46): a walls-only report has neither the "Floors and ceilings" section
nor the map's floors layer; a 10 x 6 m room planned with floors (a table CSV, the Leica P30 at 1.5 m) has the
section, its rows those of plan.json's ``surfaces`` verification, and per station the floor cells of the map are
the patches that station sees, recomputed here from the site, plan.json's stations and the sight rule. In
headless Chromium, a click on a station marks its floor cells."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
import shapely

from planner.cli import main
from planner.core.errors import ExitCode
from planner.io.load import load_site
from planner.plan import PlanOptions
from planner.plan.problem import resolve
from planner.plan.surfaces import patch_matrix
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide
from tests.browser import body_attributes, chromium, dump_dom, probe

HEADER = "zone,scan_side,index,side_length_m,wall_height_m,interior_angle_deg,vertex_height_m"
GROUP = re.compile(r'<g class="sm-fl" data-st="([^"]+)">(.*?)</g>')
PATH = re.compile(r'<path class="sm-(floor|ceiling)" d="([^"]+)" data-n="(\d+)" data-m2="([\d.]+)">')


def _plan(tmp_path: Path, name: str, *extra: str) -> tuple[Path, Path, dict]:
    room = tmp_path / "room.csv"
    if not room.exists():
        rows = [f"R,inside,{i},{length},3,90,3" for i, length in enumerate((10, 6, 10, 6), 1)]
        room.write_text("\n".join([HEADER, *rows]) + "\n")
    out = tmp_path / name
    assert main(["plan", str(room), *extra, "--quiet", "--out", str(out), "--report", str(out)]) == ExitCode.OK
    return room, out, json.loads((out / "plan.json").read_text())


@pytest.fixture(scope="module")
def floors(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, dict]:
    """The room planned with its floor: the room, the output folder and plan.json."""
    return _plan(tmp_path_factory.mktemp("floors"), "f", "--surfaces", "walls,floors", "--instrument-height", "1.5")


def _seen(room: Path, plan: dict) -> tuple[list[str], object, object]:
    """The station ids, the patches and the stations x patches sight matrix, rebuilt from plan.json."""
    site = load_site(room)
    problem = resolve(site, PlanOptions(surfaces=("walls", "floors")))
    assert problem.surfaces is not None
    stations = [
        Candidate(s["id"], s["zone"], ScanSide(s["side"]), "R", s["x"], s["y"], CandidateKind(s["kind"]))
        for s in plan["stations"]
    ]
    stations = [  # the frame as the site names it
        Candidate(c.id, c.zone, c.side, site.zones[0].frame, c.x, c.y, c.kind) for c in stations
    ]
    return [s.id for s in stations], problem.surfaces.patches, patch_matrix(site, problem.surfaces, stations)


def _shape(d: str) -> shapely.Geometry:
    """The even-odd shape of an SVG path of closed rings (centimetre text, y down)."""
    out = shapely.Polygon()
    for ring in d.split("Z"):
        pts = [tuple(map(float, p.split(","))) for p in ring.lstrip("M").split()]
        if pts:
            out = out.symmetric_difference(shapely.Polygon([(x, -y) for x, y in pts]))
    return out


def test_walls_only_report_has_no_floors(polygon_b_report: Path) -> None:
    # polygon B planned walls-only with its report (the session's, tests/conftest.py)
    out = polygon_b_report
    plan = json.loads((out / "plan.json").read_text())
    html = (out / "report.html").read_text()
    assert "surfaces" not in plan
    assert "Floors and ceilings" not in html and 'data-layer="floors"' not in html and 'class="sm-fl"' not in html
    assert 'data-fn="' not in html and "the floor and ceiling it covers" not in html


def test_section_rows_are_plan_json_verification(floors: tuple[Path, Path, dict]) -> None:
    _, out, plan = floors
    html = (out / "report.html").read_text()
    section = html[html.index("<h2>Floors and ceilings</h2>") :]
    ver = plan["surfaces"]["verification"]
    rows = re.findall(r'<tr><td class="l">([^<]*)</td><td class="l">(floor|ceiling)</td>(.*?)</tr>', section)
    cells = [(z, k, re.findall(r"<td[^>]*>([^<]*)</td>", rest)) for z, k, rest in rows]
    want = [(r["zone"], r["type"], [str(r["points"]), str(r["covered"]), f"{r['percent']:.3f}"]) for r in ver["zones"]]
    assert cells == want and [c[2][2] for c in cells] == ["100.000"] and ver["complete"]
    assert "complete</span>: 100.000 %" in section
    assert "Patches seen by no candidate: none" in section
    for rule in ("1.5 m", "68 deg", "35 deg (leica-p30)"):
        assert rule in section, rule
    # the bound the report states is plan.json's: over the plane for walls and floors, or over the pool with its reason
    if isinstance(plan.get("plane_bound"), (int, float)):
        assert (
            f"Bound: {plan['plane_bound']:g} stations over every position in the plane for walls and floors" in section
        )
        assert plan["certificate"]["scope"] == "plane, walls and floors"
    else:
        assert "candidate pool only" in section


def test_floor_cells_per_station_are_the_patches_it_sees(floors: tuple[Path, Path, dict]) -> None:
    room, out, plan = floors
    html = (out / "report.html").read_text()
    assert 'data-layer="floors"' in html
    ids, patches, seen = _seen(room, plan)
    groups = {sid: PATH.findall(body) for sid, body in GROUP.findall(html)}
    assert set(groups) == {sid for i, sid in enumerate(ids) if seen[i].nnz}
    for i, sid in enumerate(ids):
        cols = seen[i].indices
        if not cols.size:
            continue
        paths = groups[sid]
        assert sum(int(n) for *_, n, _ in paths) == cols.size
        assert sum(float(a) for *_, a in paths) == pytest.approx(patches.area_m2[cols].sum(), abs=0.01 * len(paths))
        drawn = shapely.union_all([_shape(d) for _, d, _, _ in paths])
        want = shapely.union_all(patches.polygon[cols])
        assert drawn.symmetric_difference(want).area < 1e-3  # the patches themselves, to the centimetre
        st = re.search(rf'data-id="{re.escape(sid)}"[^>]*data-fn="(\d+)" data-fm2="([\d.]+)"', html)
        assert st and int(st[1]) == cols.size


@pytest.mark.slow  # a headless browser; test_floor_cells_per_station_are_the_patches_it_sees is its quick twin
@pytest.mark.skipif(chromium() is None, reason="no Chromium here; the parse tests check the fragment")
def test_click_marks_the_stations_floor_cells(floors: tuple[Path, Path, dict], tmp_path: Path) -> None:
    room, out, plan = floors
    ids, patches, seen = _seen(room, plan)
    k = int(np.argmax(np.diff(seen.indptr)))
    steps = f"""
    var st = document.querySelector('.sm-st[data-id="{ids[k]}"]');
    var before = document.querySelectorAll('.sm-fl path.hl').length;
    st.dispatchEvent(new MouseEvent('click', {{bubbles: true, cancelable: true, view: window}}));
    var hl = document.querySelectorAll('.sm-fl path.hl'), n = 0, shown = 0;
    for (var i = 0; i < hl.length; i++) {{ n += +hl[i].getAttribute('data-n'); shown += getComputedStyle(hl[i]).display !== 'none'; }}
    b.setAttribute('data-fl', before + '/' + hl.length + '/' + shown + '/' + n);
    b.setAttribute('data-panel', document.querySelector('.sm-panel').textContent);
"""
    page = tmp_path / "probe.html"
    page.write_text((out / "report.html").read_text().replace("</body>", probe(steps) + "</body>"))
    b = body_attributes(dump_dom(page))
    assert json.loads(b["data-errors"]) == []
    cols = seen[k].indices
    kinds = len({(int(patches.zone[c]), int(patches.kind[c])) for c in cols})
    assert b["data-fl"] == f"0/{kinds}/{kinds}/{cols.size}"
    assert f"covers {cols.size} floor/ceiling patch(es)" in b["data-panel"]


def test_report_from_plan_json_draws_the_same_floor_cells(floors: tuple[Path, Path, dict], tmp_path: Path) -> None:
    """``planner report PLAN.json`` makes the patches again under the recorded rules: the same section, the same
    floors layer as the report ``planner plan --report`` wrote."""
    room, out, _ = floors
    again = tmp_path / "again"
    args = ["report", str(out / "plan.json"), "--site", str(room), "--out", str(again), "--no-network", "--quiet"]
    assert main(args) == ExitCode.OK
    first, second = (out / "report.html").read_text(), (again / "report.html").read_text()
    assert GROUP.findall(second) == GROUP.findall(first) != []
    sec = "<h2>Floors and ceilings</h2>"
    assert second[second.index(sec) :] == first[first.index(sec) :]
