"""The trade-off tables and figures of docs/field-time.md from the plans written by

    planner plan instances/SITE.json --max-point-spacing M --objective field-time --out DIR

Usage: python scripts/studies/field_time.py DIR/plan.json [...]  (prints a markdown table per plan and writes
docs/figures/field_time_<site>_<spacing mm>.png beside it).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from planner.figures.base import png_bytes
from planner.figures.tradeoff_fig import tradeoff_figure

ROOT = Path(__file__).resolve().parents[2]


def _h(v: float | None) -> str:
    return "-" if v is None else f"{v / 3600:.2f}"


def main(paths: list[str]) -> int:
    for path in paths:
        plan = json.loads(Path(path).read_text())
        h = plan["hours"]
        t = h["tradeoff"]
        mm = 1e3 * h["max_point_spacing_m"]
        name = plan["instance"] if isinstance(plan.get("instance"), str) else Path(path).parent.name
        print(f"\n{name}, at most {mm:g} mm, kept: {t['kept']}, gain {_h(t['gain_s'])} h\n")
        print("| plan | stations | set-up h | scan h | walking h | targets h | total h | settings |")
        print("|---|---|---|---|---|---|---|---|")
        for r in t["rows"]:
            label = r["label"] + (" (kept)" if r["label"] == t["kept"] else "")
            cells = [_h(r[k]) for k in ("setup_s", "scan_s", "walking_s", "targets_s", "total_s")]
            st = "-" if r["stations"] is None else str(r["stations"])
            print(f"| {label} | {st} | {' | '.join(cells)} | {r['settings'] or r['note']} |")
        fig = tradeoff_figure(t["rows"], t["kept"], f"{name}: walls at most {mm:g} mm apart")
        out = ROOT / "docs" / "figures" / f"field_time_{name}_{mm:g}mm.png"
        out.write_bytes(png_bytes(fig))
        print(f"\nwrote {out.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
