"""Start-up and refusal times of the ``planner`` command, hyperfine-style: N runs each, min / median / max.

Usage::

    python scripts/bench/bench_startup.py [--runs 10] [--huge]

Runs ``python -m planner`` in fresh processes (the import cost is what is measured) and prints a
markdown table; ``--huge`` adds the 10,000 km square (refused by the memory guard). Wall-clock
times on a shared machine: compare rows of one run, not runs of different days.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _time(cmd: list[str], runs: int) -> tuple[list[float], list[float], int]:
    """Wall-clock and CPU (user + system, which a loaded machine inflates less) seconds per run."""
    times, cpu, code = [], [], 0
    for _ in range(runs):
        t0, c0 = time.perf_counter(), _cpu()
        code = subprocess.run(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
        times.append(time.perf_counter() - t0)
        cpu.append(_cpu() - c0)
    return times, cpu, code


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=10)
    ap.add_argument("--huge", action="store_true", help="also time the refusal of the 10,000 km square")
    args = ap.parse_args()
    py = [sys.executable, "-m", "planner"]
    cases = {
        "python -c pass (interpreter alone)": [sys.executable, "-c", "pass"],
        "planner --help": py + ["--help"],
        "planner --version": py + ["--version"],
        "planner validate instances/polygon_b.json": py + ["validate", "instances/polygon_b.json"],
    }
    tmp = Path(tempfile.mkdtemp())
    if args.huge:
        side = 10_000_000
        (tmp / "huge.json").write_text(
            json.dumps(
                {
                    "format": "tls-planner/1",
                    "name": "huge",
                    "zones": [
                        {
                            "id": "sq",
                            "scan_side": "inside",
                            "coordinates": [[0, 0], [side, 0], [side, side], [0, side]],
                            "vertex_heights_m": [10, 10, 10, 10],
                        }
                    ],
                }
            )
        )
        cases["planner plan huge.json (10,000 km square)"] = py + ["plan", str(tmp / "huge.json")]
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print("| command | runs | wall min s | wall median s | wall max s | CPU median s | exit |")
    print("|---|---|---|---|---|---|---|")
    for name, cmd in cases.items():
        t, c, code = _time(cmd, args.runs)
        print(
            f"| `{name}` | {len(t)} | {min(t):.3f} | {statistics.median(t):.3f} | {max(t):.3f} | "
            f"{statistics.median(c):.3f} | {code} |"
        )


if __name__ == "__main__":
    main()
