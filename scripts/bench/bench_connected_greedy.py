"""The connected greedy (``planner plan SITE --method greedy``, the overlap rule on) before and after issue 34's bundles.

    python scripts/bench/bench_connected_greedy.py [--sites polygon_a plant_16ha ...] [--before REV [--before-files F ...]]
                                             [--md FILE]

Each run is ``python -m planner plan instances/SITE.json --method greedy --quiet`` in a fresh process under
``/usr/bin/time -v`` (wall clock and "Maximum resident set size"): the whole command, coverage build and
verification included; "solve s" is the greedy alone (plan.json ``time_s``). "after" runs this checkout;
"before" runs the ``planner/`` and ``models/`` of git revision REV (``git archive``, read only) the same way,
or, with ``--before-files``, this checkout with only those files as at REV (``git show``); without
``--before`` it is left empty. The MILP reference is the default MILP's count recorded in
tests/expected/bundled_plans.json ("feasible": stopped at its time limit), and 109 for the 16-ha plant (the
single model's count, not rerun). Every plan is checked from its plan.json: registration connected, verification
complete. Prints the Markdown table; ``--md`` also writes it with this protocol.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _timed import peak_rss_mb

ROOT = Path(__file__).resolve().parents[2]
SITES = [
    "polygon_a",
    "polygon_b",
    "polygon_c",
    "baalbek",
    "baalbek_site",
    "baalbek_site_doors",
    "building27",
    "courtyard",
    "house_doors",
    "plant_1ha",
    "plant_4ha",
    "plant_16ha",
]
#: the default MILP on the 16-ha plant (issue 34's figure; too long to rerun here)
MILP_16HA = 109
HEADER = [
    "site",
    "stations before",
    "stations after",
    "MILP reference",
    "solve s before",
    "solve s after",
    "wall s before",
    "wall s after",
    "peak GiB before",
    "peak GiB after",
    "connected, verified",
]


def milp_reference(site: str) -> str:
    rows = json.loads((ROOT / "tests/expected/bundled_plans.json").read_text())["plans"]
    if site == "plant_16ha":
        return f"{MILP_16HA} (single model)"
    row = rows.get(site)
    if row is None:
        return ""
    return f"{row['stations']}" + ("" if row["status"] == "optimal" else f" ({row['status']})")


def run(site: str, tree: Path, out: Path) -> dict:
    """One greedy plan of ``site`` with the package under ``tree``; its count, times, peak and checks."""
    cmd = [
        "/usr/bin/time",
        "-v",
        sys.executable,
        "-m",
        "planner",
        "plan",
        str(ROOT / "instances" / f"{site}.json"),
        "--method",
        "greedy",
        "--quiet",
        "--out",
        str(out),
    ]
    t0 = time.perf_counter()
    proc = subprocess.run(
        cmd,
        cwd=tree,
        capture_output=True,
        text=True,
        check=False,
        env={"PYTHONPATH": str(tree), "PATH": "/usr/bin:/bin"},
    )
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise SystemExit(f"{site} in {tree} exited {proc.returncode}: {proc.stderr.strip()[-2000:]}")
    plan = json.loads((out / "plan.json").read_text())
    m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", proc.stderr)
    if m:
        parts = [float(p) for p in m.group(1).split(":")]
        wall = sum(p * 60**k for k, p in enumerate(reversed(parts)))
    mb = peak_rss_mb(proc.stderr)
    return {
        "stations": plan["counts"]["total"],
        "solve_s": plan["time_s"],
        "wall_s": wall,
        "peak_gib": None if mb is None else mb / 1024,
        "ok": bool(plan["registration"]["connected"] and plan["verification"]["complete"]),
    }


def export(rev: str, into: Path, files: list[str] | None) -> None:
    """``planner/`` and ``models/`` of ``rev`` under ``into``, or of this checkout with only ``files`` as at
    ``rev`` (git archive and git show: the repository is only read)."""
    if not files:
        archive = subprocess.run(
            ["git", "archive", rev, "planner", "models"], cwd=ROOT, capture_output=True, check=True
        )
        subprocess.run(["tar", "-x", "-C", str(into)], input=archive.stdout, check=True)
        return
    for top in ("planner", "models"):
        shutil.copytree(ROOT / top, into / top, ignore=shutil.ignore_patterns("__pycache__"))
    for f in files:
        old = subprocess.run(["git", "show", f"{rev}:{f}"], cwd=ROOT, capture_output=True, check=True).stdout
        (into / f).write_bytes(old)


def cell(row: dict | None, key: str, fmt: str) -> str:
    return "" if row is None or row.get(key) is None else format(row[key], fmt)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sites", nargs="+", default=SITES)
    ap.add_argument("--before", metavar="REV", help="git revision whose planner/ gives the 'before' column")
    ap.add_argument("--before-files", nargs="+", metavar="FILE", help="only these files as at REV, the rest as here")
    ap.add_argument("--md", type=Path, help="also write the table, with the protocol, to this Markdown file")
    args = ap.parse_args()
    lines = ["| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    print(lines[0], flush=True)
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        old = None
        if args.before:
            old = tmp / "before"
            old.mkdir()
            export(args.before, old, args.before_files)
        for site in args.sites:
            before = run(site, old, tmp / f"{site}-before") if old is not None else None
            after = run(site, ROOT, tmp / f"{site}-after")
            ok = after["ok"] and (before is None or before["ok"])
            row = [
                site,
                cell(before, "stations", "d"),
                cell(after, "stations", "d"),
                milp_reference(site),
                cell(before, "solve_s", ".2f"),
                cell(after, "solve_s", ".2f"),
                cell(before, "wall_s", ".1f"),
                cell(after, "wall_s", ".1f"),
                cell(before, "peak_gib", ".2f"),
                cell(after, "peak_gib", ".2f"),
                "yes" if ok else "NO",
            ]
            lines.append("| " + " | ".join(row) + " |")
            print(lines[-1], flush=True)
    if args.md:
        rev = f"`--before {args.before}" + (
            f" --before-files {' '.join(args.before_files)}`" if args.before_files else "`"
        )
        rev = rev if args.before else "no `--before`"
        args.md.write_text(
            f"# The connected greedy before and after the bundles\n\nWritten by "
            f"`python scripts/bench/bench_connected_greedy.py` ({rev}; one run each, this machine). "
            + " ".join(__doc__.split("\n\n")[2].split())
            + "\n\n"
            + "\n".join(lines)
            + "\n"
        )


if __name__ == "__main__":
    main()
