"""The trade-off between stations and hours on site: the field-time plan beside the plans at one scan setting
and the fewest-stations plan, each timed whole (set-up, scan, walking, targets).

Every plan of the table is made by the same engine on the same pool and verified: a plan "at one setting" is
the fewest stations when every station scans at that setting (the instrument's table cut to it); a setting
whose scans cannot give some piece the spacing is listed as not meeting it. Walking and targets come from the
field sheet's route and proposed targets (:func:`planner.field.run.field_plan`), so the totals are the ones
the sheet would print. The plan kept is the one of least total: the field-time plan unless walking or targets
turn the order round, and then the table says so.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

from planner.core.errors import InfeasibleError, UsageError
from planner.core.text import table
from planner.field.route_search import shorter_walks
from planner.field.run import FieldOptions, FieldPlan, field_plan
from planner.instrument.field_table import FieldProperties
from planner.plan.hours import no_gain_reason, settings_line
from planner.plan.hours.field_time import field_properties
from planner.plan.run import build_problem, plan_single

if TYPE_CHECKING:
    from planner.plan.result import Plan

FIELD_TIME = "field time"
FEWEST = "fewest stations"


@dataclass(frozen=True, kw_only=True)
class Row:
    """One plan of the table; times in seconds (None: not timed); ``note`` says why a row has no plan."""

    label: str
    stations: int | None = None
    setup_s: float | None = None
    scan_s: float | None = None
    walking_s: float | None = None
    targets_s: float | None = None
    sessions: int | None = None
    #: the field sheet's route (m), its lower bound (m) and how the bound was found: the walking part's own
    #: certificate (the MILP's bound covers set-up and scan only)
    route_m: float | None = None
    route_bound_m: float | None = None
    route_bound_method: str = ""
    settings: str = ""
    note: str = ""

    @property
    def total_s(self) -> float | None:
        parts = (self.setup_s, self.scan_s, self.walking_s, self.targets_s)
        return None if any(p is None for p in parts) else float(sum(p for p in parts if p is not None))

    def to_dict(self) -> dict[str, Any]:
        return {k: getattr(self, k) for k in _ROW_KEYS}


#: the keys of a row in plan.json, in order
_ROW_KEYS = "label stations setup_s scan_s walking_s targets_s total_s sessions".split()
_ROW_KEYS += "route_m route_bound_m route_bound_method settings note".split()


@dataclass(frozen=True, kw_only=True)
class Tradeoff:
    rows: tuple[Row, ...]
    kept: str

    def best_single(self) -> Row | None:
        """The single-setting plan of least total time (None where no setting meets the spacing)."""
        timed = [r for r in self.rows if r.label.startswith("one setting") and r.total_s is not None]
        return min(timed, key=lambda r: r.total_s or 0.0) if timed else None

    def row(self, label: str) -> Row:
        return next(r for r in self.rows if r.label == label)

    @property
    def gain_s(self) -> float | None:
        """The best single-setting plan's total less the kept plan's (> 0: the kept plan saves that much)."""
        best, kept = self.best_single(), self.row(self.kept)
        if best is None or best.total_s is None or kept.total_s is None:
            return None
        return best.total_s - kept.total_s

    def lines(self) -> list[str]:
        counted = any(r.sessions is not None for r in self.rows)
        head = ["plan", "stations", "set-up h", "scan h", "walking h", "targets h", "total h"]
        head += ["sessions", "settings"] if counted else ["settings"]
        rows = [
            (
                r.label + (" (kept)" if r.label == self.kept else ""),
                "-" if r.stations is None else r.stations,
                *map(_h, (r.setup_s, r.scan_s, r.walking_s, r.targets_s, r.total_s)),
                *(["-" if r.sessions is None else r.sessions] if counted else []),
                r.settings or r.note,
            )
            for r in self.rows
        ]
        gain = self.gain_s
        best = self.best_single()
        singles = [r for r in self.rows if r.label.startswith("one setting")]
        if gain is not None and best is not None:
            tail = f"gain over the best plan at one setting ({best.label}): {gain / 3600:.2f} h ({gain:,.0f} s)"
        else:
            tail = no_gain_reason(any(r.stations is not None for r in singles))
        kept = self.row(self.kept)
        route = (
            f"route of the kept plan: {kept.route_m:,.1f} m, lower bound {kept.route_bound_m:,.1f} m "
            f"({kept.route_bound_method}), gap {_gap(kept.route_m, kept.route_bound_m):.2%}"
            if kept.route_m is not None and kept.route_bound_m is not None
            else ""
        )
        head_line = "trade-off (times for one crew; walking and targets from the field sheet's route):"
        return [head_line, *table(head, rows), tail, *([route] if route else [])]

    def to_dict(self) -> dict[str, Any]:
        best = self.best_single()
        return {
            "rows": [r.to_dict() for r in self.rows],
            "kept": self.kept,
            "best_single": None if best is None else best.label,
            "gain_s": self.gain_s,
        }


def with_tradeoff(plan: Plan) -> Plan:
    """``plan`` (a field-time plan) with its trade-off table attached, or the plan of the table with the least
    total time where that is another one (a log line says so)."""
    problem = plan.problem
    props = field_properties(plan.site)
    stations_problem = replace(problem, options=replace(problem.options, objective="stations"))
    cov = build_problem(stations_problem)  # the pool every plan of the table and the walk search share
    plans: list[tuple[str, Plan | None, str]] = []
    for name in props.settings_by_step() if problem.options.max_point_spacing_m is not None else props.settings:
        try:
            plans.append((f"one setting: {name}", plan_single(stations_problem, props.only(name), cov), ""))
        except InfeasibleError:
            spaced = problem.options.max_point_spacing_m is not None
            plans.append((f"one setting: {name}", None, "does not meet the spacing" if spaced else "no plan"))
    plans.append((FEWEST, plan_single(stations_problem, props, cov), ""))
    plans.append((FIELD_TIME, plan, ""))
    session = problem.options.session_s
    made = [_row(label, p, props, note, session) for label, p, note in plans]
    rows = [r for r, _ in made]
    fp = made[-1][1]
    if fp is not None:  # the field-time plan's stations moved to shorten its walk (planner.field.route_search)
        found = shorter_walks(plan, fp, props, cov)
        if found is not None:
            moved, n = found
            plans.append((f"{FIELD_TIME}, {n} moved for the walk", moved, ""))
            rows.append(_row(plans[-1][0], moved, props, "", session)[0])
    timed = [k for k, r in enumerate(rows) if r.total_s is not None]
    # the least total; ties keep the later row (the field-time plans come last)
    kept_index = min(timed, key=lambda k: (rows[k].total_s, -k)) if timed else len(rows) - 1
    kept_plan = plans[kept_index][1]
    if kept_plan is None or kept_plan.hours is None or not kept_plan.stations:
        kept_index, kept_plan = len(plans) - 1, plan  # nothing timed: the field-time plan as it came
    assert kept_plan.hours is not None
    trade = Tradeoff(rows=tuple(rows), kept=rows[kept_index].label)
    log = kept_plan.log
    if not plan.stations:
        log = (*log, f"field time: the field-time MILP found no plan ({plan.result.status.value})")
    if not rows[kept_index].label.startswith(FIELD_TIME):
        log = (
            *log,
            f"field time: the plan '{rows[kept_index].label}' has the least total time with walking and targets: kept",
        )
    hours = replace(kept_plan.hours, tradeoff=trade, objective="field-time", timing=_timing(plan, kept_plan))
    return replace(kept_plan, hours=hours, log=log)


def _timing(field: Plan, kept: Plan) -> dict[str, Any]:
    """The field-time MILP's bound on set-up + scan (over every pair of the pool: it holds for any plan of it),
    with the kept plan's set-up + scan and its gap to that bound."""
    assert field.hours is not None and kept.hours is not None
    timing = dict(field.hours.timing)
    bound, total = timing.get("bound_s"), kept.hours.setup_scan_s
    timing["objective_s"] = total
    if isinstance(bound, (int, float)) and total > 0:
        timing["gap"] = max(0.0, (total - bound) / total)
        if timing["gap"] > 0 and timing.get("status") == "optimal":  # optimal was said of the MILP's own plan
            timing["status"] = "feasible"
    return timing


def _row(
    label: str, plan: Plan | None, props: FieldProperties, note: str, session_s: float | None = None
) -> tuple[Row, FieldPlan | None]:
    """The row of ``plan``: set-up and scan from its settings, walking and targets from its field sheet."""
    if plan is None or plan.hours is None:
        return Row(label=label, note=note), None
    if not plan.stations:  # the solver stopped without a plan (its work limit, a wall-clock cap)
        return Row(label=label, note=f"no plan ({plan.result.status.value})"), None
    h = plan.hours
    used = settings_line(h.settings)
    row = Row(label=label, stations=len(plan.stations), setup_s=h.setup_s, scan_s=h.scan_s, settings=used, note=note)
    try:
        fp = field_plan(
            plan.problem.sight, plan.stations, FieldOptions(session_s=session_s), props, settings=h.settings
        )
    except InfeasibleError as err:  # stations in separate frames that no stair joins: no walk joins them
        return replace(row, note=f"walking not timed: {err.message}"), None
    except UsageError as err:  # a setup longer than the session
        return replace(row, note=f"sessions not counted: --session {err.message}"), None
    t = fp.time
    row = replace(row, walking_s=t.walking_s, targets_s=sum(s.targets_s for s in t.setups), route_m=fp.route_length_m)
    sessions = len(t.sessions) if session_s is not None else None
    return replace(row, sessions=sessions, route_bound_m=fp.lower_bound_m, route_bound_method=fp.bound_method), fp


def _gap(route: float, bound: float) -> float:
    return max(0.0, (route - bound) / route) if route > 0 else 0.0


def _h(seconds: float | None) -> str:
    return "-" if seconds is None else f"{seconds / 3600:.2f}"
