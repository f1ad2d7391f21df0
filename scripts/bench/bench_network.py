"""Time and peak memory of ``planner network`` on plans of the plants and buildings (issue 34, part 5).

For each case a plan is made once (``planner plan SITE --method greedy [--registration site]``, kept in
``--plans``), then ``planner network SITE PLAN --out DIR`` runs as its own process under
``/usr/bin/time -v``. Columns: stations (plan.json), network nodes, edges, observations and unknowns
(network.json: the adjustments summed), wall time and peak RSS. ``--code DIR`` runs another checkout of the
planner (e.g. the dense adjustment before this change) on the same plans, for a "before" column.

    python scripts/bench/bench_network.py [--cases plant_1ha plant_4ha ...] [--plans /tmp/network_plans]
        [--out docs/benchmarks/network.md] [--limit 900] [--code DIR]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HEADER = """# `planner network` at scale

Wall time and peak RSS of one `planner network SITE PLAN` process per case (`/usr/bin/time -v`), on
greedy plans (`planner plan SITE --method greedy`, the plants with `--registration site`; `plant_4ha_zone`
with the default registration). Observations and unknowns: the adjustments of the network (network.json).
"before": the same command on the dense adjustment and pairwise network code this change replaced."""
#: case -> (instance, options of the greedy plan)
CASES = {
    "plant_1ha": ("plant_1ha", ["--registration", "site"]),
    "plant_4ha": ("plant_4ha", ["--registration", "site"]),
    "plant_4ha_zone": ("plant_4ha", []),
    "plant_16ha": ("plant_16ha", ["--registration", "site"]),
    "building27": ("building27", []),
    "baalbek_site_doors": ("baalbek_site_doors", []),
    "house_doors": ("house_doors", []),
}


def plan(case: str, plans: Path) -> Path:
    """The case's greedy plan, made once."""
    instance, options = CASES[case]
    out = plans / case
    if not (out / "plan.json").is_file():
        subprocess.run(
            [
                sys.executable,
                "-m",
                "planner",
                "plan",
                f"instances/{instance}.json",
                "--method",
                "greedy",
                "--quiet",
                "--out",
                str(out),
                *options,
            ],
            cwd=ROOT,
            check=True,
            capture_output=True,
        )
    return out / "plan.json"


def measure(case: str, plan_path: Path, code: Path, limit_s: int) -> dict:
    """Wall time, peak RSS and the network's size of one ``planner network`` run."""
    instance = CASES[case][0]
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        try:
            proc = subprocess.run(
                [
                    "/usr/bin/time",
                    "-v",
                    sys.executable,
                    "-m",
                    "planner",
                    "network",
                    str(ROOT / f"instances/{instance}.json"),
                    str(plan_path),
                    "--out",
                    tmp,
                ],
                cwd=code,
                capture_output=True,
                text=True,
                timeout=limit_s,
                check=False,
            )
        except subprocess.TimeoutExpired:
            return {"wall_s": time.perf_counter() - t0, "peak_gib": math.nan, "note": f"stopped at {limit_s} s"}
        rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", proc.stderr)
        row: dict = {
            "wall_s": time.perf_counter() - t0,
            "peak_gib": int(rss.group(1)) / 2**20 if rss else math.nan,
            "note": "" if proc.returncode == 0 else f"exit {proc.returncode}",
        }
        net = Path(tmp) / "network.json"
        if net.is_file():
            data = json.loads(net.read_text())
            row.update(
                nodes=len(data["nodes"]),
                edges=len(data["edges"]),
                observations=sum(a.get("observations", 0) for a in data["adjustments"]) or None,
                unknowns=sum(a.get("unknowns", 0) for a in data["adjustments"]) or None,
            )
    row["stations"] = len(json.loads(plan_path.read_text())["stations"])
    return row


def table(rows: list[dict]) -> str:
    """The markdown table of the rows."""

    def num(v: object, fmt: str) -> str:
        return "-" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, fmt)

    head = (
        "| case | stations | nodes | edges | observations | unknowns | wall s | peak GiB | before: wall s | "
        "before: peak GiB |\n|---|---|---|---|---|---|---|---|---|---|\n"
    )
    body = "".join(
        f"| {r['case']} | {r['stations']} | {num(r.get('nodes'), ',')} | {num(r.get('edges'), ',')} | "
        f"{num(r.get('observations'), ',')} | {num(r.get('unknowns'), ',')} | {num(r['wall_s'], '.1f')} "
        f"{r['note']}| {num(r['peak_gib'], '.2f')} | {num(r.get('before_wall_s'), '.1f')} {r.get('before_note', '')}| "
        f"{num(r.get('before_peak_gib'), '.2f')} |\n"
        for r in rows
    )
    return head + body


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    ap.add_argument("--plans", type=Path, default=Path(tempfile.gettempdir()) / "network_plans")
    ap.add_argument("--out", type=Path, default=ROOT / "docs/benchmarks/network.md")
    ap.add_argument("--limit", type=int, default=900, help="seconds a run may take (default 900)")
    ap.add_argument("--code", type=Path, default=None, help="also run this checkout of the planner (before)")
    ap.add_argument("--before-cases", nargs="+", default=None, help="the cases --code runs (default: all)")
    ap.add_argument("--json", type=Path, default=None, help="also write the rows as JSON lines")
    ap.add_argument("--from-json", type=Path, default=None, help="only write the table of rows saved by --json")
    args = ap.parse_args(argv)
    rows: list[dict] = []
    given = argv if argv is not None else sys.argv[1:]
    meta: dict[str, object] = {"command": "python scripts/bench/bench_network.py " + " ".join(given)}
    if args.from_json is not None:
        lines = [json.loads(line) for line in args.from_json.read_text().splitlines() if line.strip()]
        meta = next((r["meta"] for r in lines if "meta" in r), meta)
        rows = [r for r in lines if "meta" not in r]
    for case in args.cases if args.from_json is None else []:
        path = plan(case, args.plans)
        row = {"case": case, **measure(case, path, ROOT, args.limit)}
        if args.code is not None and (args.before_cases is None or case in args.before_cases):
            before = measure(case, path, args.code, args.limit)
            row.update(before_wall_s=before["wall_s"], before_peak_gib=before["peak_gib"], before_note=before["note"])
        print(json.dumps(row), flush=True)
        rows.append(row)
    if args.from_json is None:
        meta.update(date=time.strftime("%Y-%m-%d %H:%M"), cores=os.cpu_count(), load=round(os.getloadavg()[0], 1))
    if args.json is not None:
        args.json.write_text(json.dumps({"meta": meta}) + "\n" + "".join(json.dumps(r) + "\n" for r in rows))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    notes = ""
    if args.out.is_file() and "\n## Notes" in args.out.read_text():  # kept from the last run, written by hand
        notes = args.out.read_text()[args.out.read_text().index("\n## Notes") :]
    args.out.write_text(
        f"{HEADER}\n\n`{meta['command']}` ({meta.get('date')}, {meta.get('cores')} cores, load average "
        f"{meta.get('load')} at the end)\n\n{table(rows)}{notes}"
    )
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
