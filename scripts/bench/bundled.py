"""Wall time of every bundled default plan, the README's main job and the surfaces case, with their phases.

Usage: python scripts/bench/bundled.py [--only polygon_a ...] [--skip-surfaces] [--out-dir docs/benchmarks]

Each row is one ``planner`` command line run once as a child under ``/usr/bin/time -v`` (wall time, CPU time,
peak RSS), in one run of this script so that the ratios between rows are measured on the same machine state: the
default plan (``planner plan instances/X.json``), the greedy of the same site (``--method greedy``: the ratio
``default / greedy`` says what the proof costs over the quickest plan), the README's main job (plan, network
check, report, field sheet and exports), ``polygon_b.csv --surfaces walls,floors`` and a malformed JSON file (time
to the one-line error). The phases are read from the plan's own log in ``plan.json`` (what the summary prints:
coverage build, pricing over the plane, connected plane bound, the solver alone); ``rest`` is the wall time less
those (start-up, reading, candidates, presolve, verification, the outputs). Times are for one thread unless a row
says otherwise. Writes ``bundled.csv`` and ``bundled.md`` to the output folder.

The package's bytecode is compiled first (``compileall``), as ``pip install`` leaves it and as any run leaves it
in ``__pycache__`` unless ``PYTHONDONTWRITEBYTECODE`` is set: with that variable set (this sandbox sets it) and no
bytecode, every run compiles the whole package again, 2-3 s of a plan. One row, polygon C ``no bytecode``, measures
that case (``PYTHONPYCACHEPREFIX`` at an empty folder, nothing written).
"""

from __future__ import annotations

import argparse
import compileall
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _timed import ROOT, append_csv, peak_rss_mb

INSTANCES = ["polygon_a", "polygon_b", "polygon_c", "baalbek", "building27", "baalbek_site"]
FIELDS = [
    "case",
    "command",
    "exit",
    "wall_s",
    "cpu_s",
    "peak_rss_mb",
    "stations",
    "status",
    "bound",
    "bound_scope",
    "connected_plane_bound",
    "coverage_s",
    "pricing_s",
    "connected_bound_s",
    "solver_s",
    "rest_s",
    "vs_greedy",
]
#: (phase, pattern over the plan's log lines and headline): the seconds each phase took, as the summary prints them
PHASES = [
    ("coverage_s", re.compile(r"^coverage built in ([\d.]+) s")),
    ("pricing_s", re.compile(r"^pricing: .*, ([\d.]+) s$")),
    ("connected_bound_s", re.compile(r"^connected plane bound: .*; ([\d.]+) s\)$")),
]


def run(case: str, args: list[str], timeout_s: float, bytecode: bool = True) -> dict[str, Any]:
    """One ``planner`` command under ``/usr/bin/time -v`` with ``--out`` to a scratch folder: its row. Without
    ``bytecode``, Python finds no compiled module and writes none (the package compiled again on the run)."""
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ)
        if not bytecode:
            env.update(PYTHONPYCACHEPREFIX=str(Path(tmp) / "pycache"), PYTHONDONTWRITEBYTECODE="1")
        out = Path(tmp) / "out"
        cmd = [*args]
        if "--out" not in cmd and cmd[0] == "plan" and not case.startswith("malformed"):
            cmd += ["--out", str(out)]
        cmd = [a.replace("{OUT}", str(out)) for a in cmd]
        timed = ["/usr/bin/time", "-v", sys.executable, "-m", "planner", *cmd]
        t0 = time.perf_counter()
        try:
            proc = subprocess.run(timed, capture_output=True, text=True, cwd=ROOT, timeout=timeout_s, env=env)
            code, err = proc.returncode, proc.stderr
        except subprocess.TimeoutExpired:
            code, err = "timeout", ""
        wall = time.perf_counter() - t0
        row: dict[str, Any] = {"case": case, "command": "planner " + " ".join(args), "exit": code}
        row["wall_s"] = round(wall, 2)
        user = re.search(r"User time \(seconds\): ([\d.]+)", err)
        system = re.search(r"System time \(seconds\): ([\d.]+)", err)
        if user and system:
            row["cpu_s"] = round(float(user.group(1)) + float(system.group(1)), 2)
        row["peak_rss_mb"] = peak_rss_mb(err)
        plan_json = out / "plan.json"
        if plan_json.exists():
            row.update(plan_phases(json.loads(plan_json.read_text()), wall))
        return row


def plan_phases(plan: dict[str, Any], wall_s: float) -> dict[str, Any]:
    """Stations, status, bound and the phase times of a plan.json (see the module docstring)."""
    row: dict[str, Any] = {
        "stations": _whole(plan.get("objective")),
        "status": plan.get("status"),
        "bound": _whole(plan.get("bound")),
        "bound_scope": plan.get("bound_scope"),
        "connected_plane_bound": plan.get("connected_plane_bound"),
        "solver_s": round(float(plan.get("time_s") or 0.0), 2),
    }
    spent = row["solver_s"]
    for line in plan.get("log", []):
        for name, pattern in PHASES:
            m = pattern.search(line)
            if m:
                row[name] = round(float(m.group(1)), 2)
                spent += row[name]
    row["rest_s"] = round(wall_s - spent, 2)
    return row


def _whole(x: Any) -> Any:
    """A count written as a float (6.0) as the whole number it is; anything else as it is."""
    return int(x) if isinstance(x, float) and x.is_integer() else x


def cases(only: list[str] | None, surfaces: bool) -> list[tuple[str, list[str], float, bool]]:
    """(case, planner arguments, timeout in s, bytecode) in the order they run."""
    out: list[tuple[str, list[str], float, bool] | None] = []
    for name in only or INSTANCES:
        site = f"instances/{name}.json"
        out.append((f"{name} default", ["plan", site], 600, True))
        out.append((f"{name} greedy", ["plan", site, "--method", "greedy"], 600, True))
    if not only:
        out.append(("polygon_c no bytecode", ["plan", "instances/polygon_c.json"], 600, False))
    main_job = ["plan", "instances/baalbek_site_doors.json", "--network", "--out", "{OUT}"]
    main_job += ["--export", "dxf,geojson,csv", "--report", "{OUT}", "--field", "{OUT}"]
    out.append(("README main job", main_job, 600, True) if not only else None)
    if surfaces:
        surf = ["plan", "instances/polygon_b.csv", "--surfaces", "walls,floors"]
        out.append(("polygon_b.csv walls,floors", surf, 600, True))
    return [c for c in out if c is not None]


def malformed_row() -> dict[str, Any]:
    """The time to the one-line error of a site file cut short mid-JSON."""
    with tempfile.TemporaryDirectory() as tmp:
        bad = Path(tmp) / "bad.json"
        text = (ROOT / "instances" / "polygon_b.json").read_text()
        bad.write_text(text[: len(text) // 2])
        return run("malformed JSON", ["plan", str(bad)], 60)


def write_md(path: Path, rows: list[dict[str, Any]]) -> None:
    """The table of ``rows`` as Markdown, with how it was measured."""
    cols = ["case", "exit", "wall_s", "cpu_s", "peak_rss_mb", "stations", "status", "bound", "bound_scope"]
    cols += ["coverage_s", "pricing_s", "connected_bound_s", "solver_s", "rest_s", "vs_greedy"]
    lines = [
        "# Bundled plans: wall time and phases",
        "",
        f"`python scripts/bench/bundled.py`, one run, {time.strftime('%Y-%m-%d')}, {os.cpu_count()} cores, load "
        f"average at the start {os.getloadavg()[0]:.2f}; each row one command as a child under `/usr/bin/time -v`. "
        "Phases from the plan's log (the solver alone on 1 thread); `rest` = wall less the phases; `vs_greedy` = "
        "this row's wall time over the greedy's of the same site in the same run. The package's bytecode compiled "
        "first, as an install leaves it, except in the `no bytecode` row.",
        "",
        "| " + " | ".join(cols) + " |",
        "|" + "---|" * len(cols),
    ]
    lines += ["| " + " | ".join(str(r.get(c, "")) for c in cols) + " |" for r in rows]
    path.write_text("\n".join(lines) + "\n")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", default=None, help="bundled instance names (default: all six)")
    ap.add_argument("--skip-surfaces", action="store_true", help="leave out polygon_b.csv --surfaces walls,floors")
    ap.add_argument("--out-dir", default=str(ROOT / "docs" / "benchmarks"))
    a = ap.parse_args()
    compileall.compile_dir(str(ROOT / "planner"), quiet=1)  # as an install leaves it (module docstring)
    rows = [malformed_row()]
    for case, args, timeout_s, bytecode in cases(a.only, not a.skip_surfaces):
        rows.append(run(case, args, timeout_s, bytecode))
        print(" ".join(f"{k}={v}" for k, v in rows[-1].items() if k != "command"), flush=True)
    greedy = {r["case"].split()[0]: r["wall_s"] for r in rows if r["case"].endswith(" greedy")}
    for r in rows:
        if r["case"].endswith(" default") and r["case"].split()[0] in greedy:
            r["vs_greedy"] = round(r["wall_s"] / greedy[r["case"].split()[0]], 2)
    out = Path(a.out_dir)
    (out / "bundled.csv").unlink(missing_ok=True)
    append_csv(out / "bundled.csv", FIELDS, rows)
    write_md(out / "bundled.md", rows)
    print(f"wrote {out / 'bundled.md'}")


if __name__ == "__main__":
    main()
