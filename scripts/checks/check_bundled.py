"""Replan every bundled instance and compare with tests/expected/bundled_plans.json (issue 33: behaviour unchanged).

    python scripts/checks/check_bundled.py [--sites polygon_a baalbek ...] [--no-greedy]

For each site: ``planner plan SITE`` (the default MILP) and ``planner plan SITE --method greedy`` as separate
processes. A row passes when the MILP plan has the recorded station count (or fewer where the recorded run ended
at its time limit, status ``feasible``), the same status, bounds and bound scope, is connected when it was, and
the greedy plan has at most the recorded count. Exit 1 on any difference, listing each.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
EXPECTED = ROOT / "tests/expected/bundled_plans.json"
#: the two small sites of issue 31, written as instances here: (parameters, outline, extra flags)
SMALL = {
    "corridor_200x8": ({"theta_max_deg": 68, "overlap": 0}, [[0, 0], [200, 0], [200, 8], [0, 8]], []),
    "room_8x4_45deg": (
        {"theta_max_deg": 45, "overlap": 0},
        [[0, 0], [8, 0], [8, 4], [0, 4]],
        ["--set", "no-precision"],
    ),
}


def site_path(name: str, tmp: Path) -> tuple[Path, list[str]]:
    """The site file of a row, and the flags it is planned with."""
    if name not in SMALL:
        return ROOT / "instances" / f"{name}.json", []
    params, xy, extra = SMALL[name]
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
    return path, extra


def plan_json(site: Path, extra: list[str], out: Path) -> dict:
    proc = subprocess.run(
        [sys.executable, "-m", "planner", "plan", str(site), "--out", str(out), "--quiet", *extra],
        capture_output=True,
        text=True,
        cwd=ROOT,
        check=False,
    )
    if proc.returncode != 0:
        raise RuntimeError(f"planner plan {site.name} exited {proc.returncode}: {proc.stderr.strip()[-300:]}")
    return json.loads((out / "plan.json").read_text())


def differences(name: str, want: dict, got: dict, greedy: dict | None) -> list[str]:
    """What differs between the recorded row ``want`` and the plans made now."""
    out = []
    n = got["counts"]["total"]
    if n > want["stations"] or (want["status"] == "optimal" and n != want["stations"]):
        out.append(f"{name}: {n} stations, recorded {want['stations']} ({want['status']})")
    if want["status"] == "optimal":
        for key in ("status", "pool_bound", "plane_bound", "connected_plane_bound", "bound_scope"):
            if got.get(key) != want[key]:
                out.append(f"{name}: {key} {got.get(key)!r}, recorded {want[key]!r}")
    if want["connected"] and not got["registration"]["connected"]:
        out.append(f"{name}: plan not connected, recorded connected")
    if got["verification"]["complete"] is not True:
        out.append(f"{name}: plan does not verify complete")
    if greedy is not None and greedy["counts"]["total"] > want["greedy_stations"]:
        out.append(f"{name}: greedy {greedy['counts']['total']} stations, recorded {want['greedy_stations']}")
    return out


def main() -> int:
    rows = json.loads(EXPECTED.read_text())["plans"]
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sites", nargs="+", choices=sorted(rows), default=sorted(rows))
    ap.add_argument("--no-greedy", action="store_true", help="skip the greedy plans")
    a = ap.parse_args()
    found: list[str] = []
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        for name in a.sites:
            site, extra = site_path(name, tmp)
            got = plan_json(site, extra, tmp / name)
            greedy = None if a.no_greedy else plan_json(site, ["--method", "greedy", *extra], tmp / f"{name}-g")
            diff = differences(name, rows[name], got, greedy)
            print(
                f"{name}: {'ok' if not diff else 'DIFFERS'} ({got['counts']['total']} stations, "
                f"{got['status']}, scope {got['bound_scope']})",
                flush=True,
            )
            found += diff
    print("\n".join(found) if found else "every row as recorded")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
