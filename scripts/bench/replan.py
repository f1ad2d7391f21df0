"""Benchmark of ``planner replan`` (issue 58): writes docs/benchmarks/replan.md.

Each site is planned once (``planner plan SITE --out DIR --field DIR``: plan.json, the sheet and replan.npz), then
``planner replan`` runs under ``/usr/bin/time -v`` (wall time, CPU time and peak RSS of the whole command) on the
shipped example (instances/baalbek_site_doors.edits.json), on seeded random edit sets of the other sites, and once
without replan.npz (the pool built again). The load average is recorded beside each row: the machine is shared.
Usage: ``python scripts/bench/replan.py [--work DIR] [--random N] [--out docs/benchmarks/replan.md]``.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ("baalbek_site_doors", ROOT / "instances" / "baalbek_site_doors.edits.json")
RANDOM_SITES = ("house_doors", "building27")


def timed(argv: list[str]) -> dict[str, object]:
    """Run ``argv`` under /usr/bin/time -v: its output, wall and CPU seconds, peak RSS (MB) and the load."""
    load = os.getloadavg()[0]
    p = subprocess.run(["/usr/bin/time", "-v", *argv], capture_output=True, text=True, cwd=ROOT)
    err = p.stderr

    def field(name: str) -> str:
        m = re.search(rf"{re.escape(name)}: (.+)", err)
        return m.group(1).strip() if m else "nan"

    parts = field("Elapsed (wall clock) time (h:mm:ss or m:ss)").split(":")
    wall = sum(float(x) * 60**k for k, x in enumerate(reversed(parts)))
    cpu = float(field("User time (seconds)")) + float(field("System time (seconds)"))
    return {
        "rc": p.returncode,
        "out": p.stdout,
        "err": err,
        "wall_s": wall,
        "cpu_s": cpu,
        "rss_mb": float(field("Maximum resident set size (kbytes)")) / 1024,
        "load": load,
    }


def plan(site: str, work: Path) -> Path:
    """The site planned once into ``work/site`` (kept between runs)."""
    folder = work / site
    if not (folder / "plan.json").is_file() or not (folder / "replan.npz").is_file():
        path = str(ROOT / "instances" / f"{site}.json")
        run = timed(
            [sys.executable, "-m", "planner", "plan", path, "--out", str(folder), "--field", str(folder), "--quiet"]
        )
        if run["rc"] != 0:
            raise SystemExit(f"planning {site} failed:\n{run['err']}")
    return folder / "plan.json"


def random_edits(meta: dict, rng: random.Random) -> dict:
    """Seeded edits of a plan: one to three stations done (in walking order, one of them moved by up to 0.3 m
    now and then), one or two blocked, sometimes a small closed square, the crew at the last done station."""
    stations = sorted(meta["stations"], key=lambda s: s["number"])
    n_done = rng.randint(1, min(3, len(stations) - 1))
    done = [{"station": s["number"], "status": "done"} for s in stations[:n_done]]
    if rng.random() < 0.3:
        s = stations[0]
        done[0] |= {"x": s["x"] + rng.uniform(-0.3, 0.3), "y": s["y"] + rng.uniform(-0.3, 0.3)}
    others = stations[n_done:]
    blocked = [
        {"station": s["number"], "status": "blocked", "radius_m": round(rng.uniform(0.5, 2.0), 2)}
        for s in rng.sample(others, min(len(others), rng.randint(1, 2)))
    ]
    edits = {
        "format": "planner-edits/1",
        "stations": done + blocked,
        "crew": {"station": stations[n_done - 1]["number"]},
    }
    if rng.random() < 0.5:
        s = rng.choice(others)
        x, y = s["x"] + 3.0, s["y"]
        edits["areas"] = [{"kind": "closed", "polygon": [[x, y], [x + 1.5, y], [x + 1.5, y + 1.5], [x, y + 1.5]]}]
    return edits


def row(site: str, what: str, run: dict[str, object]) -> str:
    out = str(run["out"])
    m = re.search(r"re-plan: (\d+) done \+ (\d+) to go = (\d+) stations; rest bound (\w+)", out)
    lost = re.search(r"walls lost \(nothing can see them any more\): ([\d.]+) m", out)
    times = re.search(r"(?:CPU )?times \(s\): (.+)", out)
    done, rest, total, bound = m.groups() if m else ("-",) * 4
    return (
        f"| {site} | {what} | {done} | {rest} | {bound} | {lost.group(1) if lost else '0'} | {run['wall_s']:.2f} | "
        f"{run['cpu_s']:.2f} | {run['rss_mb']:.0f} | {run['load']:.1f} | {times.group(1) if times else run['rc']} |"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--work", default=str(ROOT / "out" / "bench_replan"))
    ap.add_argument("--random", type=int, default=3, help="random edit sets per site (seeded)")
    ap.add_argument("--out", default=str(ROOT / "docs" / "benchmarks" / "replan.md"))
    args = ap.parse_args()
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    rows = []
    site, edits = EXAMPLE
    plan_json = plan(site, work)
    cmd = [sys.executable, "-m", "planner", "replan", str(plan_json), str(edits), "--quiet"]
    for k in range(3):
        rows.append(row(site, f"example, run {k + 1}", timed([*cmd, "--out", str(work / f"re_{site}_{k}")])))
    bare = work / "bare"
    bare.mkdir(exist_ok=True)
    shutil.copy(plan_json, bare / "plan.json")
    no_npz = [sys.executable, "-m", "planner", "replan", str(bare / "plan.json"), str(edits), "--quiet"]
    rows.append(row(site, "example, no replan.npz", timed([*no_npz, "--out", str(work / "re_bare")])))
    rng = random.Random(58)
    for site in RANDOM_SITES:
        plan_json = plan(site, work)
        meta = json.loads(plan_json.read_text())
        for k in range(args.random):
            path = work / f"{site}.edits.{k}.json"
            path.write_text(json.dumps(random_edits(meta, rng)))
            run = timed(
                [
                    sys.executable,
                    "-m",
                    "planner",
                    "replan",
                    str(plan_json),
                    str(path),
                    "--quiet",
                    "--out",
                    str(work / f"re_{site}_{k}"),
                ]
            )
            rows.append(row(site, f"random {k + 1}", run))
    head = [
        "# planner replan: measured",
        "",
        f"`python scripts/bench/replan.py` ({os.cpu_count()} cores, shared; wall and CPU time of the whole command",
        "under `/usr/bin/time -v`, load = the 1-min load average when it started). Docs: docs/field.md,",
        '"Re-planning on site".',
        "",
        "| site | edits | done | to go | bound | lost m | wall s | CPU s | RSS MB | load | steps (CPU s) |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    Path(args.out).write_text("\n".join(head + rows) + "\n")
    print("\n".join(rows))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
