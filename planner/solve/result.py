"""The outcome of a solve: a status, the chosen stations, objective, bound and time."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from enum import Enum
from typing import Any


class Status(str, Enum):
    """How a method ended (an outcome, never an exception)."""

    OPTIMAL = "optimal"  # proven optimal
    FEASIBLE = "feasible"  # a full cover, optimality not proven
    INCOMPLETE = "incomplete"  # a plan that leaves targets uncovered (e.g. the closed form on a sharp corner)
    INFEASIBLE = "infeasible"  # proven: no cover exists (some target seen by no candidate)
    NO_SOLUTION = "no_solution"  # the method stopped without a cover (its work limit, or the user's wall-clock cap)


@dataclass(frozen=True, kw_only=True)
class SolveResult:
    """Indices of the chosen candidates and what the method can say about them."""

    method: str
    status: Status
    selected: tuple[int, ...]
    objective: float | None
    bound: float | None = None
    time_s: float = 0.0
    backend: str | None = None
    info: dict[str, Any] = field(default_factory=dict)

    @classmethod
    def no_plan(
        cls, method: str, status: Status, start: float, backend: str | None = None, info: dict[str, Any] | None = None
    ) -> SolveResult:
        """A result without stations (``status`` infeasible or no solution), timed from ``start`` (a
        ``time.perf_counter()`` instant)."""
        return cls(
            method=method,
            status=status,
            selected=(),
            objective=None,
            time_s=time.perf_counter() - start,
            backend=backend,
            info=info or {},
        )

    @property
    def gap(self) -> float | None:
        """(objective - bound) / objective, or None without both."""
        if self.objective is None or self.bound is None or self.objective == 0:
            return None
        return max(0.0, (self.objective - self.bound) / self.objective)

    @property
    def wall_cap_hit(self) -> bool:
        """A MILP (``info["work"]``) that the user's wall-clock cap ended before its counted work: only then may its
        answer depend on the machine's load."""
        return bool(self.info.get("work", {}).get("wall_cap_hit", False))

    def _repr_html_(self) -> str:
        from planner.core.text import summary_html

        return summary_html(self, f"{self.method} result")

    def summary(self, time_label: str = "") -> str:
        """One line: method, status, stations, bound, gap and time (``time_label`` says what the time covers)."""
        gap = "" if self.gap is None else f", gap {self.gap:.1%}"
        bound = "" if self.bound is None or math.isnan(self.bound) else f", bound {self.bound:g}"
        obj = "-" if self.objective is None else f"{self.objective:g}"
        label = f" ({time_label})" if time_label else ""
        cap = self.info.get("work", {}).get("wall_cap_s")
        cut = f"; stopped by the wall-clock cap of {cap:g} s (may depend on the load)" if self.wall_cap_hit else ""
        return f"{self.method}: {self.state}, {obj} stations{bound}{gap}, {self.time_s:.2f} s{label}{cut}"

    @property
    def scope(self) -> str | None:
        """Where the bound holds: ``plane`` (every position), ``pool`` (the candidate pool), None without one."""
        if self.bound is None:
            return None
        return str(self.info.get("bound_scope", "pool"))

    @property
    def state(self) -> str:
        """The status in words, an optimum with its scope: "optimal over the plane" / "optimal over the pool"."""
        if self.status is Status.OPTIMAL and self.scope is not None:
            return f"optimal over the {self.scope}"
        return self.status.value
