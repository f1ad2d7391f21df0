"""The outcome of a solve: a status, the chosen stations, objective, bound and time."""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from enum import Enum
from typing import Any

#: a relative gap at most this is none: the objective meets its bound
GAP_TOL = 1e-6


class Status(str, Enum):
    """How a method ended (an outcome, never an exception)."""

    OPTIMAL = "optimal"  # proven optimal
    FEASIBLE = "feasible"  # a full cover, optimality not proven
    INCOMPLETE = "incomplete"  # a plan that leaves targets uncovered (e.g. the closed form on a sharp corner)
    INFEASIBLE = "infeasible"  # proven: no cover exists (some target seen by no candidate)
    NO_SOLUTION = "no_solution"  # the method stopped without a cover (its work limit, or the user's wall-clock cap)


@dataclass(frozen=True)
class WorkStats:
    """What stopped a MILP (:attr:`planner.solve.milp.MilpOptions.limits`) and the CP-SAT work it ``used``;
    ``wall_cap_hit``: the user's wall-clock cap, not the counted work, ended the search (only then may the plan depend
    on the machine's load)."""

    limit: float | None
    used: float
    node_limit: int | None
    wall_cap_s: float | None
    wall_cap_hit: bool = False
    #: the stall rule's work (:attr:`planner.solve.milp.MilpOptions.stall_work`) and whether it stopped a block
    stall_work: float | None = None
    stalled: bool = False


@dataclass(frozen=True)
class RingStats:
    """The ring bound's part in a MILP: ``blocks`` that got it, those it ``closed_before_search``, the Lagrangian
    ascent's steps, and the blocks whose ascent stopped on its work budget."""

    blocks: int
    closed_before_search: int
    lagrange_steps: int
    work_capped_blocks: int


@dataclass(frozen=True, kw_only=True)
class MilpStats:
    """A MILP's statistics, summed over its blocks (``SolveResult.info`` holds them as :meth:`to_dict`, after the
    presolve's report); ``plain_start``: None where no block took it."""

    rounds: int
    cuts: int
    connected: bool
    local_search_moves: int
    ring_bound: RingStats
    connectivity: str
    plain_start: dict[str, int] | None
    work: WorkStats
    #: the floor probes (:class:`planner.solve.floor.ProbeRecord` as dicts), every block's in its order
    floor: tuple[dict[str, Any], ...] = ()
    #: why the search ended: ``proven``, ``stalled``, ``work_limit``, ``wall_cap`` or ``node_limit`` (a cut loop
    #: whose solves, each stopped on its node limit, left nothing to cut)
    stop: str = "proven"

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        if self.plain_start is None:  # only where a block took it
            del d["plain_start"]
        return d


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
    #: the MILP's statistics, typed (None for the other methods)
    stats: MilpStats | None = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        """An optimal status with its objective above its bound is a contradiction (a ValueError): optimal means the
        gap over the bound's scope is 0."""
        gap = self.gap
        if self.status is Status.OPTIMAL and gap is not None and gap > GAP_TOL:
            raise ValueError(f"{self.method}: status optimal but {gap:.4%} above its bound {self.bound:g}")

    @classmethod
    def timed(
        cls, method: str, status: Status, selected: Sequence[int], objective: float | None, start: float, **more: Any
    ) -> SolveResult:
        """A result timed from ``start`` (a ``time.perf_counter()`` instant); ``more``: the other fields."""
        return cls(
            method=method,
            status=status,
            selected=tuple(selected),
            objective=objective,
            time_s=time.perf_counter() - start,
            **more,
        )

    @classmethod
    def no_plan(
        cls, method: str, status: Status, start: float, backend: str | None = None, info: dict[str, Any] | None = None
    ) -> SolveResult:
        """A result without stations (``status`` infeasible or no solution), timed from ``start``."""
        return cls.timed(method, status, (), None, start, backend=backend, info=info or {})

    @property
    def gap(self) -> float | None:
        """(objective - bound) / objective, or None without both."""
        if self.objective is None or self.bound is None or self.objective == 0:
            return None
        return max(0.0, (self.objective - self.bound) / self.objective)

    @property
    def wall_cap_hit(self) -> bool:
        """A MILP that the user's wall-clock cap ended before its counted work (:class:`WorkStats`)."""
        return self.stats is not None and self.stats.work.wall_cap_hit

    def _repr_html_(self) -> str:
        from planner.core.text import summary_html

        return summary_html(self, f"{self.method} result")

    def summary(self, time_label: str = "", state: str | None = None) -> str:
        """One line: method, status, stations, bound, gap and time (``time_label`` says what the time covers;
        ``state``: the status in words where the count is not what was minimised, else :attr:`state`)."""
        gap = "" if self.gap is None else f", {gap_words(self.status, self.gap)}"
        bound = "" if self.bound is None or math.isnan(self.bound) else f", bound {self.bound:g}"
        obj = "-" if self.objective is None else f"{self.objective:g}"
        label = f" ({time_label})" if time_label else ""
        cap = self.stats.work.wall_cap_s if self.stats is not None else None
        cut = (
            f"; stopped by the wall-clock cap of {cap:g} s (may depend on the load)"
            if cap and self.wall_cap_hit
            else ""
        )
        why = f"; {self.gap_reason}" if self.gap_reason else ""
        return f"{self.method}: {state or self.state}, {obj} stations{bound}{gap}, {self.time_s:.2f} s{label}{cut}{why}"

    @property
    def gap_reason(self) -> str | None:
        """Why the plan is above its bound, in words (a MILP's, from its statistics: :func:`gap_reason`); None where
        there is no gap or nothing to say."""
        if self.stats is None or self.objective is None or self.bound is None or self.status is Status.OPTIMAL:
            return None
        return gap_reason(self.stats, self.objective, self.bound)

    @property
    def scope(self) -> str | None:
        """Where the bound holds: ``plane`` (every position), ``pool`` (the candidate pool), None without one."""
        return None if self.bound is None else str(self.info.get("bound_scope", "pool"))

    @property
    def state(self) -> str:
        """The status in words, an optimum with its scope: "optimal over the plane" / "optimal over the pool"."""
        return state_words(self.status, self.scope)


def state_words(status: Status, scope: str | None) -> str:
    """A result's status in words, the one place they are made (the headline, the gap line and the report take
    them): an optimum with the scope its bound holds over ("optimal over the pool"), else the status itself."""
    return f"optimal over the {scope}" if status is Status.OPTIMAL and scope is not None else status.value


def gap_words(status: Status, gap: float | None, unit: str = "gap") -> str:
    """The gap beside a status, never contradicting it: an optimal result's gap is 0 (its objective meets its bound,
    :meth:`SolveResult.__post_init__`); a result not proven optimal never shows a gap rounded to 0: a gap below 0.1 %
    reads "< 0.1 %", a bound met without the proof (the plan not proven to meet every rule) says so."""
    if gap is None:
        return ""
    if status is Status.OPTIMAL:
        return f"{unit} 0%"
    if gap <= GAP_TOL:
        return f"{unit} 0% but not proven optimal ({status.value})"
    return f"{unit} {gap:.1%}" if gap >= 0.0005 else f"{unit} < 0.1%"


def _many(n: int, word: str) -> str:
    return f"{n:,} {word}" + ("" if n == 1 else "s")


def gap_reason(stats: MilpStats, objective: float, bound: float) -> str | None:
    """Why a MILP's plan (``objective`` stations) is above its ``bound``, in a surveyor's words: what stopped the
    solver, where the bound comes from and what looked for a smaller plan; None without a gap. A work-s is a
    deterministic second of CP-SAT work (a count, the same on any machine and under any load)."""
    floor = math.ceil(bound - GAP_TOL)
    if objective - floor < 0.5:
        return None
    w = stats.work
    work_s = "work-s (seconds of counted solver work, the same on any machine)"
    stop = {
        "stalled": f"the solver stopped after {w.used:.1f} {work_s}: no better plan or bound in its last "
        f"{(w.stall_work or 0):g} work-s",
        "work_limit": f"the solver stopped at its work limit of {(w.limit or 0):g} {work_s}",
        "wall_cap": f"the solver stopped at the wall-clock cap of {(w.wall_cap_s or 0):g} s",
        "node_limit": "the solver stopped when a solve"
        + (f" (within its {w.node_limit:,} nodes)" if w.node_limit is not None else "")
        + " left nothing to cut",
    }.get(stats.stop, "the solver stopped")
    refuted = [p for p in stats.floor if p["outcome"] == "refuted"]
    if refuted:
        last = refuted[-1]
        source = (
            f"bound {bound:g} from the floor probe: no registered plan of {_many(last['level'], 'station')} among "
            f"the {last['candidates']:,} of {last['of']:,} candidates such a plan can use (those in a plain cover "
            "of that size)"
        )
    elif stats.ring_bound.blocks:
        source = f"bound {bound:g} from the ring bound and the cover LP (the fewest stations that see every piece)"
    else:
        cuts_too = " and the registration cuts" if stats.connected else ""
        source = f"bound {bound:g} from the cover LP (the fewest stations that see every piece){cuts_too}"
    rounds = stats.rounds + sum(int(p["rounds"]) for p in stats.floor)
    cuts = stats.cuts + sum(int(p["cuts"]) for p in stats.floor)
    sizes = f"{floor:g}" if objective - floor < 1.5 else f"{floor:g} to {objective - 1:g}"
    found = (
        f"no plan of {sizes} stations found by the connected greedy, {_many(rounds, 'round')} of the cut "
        f"loop ({_many(cuts, 'registration cut')}), its repairs and the local search"
        if stats.connected
        else f"no plan of {sizes} stations found by the greedy start and {_many(rounds, 'solve')}"
    )
    gap = objective - floor
    return f"gap {gap:g} station{'' if gap == 1 else 's'}: {stop}; {source}; {found}"
