"""Outputs are staged and moved into place only when a command succeeds (:mod:`planner.cli.outputs`): a failed
run creates no output folder, leaves an existing one as it was and leaves no staging folder behind."""

from __future__ import annotations

import argparse
import json
import os
import sys
import types
from pathlib import Path

import pytest

from planner.cli import main
from planner.cli.main import _guarded, _run
from planner.cli.outputs import PREFIX
from planner.core.errors import ExitCode, InputError

SQUARE = {
    "format": "tls-planner/1",
    "name": "sq",
    "zones": [
        {
            "id": "A",
            "scan_side": "inside",
            "coordinates": [[0, 0], [10, 0], [10, 8], [0, 8]],
            "vertex_heights_m": [3, 3, 3, 3],
        }
    ],
}


def _tree(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` by its relative path, with its bytes."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def _no_staging_left(folder: Path) -> None:
    left = [p for p in folder.rglob("*") if p.name.startswith(PREFIX)]
    assert not left, left


@pytest.fixture
def site(tmp_path: Path) -> Path:
    path = tmp_path / "sq.json"
    path.write_text(json.dumps(SQUARE))
    return path


@pytest.fixture
def old(tmp_path: Path) -> Path:
    """An existing output folder with earlier files in it."""
    folder = tmp_path / "old"
    folder.mkdir()
    (folder / "plan.json").write_text('{"stations": []}')
    (folder / "notes.txt").write_text("kept")
    return folder


def _consistency(monkeypatch, messages: list[str]) -> list[list[Path]]:
    """Stand in for planner.report.consistency (the fake commands' files are no plan): ``messages`` for any
    folders; returns the folders it was asked about."""
    seen: list[list[Path]] = []

    def check_outputs(folders):
        seen.append(list(folders))
        return list(messages)

    module = types.ModuleType("planner.report.consistency")
    module.check_outputs = check_outputs  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "planner.report.consistency", module)
    return seen


@pytest.fixture
def agreeing(monkeypatch) -> list[list[Path]]:
    return _consistency(monkeypatch, [])


def _fake(write: dict[str, str], code: int = 0, error: Exception | None = None):
    """A command that writes ``write`` (option dest -> file name) into the folders ``args`` names, prints what it
    wrote, then fails with ``error`` or returns ``code``."""

    def command(args: argparse.Namespace) -> int:
        for dest, name in write.items():
            path = Path(getattr(args, dest)) / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(f"{dest} {os.path.relpath(args.field or '.', getattr(args, dest))}")
            print(f"wrote {path}")
        if error is not None:
            raise error
        return code

    return command


def _args(func, **outputs: str | None) -> argparse.Namespace:
    return argparse.Namespace(**({"command": "plan", "out": None, "report": None, "field": None} | outputs), func=func)


def test_a_command_that_succeeds_writes_its_files_where_given(tmp_path, capsys, old, agreeing):
    report, field = tmp_path / "a" / "r", tmp_path / "f"
    func = _fake({"out": "plan.json", "report": "report.html", "field": "field.html"})
    assert _staged(_args_with(func, out=old, report=report, field=field)) == 0
    printed = capsys.readouterr().out.splitlines()
    assert printed == [f"wrote {old}/plan.json", f"wrote {report}/report.html", f"wrote {field}/field.html"]
    assert (old / "notes.txt").read_text() == "kept"  # replaced file by file, the others left
    # the staging folders mirror the targets' folders: a relative path between two outputs holds after the move
    assert (report / "report.html").read_text() == f"report {os.path.relpath(field, report)}"
    assert (field / "field.html").is_file() and (old / "plan.json").read_text().startswith("out ")
    _no_staging_left(tmp_path)


def _args_with(func, **outputs: Path) -> argparse.Namespace:
    return _args(func, **{k: str(v) for k, v in outputs.items()})


@pytest.mark.parametrize("failure", ["exception", "exit code", "interrupt"])
def test_a_command_that_fails_writes_nothing(tmp_path, capsys, old, agreeing, failure):
    error = {"exception": InputError("bad", file="x"), "interrupt": KeyboardInterrupt(), "exit code": None}[failure]
    func = _fake({"out": "plan.json", "field": "field.json"}, code=4, error=error)
    before = _tree(old)
    code = _staged(_args_with(func, out=old, report=tmp_path / "new" / "r", field=tmp_path / "f"))
    assert code == {"exception": 3, "interrupt": 130, "exit code": 4}[failure]
    assert _tree(old) == before
    assert not (tmp_path / "new").exists() and not (tmp_path / "f").exists()
    _no_staging_left(tmp_path)


def test_the_files_read_back_are_seen_and_kept(tmp_path, capsys, old, agreeing):
    """The field sheet already in an output folder is there for the command (the report links it) and is not
    rewritten when the command leaves it alone."""
    (old / "field.html").write_text("sheet")
    stamp = (old / "field.html").stat().st_mtime_ns

    def command(args: argparse.Namespace) -> int:
        assert (Path(args.out) / "field.html").read_text() == "sheet"
        (Path(args.out) / "report.html").write_text("report")
        return 0

    args = _args_with(command, out=old)
    args.command = "report"  # a report of the plan there: the plan's sheet is its own
    assert _staged(args) == 0
    assert (old / "field.html").stat().st_mtime_ns == stamp and (old / "report.html").read_text() == "report"


def test_a_new_plan_moves_the_earlier_plans_outputs_aside(tmp_path, capsys, old, agreeing):
    """A plan written into a folder that holds an earlier plan's sheet, report and exports: those it does not rewrite
    would disagree with the new plan.json, so they are not read back and move, with the earlier plan.json, into
    superseded.N; the folder's other files (the pool, a re-plan's history, the user's own) stay. A failed plan moves
    nothing."""
    earlier = {"field.json": "sheet", "field.html": "page", "report.html": "report", "sheet/field.pdf": "pdf"}
    for name, text in {**earlier, "replan.npz": "pool", "plan.1.json": "history"}.items():
        (old / name).parent.mkdir(parents=True, exist_ok=True)
        (old / name).write_text(text)
    before = _tree(old)

    def command(args: argparse.Namespace) -> int:
        assert not (Path(args.out) / "field.html").exists()  # the earlier plan's sheet is not this plan's
        (Path(args.out) / "plan.json").write_text("new")
        (Path(args.out) / "report.html").write_text("new report")
        return 0

    assert _staged(_args_with(_fake({"out": "plan.json"}, code=4), out=old)) == 4
    assert _tree(old) == before
    assert _staged(_args_with(command, out=old)) == 0
    moved = sorted(["plan.json", *earlier.keys() - {"report.html"}])
    assert sorted(_tree(old / "superseded.1")) == moved
    assert (old / "superseded.1" / "plan.json").read_text() == '{"stations": []}'
    assert (old / "superseded.1" / "field.json").read_text() == "sheet"
    left = {"plan.json": "new", "report.html": "new report", "replan.npz": "pool", "plan.1.json": "history"}
    assert {k: v for k, v in _tree(old).items() if not k.startswith("superseded")} == {
        **{k: v.encode() for k, v in left.items()},
        "notes.txt": b"kept",
    }
    note = capsys.readouterr().err
    assert f"moved to {old / 'superseded.1'}" in note and "field.json" in note and "report.html" not in note
    (old / "field.csv").write_text("again")  # the next plan's earlier outputs go to the next number
    assert _staged(_args_with(command, out=old)) == 0
    assert sorted(_tree(old / "superseded.2")) == ["field.csv", "plan.json"]
    _no_staging_left(tmp_path)


def test_outputs_that_disagree_are_not_moved(tmp_path, capsys, monkeypatch):
    seen = _consistency(monkeypatch, ["plan.json has 3 stations, field.json 2"])
    code = _staged(_args_with(_fake({"out": "plan.json"}), out=tmp_path / "o"))
    assert code == ExitCode.INTERNAL and not (tmp_path / "o").exists()
    assert capsys.readouterr().err.strip() == "planner: inconsistent outputs: plan.json has 3 stations, field.json 2"
    assert len(seen) == 1 and seen[0][0].name == "o" and seen[0][0].parent.name.startswith(PREFIX)
    _no_staging_left(tmp_path)


def test_unusable_outputs_are_refused_before_anything_is_made(tmp_path, capsys, agreeing):
    afile = tmp_path / "afile"
    afile.write_text("x")
    for target, words in ((afile, "is a file, not a folder"), (afile / "sub", "is a file)"), ("", "is empty")):
        assert _staged(_args(_fake({"out": "plan.json"}), out=str(target))) == ExitCode.USAGE
        assert words in capsys.readouterr().err
    _no_staging_left(tmp_path)


def _staged(args: argparse.Namespace) -> int:
    """What ``planner.cli.main.main`` does with parsed ``args``."""
    return _guarded(lambda: _run(args))


def _plan(tmp_path: Path, site: Path, *extra: str) -> int:
    return main(["plan", str(site), "--method", "greedy", "--quiet", *extra])


@pytest.mark.parametrize(
    "case",
    [
        "bad site",  # invalid JSON
        "bad option",  # refused after the site is read
        pytest.param("bad sheet option", marks=pytest.mark.slow),  # refused when the field sheet's stack loads
        "infeasible",  # no wall within range: nothing to plan
    ],
)
def test_failed_plans_create_no_folder_and_keep_old_ones(tmp_path, capsys, site, old, case):
    bad = tmp_path / "bad.json"
    bad.write_text('{"zones": [')
    path, extra, code = {
        "bad site": (bad, [], ExitCode.INVALID_INPUT),
        "bad option": (site, ["--max-range", "-5"], ExitCode.USAGE),
        "bad sheet option": (site, ["--set", "field-session=zz"], ExitCode.USAGE),
        "infeasible": (site, ["--max-range", "0.5"], ExitCode.INFEASIBLE),
    }[case]
    fresh = ["--out", str(tmp_path / "o"), "--report", str(tmp_path / "r"), "--field", str(tmp_path / "f")]
    before = _tree(old)
    assert _plan(tmp_path, path, *extra, *fresh) == code
    assert _plan(tmp_path, path, *extra, "--out", str(old), "--report", str(old), "--field", str(old)) == code
    capsys.readouterr()
    assert not any((tmp_path / d).exists() for d in "orf")
    assert _tree(old) == before
    _no_staging_left(tmp_path)


def test_a_successful_plan_writes_the_same_files(tmp_path, capsys, site, old):
    assert _plan(tmp_path, site, "--out", str(tmp_path / "a" / "o"), "--export", "csv") == 0
    assert set(_tree(tmp_path / "a" / "o")) == {"plan.json", "stations.csv", "replan.npz"}
    out = capsys.readouterr().out
    assert f"wrote {tmp_path / 'a' / 'o' / 'plan.json'}\n" in out and PREFIX not in out
    assert _plan(tmp_path, site, "--out", str(old)) == 0
    assert (
        set(_tree(old)) == {"plan.json", "notes.txt", "replan.npz"}
        and json.loads((old / "plan.json").read_text())["stations"]
    )
    _no_staging_left(tmp_path)


def test_export_writes_its_file_only_on_success(tmp_path, capsys, site):
    target = tmp_path / "problem.mps"
    target.write_text("old")
    argv = ["export", str(site), "--format", "orlib", "--out", str(target), "--quiet"]
    assert main([*argv, "--max-range", "-5"]) == ExitCode.USAGE
    assert target.read_text() == "old"
    assert main(argv) == 0 and target.read_text() != "old"
    assert f"wrote {target}:" in capsys.readouterr().out
    _no_staging_left(tmp_path)


@pytest.mark.slow
def test_plan_with_report_and_field_writes_every_file(tmp_path, capsys, site):
    out, report, field = tmp_path / "o", tmp_path / "r", tmp_path / "f"
    assert _plan(tmp_path, site, "--out", str(out), "--report", str(report), "--field", str(field)) == 0
    assert set(_tree(out)) == {"plan.json", "replan.npz"} and set(_tree(report)) == {"report.html"}
    assert set(_tree(field)) == {f"field.{ext}" for ext in ("html", "csv", "geojson", "json", "pdf")}
    assert 'href="../f/field.html"' in (report / "report.html").read_text()
    _no_staging_left(tmp_path)
