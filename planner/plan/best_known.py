"""The best plans known for the bundled sites (``docs/benchmarks/best_known.json``) and a plan's gap to them.

The file lists long runs, one each, with the command that made each plan and the pool it was chosen from (its
fingerprint, :mod:`planner.coverage.fingerprint`). An entry is the same problem as a plan when the instance, the
problem (``connected`` under the registration rule, or the ``plain cover`` of a run with no rule), the
registration mode and the overlap share match; ``planner plan`` prints its gap to such an entry only when the
pool's fingerprint matches too. An entry of the same problem on another pool (or on one not recorded: ``"pool":
null``) gets a line saying so, with no gap. A wheel install reads the copy it ships
(:func:`planner.core.resources.data_path`), so it prints what the checkout prints.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from planner.core.resources import data_path

#: the file: the checkout's ``docs/benchmarks/best_known.json``, else the copy an installed wheel ships
BEST_KNOWN = data_path("best_known.json")
#: the two problems an entry may hold for
CONNECTED, PLAIN = "connected", "plain cover"


def problem_kind(has_rule: bool) -> str:
    """``connected`` for a run with a registration rule, ``plain cover`` for one without (``--no-overlap``,
    overlap share 0: ``Problem.rule`` is None)."""
    return CONNECTED if has_rule else PLAIN


@dataclass(frozen=True)
class Known:
    """One entry of the file: the stations of the best plan known, what it solves, how it was made, on which
    pool; ``same_pool``: whether that pool is the plan's (only then is a gap printed)."""

    instance: str
    problem: str  # "connected" or "plain cover"
    registration: str | None
    overlap: float
    stations: int
    command: str
    measured: str
    proven_optimal: bool = False
    pool: dict[str, Any] | None = None
    same_pool: bool = False
    plan_fingerprint: str | None = None

    @property
    def fingerprint(self) -> str | None:
        """The fingerprint of the entry's pool (None: made on an older pool, never matched)."""
        return (self.pool or {}).get("fingerprint")

    def gap(self, stations: int) -> float | None:
        """(plan - best) / plan, as the bound's gap; None on another pool."""
        if not self.same_pool:
            return None
        return (stations - self.stations) / stations if stations else math.nan

    def line(self, stations: int) -> str:
        """How a plan of ``stations`` compares: the gap on the same pool, else that the pools differ."""
        proven = ", proven optimal over its pool" if self.proven_optimal else ""
        head = (
            f"best known: {self.stations} stations ({self.problem}, registration {self.registration or 'none'}, overlap "
            f"{self.overlap:g}{proven}; {self.measured}: {self.command})"
        )
        gap = self.gap(stations)
        if gap is not None:
            return f"{head} on this plan's pool ({self.fingerprint}); this plan {stations}, gap to it {gap * 100:.1f} %"
        theirs = f"fingerprint {self.fingerprint}" if self.fingerprint else "its pool not recorded"
        ours = f"this plan's {self.plan_fingerprint}" if self.plan_fingerprint else "this plan's pool not recorded"
        return f"{head} on another pool ({theirs}; {ours}), no gap printed; this plan {stations}"

    def to_dict(self, stations: int) -> dict[str, Any]:
        """What plan.json ``solver.best_known`` holds."""
        kept = ("stations", "problem", "registration", "overlap", "command", "measured", "pool", "same_pool")
        return {**{k: getattr(self, k) for k in kept}, "gap": self.gap(stations)}


def best_known(
    instance: str,
    problem: str,
    registration: str | None,
    overlap: float,
    fingerprint: str | None,
    path: Path | None = None,
) -> Known | None:
    """The entry for a plan of ``instance`` solving ``problem`` (:func:`problem_kind`) under ``registration`` and
    ``overlap`` (a plain cover: any registration, overlap 0) from the pool of ``fingerprint``; where the file lists
    the problem only on other pools, the best of those with ``same_pool`` False; else None. ``path``: the file
    (default :data:`BEST_KNOWN`, read when called)."""
    try:
        rows = json.loads((path or BEST_KNOWN).read_text())["plans"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if problem == PLAIN:
        overlap = 0.0
    same: list[tuple[dict[str, Any], dict[str, Any] | None]] = []
    other: list[tuple[dict[str, Any], dict[str, Any] | None]] = []
    for row in rows:
        if not (
            isinstance(row, dict)
            and row.get("instance") == instance
            and row.get("problem") == problem
            and math.isclose(float(row.get("overlap", -1)), overlap)
            and (problem == PLAIN or row.get("registration") == registration)
        ):
            continue
        pool = row.get("pool") if isinstance(row.get("pool"), dict) else None
        matched = fingerprint is not None and pool is not None and pool.get("fingerprint") == fingerprint
        (same if matched else other).append((row, pool))
    if not same and not other:
        return None
    row, pool = min(same or other, key=lambda r: int(r[0]["stations"]))
    return Known(
        row["instance"],
        problem,
        row.get("registration"),
        float(row["overlap"]),
        int(row["stations"]),
        str(row.get("command", "")),
        str(row.get("measured", "")),
        bool(row.get("proven_optimal")),
        pool,
        bool(same),
        fingerprint,
    )
