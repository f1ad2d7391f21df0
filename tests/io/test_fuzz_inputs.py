"""Fuzzing every reader through the command line: a bundled or exported file, cut short, with bytes changed or with
lines dropped, is read whole or refused in one line.

Files: the table CSVs and JSON instances of instances/ (the plant_16ha/64ha instances left out: their size only slows
the run; baalbek.csv is read through baalbek.json, alone it is refused for the misclosures the instance corrects),
house2.ifc, a DXF drawing written with ezdxf, the DXF and GeoJSON the planner's exporters write for polygon_b's plan,
the AGPLIB polygons of tests/data, the plan.json of ``planner plan instances/polygon_b.json --method closed-form``,
and a control and an observation file for that plan. Each is read by the CLI in-process: ``planner validate FILE``
for sites, ``planner verify SITE PLAN`` and ``planner field PLAN`` (the site the plan names, read by
planner/io/plan_file.py) for plan.json, ``planner network SITE PLAN --control FILE`` / ``--observations FILE``.

Oracle, for every mutant:

* no traceback and no exit 1 (internal error): the exit code is 0, 2 or 3;
* on an error, stderr is exactly one line, and it names the mutated file;
* no exit 0 on a mutant that lost content (a cut, or dropped lines) unless one of these holds:

  - the read equals the original's: only insignificant bytes were lost (trailing whitespace, a blank line, an unused
    header entry); for a site, :func:`planner.load_site` of the mutant equals the original's (name and path aside);
    for plan, control and observation files, the parsed JSON is equal;
  - the format cannot tell, and the read is what the format says was kept:

    - table CSV: whole zones were lost (the read zones are the original's, in order, some left out: a table CSV
      cannot tell a zone it lost from one never written). A row cut mid-line is refused (the last row must end with
      a line end), a zone short of rows fails its closure;
    - AGPLIB .pol (one line of tokens, no end marker, the hole list optional): the cut keeps exactly the outline
      (1 + 2n tokens: the hole list is lost whole), or every token with the last cut short (a number cut short is a
      shorter number);
    - JSON files (instances, GeoJSON, plan, control, observations), dropped lines only: the mutant is still valid
      JSON (a complete member or element removed reads as one never written; a cut JSON never parses);
    - DXF, dropped lines only: whole group-code pairs were dropped (an even number of lines from a group code: a
      removed tag reads as one never written); a pair broken apart is refused.

  IFC has no such case: a cut loses the end marker, a dropped instance leaves a reference undefined or a product in
  no storey, all refused.

Bytes changed may give another valid file (a digit changed is another number): only the first two rules apply.
"""

from __future__ import annotations

import contextlib
import dataclasses
import io
import json
import shutil
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from planner.cli.main import main
from planner.core.errors import PlannerError
from tests.conftest import INSTANCES, ROOT

#: the JSON instances fuzzed (the 16 ha and 64 ha plants only take longer)
JSON_INSTANCES = sorted(
    p.name
    for p in INSTANCES.glob("*.json")
    if p.stem not in ("plant_16ha", "plant_64ha") and not p.name.endswith(".edits.json")
)
CSV_INSTANCES = sorted(p.name for p in INSTANCES.glob("*.csv"))
POL_FILES = sorted((ROOT / "tests" / "data" / "agplib").glob("*.pol"))


@dataclass(frozen=True, kw_only=True)
class Case:
    """One bundled or written file to mutate: its bytes, the format, the CLI arguments reading a copy, the read."""

    name: str
    fmt: str  # csv, json, ifc, dxf, geojson, pol, plan, control, observations
    data: bytes
    argv: Callable[[Path], list[str]]
    original: Any  # the normalised read of the unmutated file


def _run(argv: list[str]) -> tuple[int, str, str]:
    """The CLI in-process: exit code, stdout, stderr."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as done:  # main returns its code; a SystemExit escaping it is a finding too
            code = done.code if isinstance(done.code, int) else 1
    return code, out.getvalue(), err.getvalue()


def _site(path: Path) -> Any:
    from planner.io.load import load_site

    return dataclasses.replace(load_site(path), name="", source="")


def _json(path: Path) -> Any:
    return json.loads(path.read_bytes().decode("utf-8-sig"))


@pytest.fixture(scope="module")
def work(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder with the instances' table CSVs (a JSON instance names its tables relative to itself)."""
    folder = tmp_path_factory.mktemp("fuzz")
    for name in CSV_INSTANCES:
        shutil.copy(INSTANCES / name, folder / name)
    return folder


def _site_case(name: str, fmt: str, path: Path) -> Case:
    return Case(name=name, fmt=fmt, data=path.read_bytes(), argv=lambda p: ["validate", str(p)], original=_site(path))


def _dxf(folder: Path) -> Path:
    """A drawing with two zones, a hole and an obstacle, metres, as a CAD user draws one."""
    import ezdxf

    doc = ezdxf.new("R2000")
    doc.header["$INSUNITS"] = 6
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (10, 0), (10, 6), (0, 6)], close=True, dxfattribs={"layer": "ZONES", "thickness": 3})
    msp.add_lwpolyline(
        [(12, 0), (20, 0), (20, 8), (16, 10), (12, 8)],
        close=True,
        dxfattribs={"layer": "ZONES-OUTSIDE", "thickness": 4},
    )
    msp.add_lwpolyline([(4, 2), (5, 2), (5, 3), (4, 3)], close=True, dxfattribs={"layer": "HOLES", "thickness": 3})
    msp.add_lwpolyline([(7, 4), (8, 4), (8, 5)], close=True, dxfattribs={"layer": "OBSTACLES", "thickness": 1})
    msp.add_text("Hall", dxfattribs={"layer": "ZONES", "insert": (1, 1)})
    path = folder / "drawing.dxf"
    doc.saveas(path)
    return path


@pytest.fixture(scope="module")
def plan_dir(work: Path) -> Path:
    """polygon_b planned by closed form (plan.json), with its GeoJSON export, a control and an observation file."""
    instance = work / "polygon_b.json"
    shutil.copy(INSTANCES / "polygon_b.json", instance)
    out = work / "plan"
    code, _, err = _run(["plan", str(instance), "--method", "closed-form", "--out", str(out), "--quiet"])
    assert code == 0, err
    from planner.io.dxf_out import write_dxf
    from planner.io.geojson_out import write_geojson
    from planner.io.plan_file import outcome_from_file

    outcome = outcome_from_file(out / "plan.json")
    write_geojson(outcome, out / "plan.geojson")
    write_dxf(outcome, out / "plan.dxf")
    stations = json.loads((out / "plan.json").read_text())["stations"]
    control = [
        {"name": "CP1", "x": -30.0, "y": -40.0, "sigma_x_mm": 0, "sigma_y_mm": 0},
        {"name": "CP2", "x": 160.0, "y": 80.0, "sigma_x_mm": 2, "sigma_y_mm": 2},
    ]
    (out / "control.json").write_text(json.dumps(control, indent=2) + "\n")
    obs = [
        {"kind": k, "at": s["id"], "value": round(s[k], 3), "sigma": 0.005} for s in stations for k in ("x", "y")
    ] + [{"kind": "distance", "at": stations[0]["id"], "to": stations[1]["id"], "value": 95.0, "sigma": 0.01}]
    text = json.dumps({"angle_unit": "deg", "length_unit": "m", "observations": obs}, indent=2) + "\n"
    (out / "observations.json").write_text(text)
    return out


def _cases(fmt: str, work: Path, plan: Path | None) -> list[Case]:
    """The files of one reader."""
    site = str(work / "polygon_b.json")
    if fmt == "csv":
        return [_site_case(n, fmt, INSTANCES / n) for n in CSV_INSTANCES if n != "baalbek.csv"]
    if fmt == "json":
        for n in JSON_INSTANCES:
            shutil.copy(INSTANCES / n, work / n)
        return [_site_case(n, fmt, work / n) for n in JSON_INSTANCES]
    if fmt == "ifc":
        return [_site_case("house2.ifc", fmt, INSTANCES / "house2.ifc")]
    if fmt == "pol":
        return [_site_case(p.name, fmt, p) for p in POL_FILES]
    assert plan is not None
    if fmt == "geojson":
        return [_site_case("plan.geojson", fmt, plan / "plan.geojson")]
    if fmt == "dxf":
        return [_site_case("drawing.dxf", fmt, _dxf(work)), _site_case("plan.dxf", fmt, plan / "plan.dxf")]
    if fmt == "plan":
        argv = lambda p: ["verify", site, str(p), "--spacing", "1", "--quiet"]  # noqa: E731
        return [Case(name="plan.json", fmt=fmt, data=(plan / "plan.json").read_bytes(), argv=argv, original=None)]
    if fmt == "plan_field":  # plan.json as planner/io/plan_file.py reads it: the site it names, its parameters
        argv = lambda p: ["field", str(p), "--out", str(work / "field")]  # noqa: E731
        return [Case(name="plan.json", fmt=fmt, data=(plan / "plan.json").read_bytes(), argv=argv, original=None)]
    plan_json = str(plan / "plan.json")
    option = "--control" if fmt == "control" else "--observations"
    name = f"{fmt}.json"
    argv = lambda p: ["network", site, plan_json, option, str(p), "--quiet"]  # noqa: E731
    return [Case(name=name, fmt=fmt, data=(plan / name).read_bytes(), argv=argv, original=None)]


# ---- mutations -------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Mutation:
    """A cut at ``at`` bytes, ``changes`` (offset, byte) put in, or ``count`` lines dropped from line ``at``."""

    kind: str  # cut, bytes, drop
    at: int = 0
    count: int = 0
    changes: tuple[tuple[int, int], ...] = ()

    def apply(self, data: bytes) -> bytes:
        if self.kind == "cut":
            return data[: self.at % max(1, len(data))]
        if self.kind == "bytes":
            out = bytearray(data)
            for pos, byte in self.changes:
                out[pos % len(out)] = byte
            return bytes(out)
        lines = data.splitlines(keepends=True)
        start = self.at % len(lines)
        return b"".join(lines[:start] + lines[start + self.count :])


_BYTES = b"0123456789.-,;:()#'\"{}[] \nAZaz\xff\x00"


def mutations(data: bytes) -> st.SearchStrategy[Mutation]:
    """Cuts (anywhere, and at line ends, where a format's units end), 1-3 bytes changed, 1-3 lines dropped."""
    ends = [0]
    for line in data.splitlines(keepends=True):
        ends.append(ends[-1] + len(line))
    lines = len(ends) - 1
    return st.one_of(
        st.builds(Mutation, st.just("cut"), st.integers(0, len(data) - 1)),
        st.builds(Mutation, st.just("cut"), st.sampled_from(ends[1:-1] or [0])),
        st.builds(
            Mutation,
            st.just("bytes"),
            changes=st.lists(
                st.tuples(st.integers(0, len(data) - 1), st.sampled_from(_BYTES)), min_size=1, max_size=3
            ).map(tuple),
        ),
        st.builds(Mutation, st.just("drop"), st.integers(0, lines - 1), st.integers(1, 3)),
    )


# ---- the oracle ------------------------------------------------------------------------------------------------


def _read(case: Case, path: Path) -> Any:
    """The mutant's read as the original's is compared (None: it cannot be read)."""
    try:
        return _json(path) if case.original is None else _site(path)
    except (PlannerError, ValueError):
        return None


def _format_cannot_tell(case: Case, mutation: Mutation, mutant: bytes, path: Path) -> bool:
    """The exceptions of the module docstring, where a format cannot tell lost content from content never given."""
    if case.fmt == "csv":
        read = _read(case, path)
        zones = list(case.original.zones)
        kept = [z for z in zones if read is not None and z in read.zones]
        return read is not None and len(kept) == len(read.zones) and list(read.zones) == kept
    if case.fmt == "pol" and mutation.kind == "cut":
        tokens, whole = mutant.split(), case.data.split()
        n = int(whole[0])
        prefix = tokens[:-1] == whole[: len(tokens) - 1] and whole[len(tokens) - 1].startswith(tokens[-1])
        return prefix and len(tokens) in (1 + 2 * n, len(whole))
    if mutation.kind == "drop" and case.fmt in ("json", "geojson", "plan", "plan_field", "control", "observations"):
        try:
            json.loads(mutant.decode("utf-8-sig"))
        except ValueError:
            return False
        return True
    if mutation.kind == "drop" and case.fmt == "dxf":
        return mutation.at % len(case.data.splitlines()) % 2 == 0 and mutation.count % 2 == 0
    return False


def check_mutant(case: Case, mutation: Mutation, folder: Path) -> None:
    """Write the mutant next to the instances' tables, read it through the CLI and apply the oracle."""
    mutant = mutation.apply(case.data)
    if mutant == case.data:
        return
    path = folder / f"mutant_{case.name}"
    path.write_bytes(mutant)
    code, _, err = _run(case.argv(path))
    assert "Traceback" not in err, err
    assert code in (0, 2, 3), f"{mutation}: exit {code}: {err}"
    if code != 0:
        lines = err.strip().splitlines()
        assert len(lines) == 1, f"{mutation}: {err}"
        assert path.name in lines[0], f"{mutation}: the error names another file: {err}"
        return
    if mutation.kind == "bytes":
        return
    read = _read(case, path)
    original = case.original if case.original is not None else json.loads(case.data.decode("utf-8-sig"))
    same = read is not None and read == original
    assert same or _format_cannot_tell(case, mutation, mutant, path), f"{mutation}: exit 0 on a file that lost content"


FORMATS = ("csv", "json", "ifc", "dxf", "geojson", "pol", "plan", "plan_field", "control", "observations")
#: examples per reader: quick tier (about 110 in all), slow tier (over 500)
QUICK = {
    "csv": 15,
    "json": 15,
    "ifc": 12,
    "dxf": 15,
    "geojson": 10,
    "pol": 15,
    "plan": 6,
    "plan_field": 3,
    "control": 8,
    "observations": 8,
}
FULL = {
    "csv": 80,
    "json": 80,
    "ifc": 60,
    "dxf": 80,
    "geojson": 50,
    "pol": 70,
    "plan": 30,
    "plan_field": 15,
    "control": 30,
    "observations": 30,
}


def _fuzz(fmt: str, examples: int, work: Path, request: pytest.FixtureRequest) -> None:
    plan = (
        request.getfixturevalue("plan_dir")
        if fmt in ("dxf", "geojson", "plan", "plan_field", "control", "observations")
        else None
    )
    cases = _cases(fmt, work, plan)

    @settings(
        max_examples=examples,
        derandomize=True,
        deadline=None,
        database=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
    )
    @given(st.sampled_from(cases).flatmap(lambda c: st.tuples(st.just(c), mutations(c.data))))
    def run(pair: tuple[Case, Mutation]) -> None:
        check_mutant(*pair, work)

    run()


@pytest.mark.parametrize("fmt", FORMATS)
def test_mutated_inputs_are_read_whole_or_refused_in_one_line(fmt, work, request):
    _fuzz(fmt, QUICK[fmt], work, request)


@pytest.mark.slow
@pytest.mark.heavy
@pytest.mark.parametrize("fmt", FORMATS)
def test_mutated_inputs_at_full_size(fmt, work, request):
    _fuzz(fmt, FULL[fmt], work, request)


def test_total_examples_cover_every_reader():
    """At least 500 mutants in the slow tier, over every reader; a modest quick tier."""
    assert set(QUICK) == set(FULL) == set(FORMATS)
    assert sum(FULL.values()) >= 500 and 100 <= sum(QUICK.values()) <= 150


@pytest.mark.parametrize("command", ["validate", "plan"])
def test_a_cut_ifc_file_is_refused_naming_the_missing_end_marker(command, tmp_path):
    """The first 10,000 of house2.ifc's bytes: it planned 3 of 6 rooms before, with exit 0."""
    cut = tmp_path / "house2_cut.ifc"
    cut.write_bytes((INSTANCES / "house2.ifc").read_bytes()[:10000])
    argv = [command, str(cut)] + (["--out", str(tmp_path / "out"), "--quiet"] if command == "plan" else [])
    code, _, err = _run(argv)
    assert code == 3
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "house2_cut.ifc" in lines[0] and "END-ISO-10303-21;" in lines[0], err
    assert not (tmp_path / "out" / "plan.json").exists()
