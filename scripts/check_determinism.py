"""Run a ``planner`` command twice, the second time with every core kept busy, and compare what it wrote.

    python scripts/check_determinism.py [--burners N] [--work DIR] -- planner plan instances/polygon_a.json \
        --out OUT [--field FIELD]

The command's ``--out``, ``--field`` and ``--report`` folders are replaced by one folder per run under ``--work``
(default: a temporary folder). Run 1 runs on the machine as it is; run 2 beside ``--burners`` processes that spin
``while True: pass`` (default: one per core), started before it and ended after it. Compared: plan.json apart
from its time fields (every ``time_s``, ``solve_s``, ``coverage_s``, ``times`` and the seconds in its log lines),
and for a field sheet field.json's visiting order, route length and bound. Prints a small table and exits 1 when
the runs differ, 2 when a run fails.

The planner's default limits count work (CP-SAT deterministic time, rounds, moves, nodes, routing solutions), so
the two runs should write the same plan; a run that the user's wall-clock cap cut (``wall_cap_hit`` in plan.json)
may differ, and the table says so.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
#: the command's output folders, each replaced by a folder of the run
FOLDER_FLAGS = ("--out", "--field", "--report")
#: keys of plan.json (at any depth) that hold times, not results
TIME_KEYS = frozenset({"time_s", "solve_s", "coverage_s", "times"})
#: a duration in a log line: "13.60 s", "0.7 s", "60 s"
_SECONDS = re.compile(r"\b\d+(\.\d+)? s\b")
#: what field.json must repeat: the visiting order, the route and its bound
FIELD_KEYS = ("order", "route_length_m", "lower_bound_m", "search_capped")


def without_times(value: Any) -> Any:
    """``value`` (parsed JSON) with the time fields dropped and the durations in its strings blanked."""
    if isinstance(value, dict):
        return {k: without_times(v) for k, v in value.items() if k not in TIME_KEYS}
    if isinstance(value, list):
        return [without_times(v) for v in value]
    if isinstance(value, str):
        return _SECONDS.sub("# s", value)
    return value


def differences(a: Any, b: Any, path: str = "") -> list[str]:
    """The JSON paths where ``a`` and ``b`` differ (at most one per differing leaf or list length)."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = [f"{path}/{k}: only in run {1 if k in a else 2}" for k in sorted(set(a) ^ set(b))]
        for k in a.keys() & b.keys():
            out += differences(a[k], b[k], f"{path}/{k}")
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{path}: {len(a)} items, then {len(b)}"]
        return [d for k, (x, y) in enumerate(zip(a, b)) for d in differences(x, y, f"{path}[{k}]")]
    return [] if a == b else [f"{path}: {a!r}, then {b!r}"]


def plan_differences(first: dict[str, Any], second: dict[str, Any]) -> list[str]:
    """Where two plan.json files differ, apart from times."""
    return differences(without_times(first), without_times(second))


def field_differences(first: dict[str, Any], second: dict[str, Any]) -> list[str]:
    """Where two field.json files differ in order, route length, bound or cap."""
    return differences({k: first.get(k) for k in FIELD_KEYS}, {k: second.get(k) for k in FIELD_KEYS}, "field")


@contextmanager
def busy(burners: int) -> Iterator[list[subprocess.Popen[bytes]]]:
    """``burners`` processes that keep a core each busy while the body runs; each ended by its own id after."""
    procs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(burners)]
    try:
        time.sleep(0.5)  # let them take the cores before the run starts
        yield procs
    finally:
        for p in procs:
            p.kill()
        for p in procs:
            p.wait()


def with_folders(command: list[str], run_dir: Path) -> tuple[list[str], dict[str, Path]]:
    """``command`` with each output folder (``--out DIR``, ``--out=DIR``...) moved under ``run_dir``."""
    out, folders = [], {}
    args = iter(command)
    for arg in args:
        flag, eq, _ = arg.partition("=")
        if flag in FOLDER_FLAGS:
            if not eq:
                next(args, "")  # the folder given: replaced
            folders[flag] = run_dir / flag.lstrip("-")
            out += [flag, str(folders[flag])]
        else:
            out.append(arg)
    return out, folders


def run_once(command: list[str], run_dir: Path) -> tuple[float, dict[str, Path], subprocess.CompletedProcess[str]]:
    """Run ``command`` with its folders under ``run_dir``; its wall time, folders and process."""
    cmd, folders = with_folders(command, run_dir)
    if cmd and cmd[0] == "planner":  # the planner of this interpreter, whatever PATH says
        cmd = [sys.executable, "-m", "planner", *cmd[1:]]
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, check=False)
    return time.perf_counter() - start, folders, proc


def read(folder: Path | None, name: str) -> dict[str, Any] | None:
    path = folder / name if folder is not None else None
    return json.loads(path.read_text()) if path is not None and path.is_file() else None


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--burners", type=int, default=os.cpu_count() or 2, help="busy processes beside run 2")
    ap.add_argument("--work", metavar="DIR", help="keep the runs' folders here (default: a temporary folder)")
    ap.add_argument("command", nargs=argparse.REMAINDER, help="the command, after --")
    a = ap.parse_args(argv)
    command = a.command[1:] if a.command[:1] == ["--"] else a.command
    if not command:
        ap.error("give the command to run after --")
    work = Path(a.work) if a.work else Path(tempfile.mkdtemp(prefix="determinism-"))
    rows, runs = [], []
    for k, load in enumerate(("as found", f"+{a.burners} busy processes"), 1):
        run_dir = work / f"run{k}"
        shutil.rmtree(run_dir, ignore_errors=True)
        if k == 1:
            wall, folders, proc = run_once(command, run_dir)
        else:
            with busy(a.burners):
                wall, folders, proc = run_once(command, run_dir)
        if proc.returncode != 0:
            print(f"run {k} exited {proc.returncode}: {proc.stderr.strip()[-500:]}")
            return 2
        plan, field = read(folders.get("--out"), "plan.json"), read(folders.get("--field"), "field.json")
        runs.append((plan, field))
        capped = ", ".join(plan.get("wall_cap_hit") or []) if plan else ""
        rows.append((k, load, wall, capped or "-"))
    (plan1, field1), (plan2, field2) = runs
    found = plan_differences(plan1, plan2) if plan1 is not None and plan2 is not None else []
    found += field_differences(field1, field2) if field1 is not None and field2 is not None else []
    print("command: " + " ".join(command))
    print(f"{'run':>3}  {'load':<20} {'wall s':>8}  wall cap hit")
    for k, load, wall, capped in rows:
        print(f"{k:>3}  {load:<20} {wall:>8.1f}  {capped}")
    parts = ["plan.json" if plan1 is not None else None, "field order and route" if field1 is not None else None]
    compared = " and ".join(p for p in parts if p) or "nothing (no --out or --field)"
    print(f"{compared}: {'identical apart from times' if not found else 'DIFFER'}")
    for line in found[:40]:
        print(f"  {line}")
    if field1 is not None and field2 is not None:
        print(f"route {field1['route_length_m']:.1f} m, then {field2['route_length_m']:.1f} m")
    if a.work:
        print(f"runs kept in {work}")
    else:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
