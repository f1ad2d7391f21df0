"""The entry of docs/benchmarks/best_known.json for a finished plan, printed for copy-paste (issue 44).

    python scripts/checks/best_known_entry.py PLAN_DIR        (or the path of its plan.json)

Reads PLAN_DIR/plan.json and prints one JSON object: instance, problem (``plain cover`` when the run had no
registration rule, else ``connected``), registration, overlap and stations as ``planner plan`` matches them, the
pool it holds for (plan.json ``pool``: fingerprint, candidates, targets, pairs), ``proven_optimal`` where the
plan's status is optimal, the date measured (the file's modification date), a source line (method, status, time,
verification) and the command where plan.json records one (else null: fill it in). Warnings go to stderr: a plan
without a recorded pool (its entry would never match), a connected entry whose plan is not connected, a plan not
verified complete. Exit 1 when there is no plan.json to read.
"""

from __future__ import annotations

import argparse
import datetime
import json
import sys
from pathlib import Path
from typing import Any


def entry(plan: dict[str, Any], measured: str) -> tuple[dict[str, Any], list[str]]:
    """The entry for ``plan`` (plan.json's contents) and the warnings about it."""
    rule = (plan.get("resolved") or {}).get("rule")
    connected = rule is not None
    registration = plan.get("registration") or {}
    verification = plan.get("verification") or {}
    out: dict[str, Any] = {
        "instance": plan.get("instance"),
        "problem": "connected" if connected else "plain cover",
        "registration": (plan.get("resolved") or {}).get("registration") if connected else None,
        # the share the engine matches: the one the registration was checked at, 0 for a plain cover
        "overlap": float(registration.get("overlap", rule["overlap"])) if connected else 0.0,
        "stations": int((plan.get("counts") or {}).get("total", len(plan.get("stations") or []))),
        "pool": plan.get("pool"),
    }
    if plan.get("status") == "optimal":
        out["proven_optimal"] = True
    time_s = plan.get("time_s")
    out["measured"] = measured
    out["source"] = (
        f"method {plan.get('method')}, status {plan.get('status')}"
        + (f", {time_s:.0f} s ({plan.get('time_covers')})" if isinstance(time_s, (int, float)) else "")
        + (f", verified {verification['percent']:.3f} %" if "percent" in verification else "")
    )
    out["command"] = plan.get("command")
    warnings = []
    if not out["pool"]:
        warnings.append("plan.json records no pool: the entry would never match (plan it again on today's main)")
    if connected and registration.get("connected") is False:
        warnings.append("the plan is not connected under its registration rule: not a connected entry")
    if verification.get("complete") is False:
        warnings.append("the plan is not verified complete")
    if out["command"] is None:
        warnings.append("plan.json records no command: fill in 'command' with the one that made the plan")
    return out, warnings


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("plan_dir", type=Path, help="the --out folder of a finished plan, or its plan.json")
    args = parser.parse_args(argv)
    path = args.plan_dir if args.plan_dir.suffix == ".json" else args.plan_dir / "plan.json"
    try:
        plan = json.loads(path.read_text())
    except (OSError, ValueError) as err:
        print(f"best_known_entry: cannot read {path}: {err}", file=sys.stderr)
        return 1
    measured = datetime.date.fromtimestamp(path.stat().st_mtime).isoformat()
    out, warnings = entry(plan, measured)
    for w in warnings:
        print(f"warning: {w}", file=sys.stderr)
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
