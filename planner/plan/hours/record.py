"""What a plan with scan settings says about the hours on site: the objective, each station's
setting, the set-up + scan time with the bound the MILP proves on it, and the spacing verification."""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from planner.plan.hours.verify import SpacingReport
from planner.solve.result import Status, gap_words


def settings_line(settings: Sequence[str]) -> str:
    """How many stations scan at each setting, the most used first: "28 x 3.1 mm @ 10 m, 11 x 6.3 mm @ 10 m"."""
    return ", ".join(f"{n} x {s}" for s, n in sorted(Counter(settings).items(), key=lambda kv: -kv[1]))


def no_gain_reason(single_timed: bool) -> str:
    """Why a trade-off prints no gain: some plan at one setting exists but not every plan was timed whole
    (``single_timed``), or no plan at one setting meets the spacing (the summary's and the report's words)."""
    if single_timed:
        return "gain not computed: the plans are not all timed whole (see their notes)"
    return "no plan at one setting meets the spacing"


@dataclass(frozen=True, kw_only=True)
class Hours:
    """``settings[k]``: the scan setting of the plan's station k. ``timing``: the set-up + scan objective
    (``objective_s``), its bound (``bound_s``, over the pool), gap and status: for ``field-time`` the MILP's over
    every (station, setting) pair; for ``stations`` the settings' over the chosen stations only."""

    objective: str
    max_spacing_m: float | None
    settings: tuple[str, ...]
    setup_s: float
    scan_s: float
    timing: dict[str, Any]
    spacing: SpacingReport | None = None
    tradeoff: Any = None  # planner.field.tradeoff.Tradeoff, attached by the engine

    @property
    def setup_scan_s(self) -> float:
        return self.setup_s + self.scan_s

    def lines(self) -> list[str]:
        """The objective, the settings used, the set-up + scan time with its bound and the spacing check."""
        used = settings_line(self.settings)
        t = self.timing
        bound = t.get("bound_s")
        gap = t.get("gap")
        what = (
            "over every (station, setting) pair of the pool" if self.objective == "field-time" else "for these stations"
        )
        words = gap_words(Status(t.get("status", "feasible")), gap)
        proven = f"; bound {bound / 3600:.2f} h {what}, {words}" if bound is not None and words else ""
        spacing = "none" if self.max_spacing_m is None else f"at most {1e3 * self.max_spacing_m:g} mm"
        lines = [
            f"objective: {self.objective}; point spacing {spacing}; settings: {used}",
            f"set-up + scan: {self.setup_scan_s / 3600:.2f} h (set-up {self.setup_s / 3600:.2f} h, scan "
            f"{self.scan_s / 3600:.2f} h){proven}",
        ]
        if self.spacing is not None:
            lines += self.spacing.lines()
        if self.tradeoff is not None:
            lines += self.tradeoff.lines()
        return lines

    def to_dict(self) -> dict[str, Any]:
        return {
            "objective": self.objective,
            "max_point_spacing_m": self.max_spacing_m,
            "settings": list(self.settings),
            "setup_s": self.setup_s,
            "scan_s": self.scan_s,
            "setup_scan_s": self.setup_scan_s,
            "setup_scan_bound": self.timing,
            "spacing": None if self.spacing is None else self.spacing.to_dict(),
            "tradeoff": None if self.tradeoff is None else self.tradeoff.to_dict(),
        }
