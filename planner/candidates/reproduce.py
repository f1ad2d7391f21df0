"""Compare the closed form with the dissertation's printed candidate tables (3.2-3.4).

Printed vertex labels do not follow one convention (docs/method.md section 2), so vertex rows are matched by angle: the
computed vertex of the same side whose alpha is closest to the printed one (ties: the printed label, then the closest
HD).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from planner.candidates.closed_form import Limits, ZoneSidePlan, plan_zone_side
from planner.site.model import Zone

#: The print rounds to 3 decimals, but its intermediate values were rounded too: differences up to 0.003 are rounding;
#: anything larger is listed as not reproduced.
ROUNDING = 0.003


@dataclass(frozen=True)
class Comparison:
    table: str
    candidate: int
    quantity: str
    printed: float
    computed: float | None
    where: str

    @property
    def diff(self) -> float | None:
        return None if self.computed is None else self.computed - self.printed

    @property
    def ok(self) -> bool:
        return self.diff is not None and abs(self.diff) <= ROUNDING


def _plans(zone: Zone, limits: Limits) -> dict[str, ZoneSidePlan]:
    return {side.value: plan_zone_side(zone, side, limits) for side in zone.scan_side.sides}


def compare_table(table: str, printed: dict[str, Any], zone: Zone, limits: Limits) -> list[Comparison]:
    """Every printed number of a candidate table next to the computed one."""
    plans = _plans(zone, limits)
    out: list[Comparison] = []
    for row in printed.get("vertex", []):
        plan = plans[row["side"]]
        options = [(i, g) for i, g in enumerate(plan.vertices) if g is not None]
        i, g = min(
            options,
            key=lambda ig: (
                round(abs(ig[1].alpha_deg - row["alpha_deg"]), 2),
                ig[0] + 1 != row["vertex_label"],
                abs(ig[1].hd_m - row["hd_m"]),
            ),
        )
        where = f"{row['side']} vertex {i + 1} (printed label {row['vertex_label']})"
        for q, computed in (("alpha_deg", g.alpha_deg), ("hd_m", g.hd_m), ("gamma_deg", g.gamma_deg)):
            out.append(Comparison(table, row["candidate"], q, row[q], computed, where))
    for row in printed.get("wall", []):
        plan = plans[row["side"]]
        wall = plan.walls[row["wall"] - 1]
        k = sum(
            1
            for r in printed["wall"]
            if r["side"] == row["side"] and r["wall"] == row["wall"] and r["candidate"] < row["candidate"]
        )
        st = wall.stations[k] if k < len(wall.stations) else None
        where = f"{row['side']} wall {row['wall']} candidate {k + 1} of {len(wall.stations)}"
        for q, attr in (("x_m", "x_m"), ("y_m", "y_m"), ("half_base_m", "half_base_m"), ("field_height_m", "height_m")):
            out.append(Comparison(table, row["candidate"], q, row[q], None if st is None else getattr(st, attr), where))
    return out


def generated_counts(zone: Zone, limits: Limits) -> dict[str, int]:
    """Closed-form candidates per side, before the final step."""
    return {side: len(p.candidates) for side, p in _plans(zone, limits).items()}
