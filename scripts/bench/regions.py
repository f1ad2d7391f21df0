"""The region-candidate stage, before and after a change to the region code, in one run on one machine state.

    python scripts/bench/regions.py [--sites polygon_a baalbek ...] [--before COMMIT] [--repeat 1] [--json FILE]

The stage is what :func:`planner.plan.run.site_candidates` spends on coverage regions: the whole-side candidates
(:func:`planner.candidates.from_regions.whole_side_candidates`, which draws the regions of the pieces it needs) and the
maximal-cell candidates along the medial axes (:func:`planner.candidates.axis.axis_candidates`, which draws the rest).
"before" runs the same two functions with the modules ``planner/coverage/regions.py``,
``planner/candidates/from_regions.py`` and ``planner/candidates/axis.py`` as they were at ``--before`` (read with
``git show``, no checkout), so both columns come from this process and this machine state: quote the ratio, not the
seconds (the machine is shared). Besides the times, each row says whether the two pools are the same (candidate ids
and kinds, and the largest shift of a candidate's position) and the largest area of the symmetric difference between
a piece's region before and after (the regions must agree as point sets, up to rounding).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
import types
from pathlib import Path
from typing import Any

import numpy as np
import shapely

import planner.candidates.axis as axis_now
import planner.candidates.from_regions as from_regions_now
from planner.engine import problem_of

ROOT = Path(__file__).resolve().parents[2]
SITES = ["polygon_a", "polygon_b", "polygon_c", "baalbek", "building27", "baalbek_site"]
#: the commit before the region stage was sped up (only the shadows that meet a region are unioned)
BEFORE = "5c16c98"


def module_at(commit: str, path: str, name: str, patch: dict[str, Any]) -> types.ModuleType:
    """The module at ``path`` as it was at ``commit``, its globals named in ``patch`` replaced (the old regions)."""
    source = subprocess.run(
        ["git", "show", f"{commit}:{path}"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout
    mod = types.ModuleType(name)
    mod.__dict__["__name__"] = name
    sys.modules[name] = mod  # dataclasses look their module up
    exec(compile(source, f"{commit}:{path}", "exec"), mod.__dict__)
    mod.__dict__.update({k: v for k, v in patch.items() if k in mod.__dict__})
    return mod


def before_modules(commit: str) -> tuple[types.ModuleType, types.ModuleType]:
    """(from_regions, axis) of ``commit``, drawing regions with that commit's regions module."""
    regions = module_at(commit, "planner/coverage/regions.py", "before_regions", {})
    names = {k: getattr(regions, k) for k in ("FrameSpace", "coverage_regions", "frame_space")}
    from_regions = module_at(commit, "planner/candidates/from_regions.py", "before_from_regions", names)
    axis = module_at(commit, "planner/candidates/axis.py", "before_axis", names)
    return from_regions, axis


def stage(problem: Any, from_regions: Any, axis: Any) -> tuple[float, list[Any], dict[int, Any]]:
    """Seconds of the region-candidate stage, its candidates and the regions drawn."""
    site, targets, limits, options = problem.site, problem.targets, problem.limits, problem.options
    spaces: dict[str, Any] = {}
    cache: dict[int, Any] = {}
    start = time.perf_counter()
    pool = from_regions.whole_side_candidates(site, targets, limits, spaces, cache)
    pool += axis.axis_candidates(site, targets, limits, spaces, cache, cells=True, step_m=options.target_spacing_m)
    return time.perf_counter() - start, pool, cache


def compare(old: list[Any], new: list[Any], old_regions: dict, new_regions: dict) -> dict[str, Any]:
    """Whether the pools match (ids, kinds, order) and how far apart positions and regions are."""
    same_ids = [(c.id, c.kind) for c in old] == [(c.id, c.kind) for c in new]
    shift = max((float(np.hypot(a.x - b.x, a.y - b.y)) for a, b in zip(old, new)), default=0.0) if same_ids else None
    common = sorted(set(old_regions) & set(new_regions))
    sd = [float(shapely.symmetric_difference(old_regions[t], new_regions[t]).area) for t in common]
    return {
        "same_ids": same_ids,
        "max_shift_m": shift,
        "moved": sum(a.x != b.x or a.y != b.y for a, b in zip(old, new)) if same_ids else None,
        "regions_compared": len(common),
        "max_sym_diff_m2": max(sd, default=0.0),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sites", nargs="+", default=SITES)
    ap.add_argument("--before", default=BEFORE, help="commit of the code to compare with (default %(default)s)")
    ap.add_argument("--repeat", type=int, default=1, help="runs of each, alternating; the fastest counts")
    ap.add_argument("--json", type=Path, help="write the rows here")
    args = ap.parse_args()
    old_fr, old_axis = before_modules(args.before)
    rows = []
    print(
        "| site | pieces | before (s) | after (s) | ratio | pool | same ids | moved | max shift (m) | max sym diff (m2) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name in args.sites:
        problem = problem_of(ROOT / "instances" / f"{name}.json")
        _ = problem.targets
        t_old = t_new = float("inf")
        for _ in range(args.repeat):
            dt, old_pool, old_cache = stage(problem, old_fr, old_axis)
            t_old = min(t_old, dt)
            dt, new_pool, new_cache = stage(problem, from_regions_now, axis_now)
            t_new = min(t_new, dt)
        row = {"site": name, "pieces": len(problem.targets), "before_s": t_old, "after_s": t_new}
        row |= {"ratio": t_old / t_new, "pool": len(new_pool)} | compare(old_pool, new_pool, old_cache, new_cache)
        rows.append(row)
        print(
            f"| {name} | {row['pieces']} | {t_old:.2f} | {t_new:.2f} | {row['ratio']:.1f}x | {row['pool']} | "
            f"{row['same_ids']} | {row['moved']} | {row['max_shift_m']} | {row['max_sym_diff_m2']:.2e} |",
            flush=True,
        )
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
