"""The connected plane bound (the ring walk over patches) alone, timed on the bundled instances, before and after.

``capture`` runs ``planner plan instances/NAME.json`` once per instance with
:func:`planner.bounds.plane_ring.connected_plane_bound` wrapped, and pickles the call's arguments (site, coverage
problem, limits, share, duals, the plan's counts and region cache) to ``out/ring_bound/NAME.pkl``: the MILP before it
is then out of the timing and the counts fixed. ``time`` calls the bound on each captured call ``--repeat`` times and
prints the best wall time, the bound and every zone-side's fields; with ``--rev REV`` it does the same in a child whose
``planner`` package is that git revision's (``git archive``), the old and the new in turn per instance, so that both
see about the same load::

    python scripts/bench/ring_bound.py capture [--instances polygon_a ...]
    python scripts/bench/ring_bound.py time [--rev HEAD~3] [--repeat 2] [--instances ...]
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import subprocess
import sys
import tarfile
import tempfile
import time
from io import BytesIO
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
INSTANCES = ["polygon_a", "polygon_c", "baalbek", "baalbek_site", "building27"]
STORE = ROOT / "out" / "ring_bound"


def capture(names: list[str]) -> None:
    """Pickle the arguments of each instance's connected-plane-bound call (none where the plan makes none)."""
    import planner.plan.methods as methods
    from planner.cli.main import main as cli

    STORE.mkdir(parents=True, exist_ok=True)
    inner = methods.connected_plane_bound
    for name in names:
        seen: list[Any] = []

        def wrapped(*args: Any, _seen: list[Any] = seen, _path: Path = STORE / f"{name}.pkl", **kw: Any) -> Any:
            _seen.append(True)
            with _path.open("wb") as f:  # not the walks done ahead: a process and its pipe
                pickle.dump((args, {k: v for k, v in kw.items() if k != "ahead"}), f)
            return inner(*args, **kw)

        methods.connected_plane_bound = wrapped  # type: ignore[assignment]
        with tempfile.TemporaryDirectory() as tmp:
            cli(["plan", str(ROOT / f"instances/{name}.json"), "--quiet", "--out", tmp])
        print(f"{name}: {'captured' if seen else 'no connected plane bound in this plan'}", flush=True)
    methods.connected_plane_bound = inner  # type: ignore[assignment]


def time_here(names: list[str], repeat: int) -> list[dict[str, Any]]:
    """Best-of-``repeat`` wall time of the bound on each captured call, with its values, in this process."""
    import planner.bounds.ring_walks as ring_module
    from planner.bounds.plane_ring import connected_plane_bound

    regions = ring_module.coverage_regions
    spent = [0.0]

    def timed_regions(*args: Any, **kw: Any) -> Any:  # the coverage regions drawn inside the bound, timed apart
        t0 = time.perf_counter()
        out = regions(*args, **kw)
        spent[0] += time.perf_counter() - t0
        return out

    ring_module.coverage_regions = timed_regions  # type: ignore[assignment]
    rows = []
    for name in names:
        path = STORE / f"{name}.pkl"
        if not path.exists():
            continue
        best, cb, drawn = float("inf"), None, 0.0
        for _ in range(repeat):
            with path.open("rb") as f:
                args, kw = pickle.load(f)  # a fresh region cache each time
            spent[0] = 0.0
            t0 = time.perf_counter()
            cb = connected_plane_bound(*args, **kw)
            if time.perf_counter() - t0 < best:
                best, drawn = time.perf_counter() - t0, spent[0]
        assert cb is not None
        sides = [[s.zone_side, round(s.farley, 9), s.ring, s.patch_m, s.family, str(s.refined)] for s in cb.sides]
        rows.append(
            {"instance": name, "time_s": best, "regions_s": drawn, "bound": cb.bound, "sides": sides, "note": cb.note}
        )
    return rows


def time_at(rev: str, names: list[str], repeat: int) -> list[dict[str, Any]]:
    """:func:`time_here` in a child whose ``planner`` package is git revision ``rev``'s."""
    blob = subprocess.run(["git", "archive", rev, "planner"], cwd=ROOT, capture_output=True, check=True).stdout
    with tempfile.TemporaryDirectory() as tmp:
        with tarfile.open(fileobj=BytesIO(blob)) as tar:
            tar.extractall(tmp, filter="data")
        env = {**os.environ, "PYTHONPATH": tmp}
        out = Path(tmp) / "rows.json"
        cmd = [sys.executable, __file__, "time", "--repeat", str(repeat), "--json", str(out), "--instances", *names]
        subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL)
        return list(json.loads(out.read_text()))


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("mode", choices=["capture", "time"])
    ap.add_argument("--instances", nargs="+", default=INSTANCES)
    ap.add_argument("--rev", help="also time this git revision's planner, in a child")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--json", help="write the rows here (the child's answer)")
    a = ap.parse_args()
    if a.mode == "capture":
        capture(a.instances)
        return
    if a.json:  # the child of time_at
        Path(a.json).write_text(json.dumps(time_here(a.instances, a.repeat)))
        return
    old, new = [], []
    for name in a.instances:  # old and new in turn, best of --repeat each: under the same load, near enough
        olds, news = [], []
        for _ in range(a.repeat):
            olds += time_at(a.rev, [name], 1) if a.rev else []
            news += time_here([name], 1)
        old += [min(olds, key=lambda r: r["time_s"])] if olds else []
        new += [min(news, key=lambda r: r["time_s"])] if news else []
    by_old = {r["instance"]: r for r in old}
    print(
        "| instance | before s | after s | speed-up | of which outer regions before / after s | speed-up without "
        "them | bound before | bound after | sides equal |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for r in new:
        o = by_old.get(r["instance"])
        if o is None:
            print(
                f"| {r['instance']} | - | {r['time_s']:.2f} | - | - / {r['regions_s']:.2f} | - | - | {r['bound']} | - |"
            )
            continue
        same = o["sides"] == r["sides"] and o["note"] == r["note"]
        rest = (o["time_s"] - o["regions_s"]) / max(r["time_s"] - r["regions_s"], 1e-9)
        print(
            f"| {r['instance']} | {o['time_s']:.2f} | {r['time_s']:.2f} | {o['time_s'] / r['time_s']:.1f}x | "
            f"{o['regions_s']:.2f} / {r['regions_s']:.2f} | {rest:.1f}x | {o['bound']} | {r['bound']} | "
            f"{'yes' if same else 'NO'} |"
        )
    for r in new:
        print(r["instance"], json.dumps(r["sides"]))
        if (o := by_old.get(r["instance"])) is not None and o["sides"] != r["sides"]:
            print("  before:", json.dumps(o["sides"]))


if __name__ == "__main__":
    main()
