"""The best plans known for the bundled sites (``docs/benchmarks/best_known.json``) and a plan's gap to them.

The file lists long runs, one each, with the command that made each plan; ``planner plan`` prints the gap of
its own plan to the entry of the same instance, problem (connected under the overlap rule, or the plain
cover), registration mode and overlap share. Outside a checkout of the repository (no ``docs/``) there is no
file and nothing is printed.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

#: the file in a checkout of the repository
BEST_KNOWN = Path(__file__).resolve().parents[2] / "docs" / "benchmarks" / "best_known.json"


@dataclass(frozen=True)
class Known:
    """One entry of the file: the stations of the best plan known, what it solves, and how it was made."""

    instance: str
    problem: str  # "connected" or "plain cover"
    registration: str | None
    overlap: float
    stations: int
    command: str
    measured: str
    proven_optimal: bool = False

    def line(self, stations: int) -> str:
        """How a plan of ``stations`` compares (the gap is (plan - best) / plan, as the bound's gap)."""
        gap = (stations - self.stations) / stations if stations else math.nan
        proven = ", proven optimal over its pool" if self.proven_optimal else ""
        return (
            f"best known: {self.stations} stations ({self.problem}, registration {self.registration}, overlap "
            f"{self.overlap:g}{proven}; {self.measured}: {self.command}); this plan {stations}, gap to it "
            f"{gap * 100:.1f} %"
        )


def best_known(instance: str, registration: str | None, overlap: float, path: Path = BEST_KNOWN) -> Known | None:
    """The entry for a plan of ``instance`` under ``registration`` and ``overlap`` (0: the plain cover), or None."""
    try:
        rows = json.loads(path.read_text())["plans"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    problem = "connected" if overlap > 0 else "plain cover"
    for row in rows:
        if (
            row.get("instance") == instance
            and row.get("problem") == problem
            and math.isclose(float(row.get("overlap", -1)), overlap)
            and (problem == "plain cover" or row.get("registration") == registration)
        ):
            return Known(
                row["instance"],
                problem,
                row.get("registration"),
                float(row["overlap"]),
                int(row["stations"]),
                str(row.get("command", "")),
                str(row.get("measured", "")),
                bool(row.get("proven_optimal")),
            )
    return None
