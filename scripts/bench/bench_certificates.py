"""Certificates on every bundled instance (issue 31): the default command beside the greedy, with both bounds.

For each site the plain ``planner plan SITE --out DIR`` (default: connected MILP with the site's overlap, regions
and pricing) and ``planner plan SITE --method greedy`` run as separate processes under ``/usr/bin/time -v``,
one run each, 1 thread. Columns: the plan's stations, whether it is connected, the pool bound (the MILP's,
over the candidate pool), the plane bound (ceil of Farley's bound on the cover LP priced over the coverage
regions: a plain cover, no registration), the connected plane bound (every plan connected under the overlap rule,
stations anywhere: the ring walk over patches, ``zone`` registration only; "-" where not formed), the bound's scope, the default run's wall time and peak RSS, the
greedy's, and their ratio. Sites: the bundled instances (but the 16-ha plant: issue 34's) and the issue's two small cases (a 200 x 8 m
corridor at theta_max 68 deg, an 8 x 4 m room at 45 deg without precision; both overlap 0).

    python scripts/bench/bench_certificates.py [--out docs/benchmarks/certificates.md]
    python scripts/bench/bench_certificates.py --sites baalbek,polygon_a --refine-steps 20

``--sites`` keeps the named rows only; ``--refine-steps N`` adds ``--set plane-refine-steps=N`` to the default run
(the connected cover over refined patches, docs/plane.md), the row named with it.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BUNDLED = [
    "polygon_a",
    "polygon_b",
    "polygon_c",
    "baalbek",
    "building27",
    "courtyard",
    "house_doors",
    "baalbek_site",
    "baalbek_site_doors",
    "plant_1ha",
    "plant_4ha",
]
SMALL = {
    "corridor_200x8": ({"theta_max_deg": 68, "overlap": 0}, [[0, 0], [200, 0], [200, 8], [0, 8]], []),
    "room_8x4_45deg": (
        {"theta_max_deg": 45, "overlap": 0},
        [[0, 0], [8, 0], [8, 4], [0, 4]],
        ["--set", "no-precision"],
    ),
}


def run(args: list[str]) -> tuple[float, float, str]:
    """Wall seconds, peak RSS (GiB) and stdout of ``planner ARGS`` under /usr/bin/time -v."""
    t0 = time.perf_counter()
    proc = subprocess.run(
        ["/usr/bin/time", "-v", sys.executable, "-m", "planner", *args, "--quiet"],
        capture_output=True,
        text=True,
        cwd=ROOT,
        check=False,
    )
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise SystemExit(f"planner {' '.join(args)} exited {proc.returncode}: {proc.stderr[-500:]}")
    rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", proc.stderr)
    return wall, (int(rss.group(1)) / 2**20 if rss else float("nan")), proc.stdout


def row(name: str, site: Path, extra: list[str], tmp: Path, refine: int = 0) -> str:
    out = tmp / name
    more = ["--set", f"plane-refine-steps={refine}"] if refine else []
    wall, rss, _ = run(["plan", str(site), "--out", str(out), *extra, *more])
    g_wall, g_rss, _ = run(["plan", str(site), "--method", "greedy", "--out", str(tmp / f"{name}-greedy"), *extra])
    plan = json.loads((out / "plan.json").read_text())
    greedy = json.loads((tmp / f"{name}-greedy" / "plan.json").read_text())
    conn = "yes" if plan["registration"]["connected"] else "no"
    return (
        f"| {name}{f' (--set plane-refine-steps={refine})' if refine else ''} | {plan['counts']['total']} | {plan['status']} | {conn} | {plan['pool_bound']:g} | "
        f"{plan['plane_bound']} | {_dash(plan.get('connected_plane_bound'))} | {plan['bound_scope']} | {plan['problem']['candidates']:,} | {wall:.1f} | {rss:.2f} | "
        f"{greedy['counts']['total']} | {g_wall:.1f} | {g_rss:.2f} | {wall / g_wall:.1f} |"
    )


def _dash(value: object) -> str:
    return "-" if value is None else f"{value}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out")
    ap.add_argument("--sites", help="comma-separated site names (default: all)")
    ap.add_argument("--refine-steps", type=int, default=0, help="plane-refine-steps for the default run")
    a = ap.parse_args()
    lines = [
        (
            "| site | stations | status | connected | pool bound | plane bound | connected plane bound | scope | candidates | "
            "wall s | peak GiB | greedy stations | greedy wall s | greedy peak GiB | time ratio |"
        ),
        "|---" * 15 + "|",
    ]
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        sites = [(n, ROOT / f"instances/{n}.json", []) for n in BUNDLED]
        for name, (params, xy, extra) in SMALL.items():
            path = tmp / f"{name}.json"
            path.write_text(
                json.dumps(
                    {
                        "format": "tls-planner/1",
                        "name": name,
                        "parameters": params,
                        "zones": [{"id": "R", "scan_side": "inside", "coordinates": xy, "height_m": 3}],
                    }
                )
            )
            sites.append((name, path, extra))
        keep = set(a.sites.split(",")) if a.sites else None
        for name, path, extra in sites:
            if keep is not None and name not in keep:
                continue
            lines.append(row(name, path, extra, tmp, a.refine_steps))
            print(lines[-1], flush=True)
    if a.out:
        Path(a.out).write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
