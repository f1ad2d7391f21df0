"""Children of the benchmark scripts, run under ``/usr/bin/time -v`` for their peak resident memory."""

from __future__ import annotations

import csv
import json
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]


def peak_rss_mb(stderr: str) -> int | None:
    """The "Maximum resident set size" that ``/usr/bin/time -v`` wrote, in MB (None when absent)."""
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", stderr)
    return round(int(m.group(1)) / 1024) if m else None


def json_child(script: str, args: list[str], what: str) -> dict:
    """Run ``python script *args --json FILE`` under ``/usr/bin/time -v``; the row it wrote, with
    ``peak_rss_mb``. Exits with the child's standard error when it fails (``what`` names the run)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "row.json"
        cmd = ["/usr/bin/time", "-v", sys.executable, script, *args, "--json", str(out)]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0 or not out.exists():
            raise SystemExit(f"{what} failed:\n{proc.stderr[-3000:]}")
        row = json.loads(out.read_text())
    row["peak_rss_mb"] = peak_rss_mb(proc.stderr)
    return row


def append_csv(path: Path, fields: list[str], rows: list[dict]) -> None:
    """Append ``rows`` (only ``fields``, missing ones empty) to the CSV at ``path``, with a header when new."""
    new = not path.exists()
    with path.open("a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        if new:
            w.writeheader()
        w.writerows({k: r.get(k, "") for k in fields} for r in rows)


class TreeRss:
    """Peak of the summed RSS of a process (``pid``, default this one) and all its descendants, sampled every
    ``every_s``: the planner and its Dask workers together, where ``/usr/bin/time -v`` gives the largest one."""

    def __init__(self, every_s: float = 0.2, pid: int | None = None) -> None:
        import psutil

        self.proc, self.peak, self.every = psutil.Process(pid), 0, every_s
        self._stop = threading.Event()
        self._t = threading.Thread(target=self._run, daemon=True)

    def _run(self) -> None:
        import psutil

        while not self._stop.wait(self.every):
            total = 0
            try:
                family = [self.proc, *self.proc.children(recursive=True)]
            except psutil.Error:  # the process has ended
                continue
            for p in family:
                try:
                    total += p.memory_info().rss
                except psutil.Error:
                    pass
            self.peak = max(self.peak, total)

    def __enter__(self) -> TreeRss:
        self._t.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._t.join()


def usage_so_far(pid: int) -> tuple[float, float]:
    """CPU seconds (user + system) and peak RSS (GiB, VmHWM) so far of the children of ``pid`` (``time``'s
    planner), from /proc; NaN where it cannot be read."""
    try:
        kids = Path(f"/proc/{pid}/task/{pid}/children").read_text().split()
        cpu, peak = 0.0, 0.0
        for kid in kids:
            stat = Path(f"/proc/{kid}/stat").read_text().rsplit(")", 1)[1].split()
            cpu += (int(stat[11]) + int(stat[12])) / os.sysconf("SC_CLK_TCK")  # utime, stime: fields 14, 15
            hwm = re.search(r"VmHWM:\s+(\d+) kB", Path(f"/proc/{kid}/status").read_text())
            peak = max(peak, int(hwm.group(1)) / 2**20 if hwm else math.nan)
        return (cpu, peak) if kids else (math.nan, math.nan)
    except (OSError, ValueError, IndexError):
        return math.nan, math.nan


def timed_plan(argv: list[str], out: Path, limit_s: int) -> tuple[dict[str, Any], dict[str, Any] | None]:
    """``python -m planner plan *argv --out OUT --quiet`` under ``/usr/bin/time -v``, from the checkout; past
    ``limit_s`` its whole process group is stopped (the planner and its Dask workers too, not only ``time``).

    Returns the row (``wall_s``; ``cpu_s``, user + system of the planner and the children it waited for;
    ``peak_gib``, the largest single process; ``tree_gib``, the summed RSS of the planner and all its
    descendants sampled every 0.2 s; ``exit``; ``error``: the planner's last line, or the limit) and the plan.json
    it wrote (None when it did not finish)."""
    t0 = time.perf_counter()
    cmd = ["/usr/bin/time", "-v", sys.executable, "-m", "planner", "plan", *argv, "--out", str(out), "--quiet"]
    proc = subprocess.Popen(
        cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT, start_new_session=True
    )
    stopped: tuple[float, float] | None = None
    with TreeRss(pid=proc.pid) as tree:
        try:
            _, stderr = proc.communicate(timeout=limit_s)
        except subprocess.TimeoutExpired:  # a row that says so (CPU and peak so far), and the next run goes on
            stopped = usage_so_far(proc.pid)
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
    row: dict[str, Any] = {"wall_s": time.perf_counter() - t0, "tree_gib": tree.peak / 2**30}
    if stopped is not None:
        row |= {"cpu_s": stopped[0], "peak_gib": stopped[1], "exit": "stopped"}
        return row | {"error": f"stopped at the {limit_s}-s limit"}, None
    rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", stderr)
    cpu = [re.search(rf"{k} time \(seconds\): ([\d.]+)", stderr) for k in ("User", "System")]
    row |= {
        "cpu_s": sum(float(m.group(1)) for m in cpu if m) if all(cpu) else math.nan,
        "peak_gib": int(rss.group(1)) / 2**20 if rss else math.nan,
        "exit": proc.returncode,
    }
    if proc.returncode == 0:
        return row, json.loads((out / "plan.json").read_text())
    own = [ln for ln in stderr.split("\tCommand being timed")[0].splitlines() if ln.strip()]  # not time's
    row["error"] = next((ln.strip()[:200] for ln in reversed(own) if not ln.startswith("Command exited")), "")
    return row, None
