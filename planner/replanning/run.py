"""A plan repaired on site (:func:`replan`): its edits read, the problem of the rest made from the plan's stored
pool (:mod:`planner.io.replan_data`; the pool is built again where the plan has none, and the result says so),
solved warm (:mod:`planner.replanning.solve_rest`), checked as one registration network with the done stations,
verified at the plan's verification spacing on the edited site, and walked from where the crew stands within the
time left today (:mod:`planner.field`)."""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from planner.field.run import FieldOptions, FieldPlan, field_plan
from planner.io.edits import Edits
from planner.io.replan_data import FILE_NAME, ReplanData, make_replan_data, read_replan_data
from planner.plan.problem import Problem
from planner.plan.result import Plan
from planner.plan.run import build_problem
from planner.plan.verify import VerifyReport, verify_stations
from planner.replanning.changes import Changes, changes_of, reachable_gaps
from planner.replanning.rest import RestProblem, edited_site, rest_problem
from planner.replanning.solve_rest import REPLAN_WORK_S, RestSolution, solve_rest
from planner.replanning.source import PlanSource, edits_of, plan_source
from planner.site.candidate import Candidate


@dataclass(frozen=True, kw_only=True, eq=False)
class Replan:
    """A re-plan: the plan it repairs (``source``), the ``edits``, the ``problem`` of the edited site, the rest's
    problem and solution, the ``stations`` (done first, in the edits' order, then the new ones), the verification
    on the edited site, the registration check, the field sheet of the stations left (None: none left), what
    changed, how the pool was had (``pool_from``) and the CPU time of each step (process time: on a shared machine
    the wall clock tells the load)."""

    source: PlanSource
    edits: Edits
    problem: Problem
    rest: RestProblem
    solution: RestSolution
    stations: tuple[Candidate, ...]
    done: tuple[Candidate, ...]
    verification: VerifyReport
    registration: dict[str, int]
    sheet: FieldPlan | None
    changes: Changes
    pool_from: str
    times: dict[str, float] = field(default_factory=dict)

    @property
    def new(self) -> tuple[Candidate, ...]:
        return self.stations[len(self.done) :]

    @property
    def connected(self) -> bool:
        """Every registration group (accessible area, or zone-side) of the stations, done ones included, is one
        network."""
        return all(n <= 1 for n in self.registration.values())

    @property
    def unexpected_gaps_m(self) -> float:
        """Metres of wall still reachable that the verification finds uncovered (0 for a sound re-plan)."""
        return sum(g.to_m - g.from_m for g in reachable_gaps(self.verification, self.rest))

    def plan(self) -> Plan:
        """The re-plan as a :class:`~planner.plan.result.Plan` (what plan.json is written from)."""
        cov = self.rest.coverage
        size = {"candidates": cov.shape[0], "targets": cov.shape[1], "pairs": int(cov.by_candidate.nnz)}
        return Plan(
            problem=self.problem,
            result=self.solution.result,
            stations=self.stations,
            verification=self.verification,
            problem_size=size,
            log=tuple(self.lines()),
            registration=self.registration,
        )

    def lines(self) -> list[str]:
        """The re-plan in words: edits, pool, rest, bound, walls lost, verification, network, sheet, changes."""
        s, rest = self.solution, self.rest
        removed = ", ".join(f"{n} {r}" for r, n in rest.removed.items() if n)
        bound = (
            "no bound" if s.rest_bound is None else f"bound {s.rest_bound} (scope pool: the pool left after the edits)"
        )
        out = [
            *self.edits.lines(),
            f"pool: {self.pool_from}; candidates removed by the edits: {removed or 'none'}"
            + (f"; {rest.hidden_pairs:,} pairs hidden by obstacles" if rest.hidden_pairs else ""),
            f"re-plan: {len(self.done)} done + {s.rest_count} to go = {len(self.stations)} stations; rest {bound}; "
            f"solver {s.result.status.value}",
            f"warm start: {s.warm}",
            rest.lost.line(),
            self._verified_line(),
            "registration: one network with the done stations"
            if self.connected
            else f"registration: NOT one network ({self.registration})",
        ]
        if self.sheet is not None:
            out.append(self._sheet_line(self.sheet))
        took = ", ".join(f"{k} {v:.2f}" for k, v in self.times.items())
        return out + self.changes.lines() + [f"CPU times (s): {took}"]

    def _verified_line(self) -> str:
        v = self.verification
        left = self.unexpected_gaps_m
        reach = "100 % of the walls still reachable" if left == 0 else f"{left:.2f} m of reachable wall NOT covered"
        return f"verified at {v.spacing_m:g} m on the edited site: {v.percent:.3f} % of all walls; {reach}"

    def _sheet_line(self, fp: FieldPlan) -> str:
        t = fp.time
        today = t.sessions[0] if t.sessions else None
        later = sum(len(x.setups) for x in t.sessions[1:])
        fit = ""
        if self.edits.time_left_h is not None and today is not None:
            fit = f"; today ({self.edits.time_left_h:g} h left): {len(today.setups)} setups" + (
                f", {later} for a next session" if later else ", all fit"
            )
        return f"field sheet: {len(fp.order)} setups from {fp.start_label}, {fp.route_length_m:.0f} m walking, {t.total_s / 3600:.2f} h{fit}"

    def to_dict(self) -> dict[str, Any]:
        """plan.json's ``replan``: what was repaired, with what, and what changed."""
        s = self.solution
        return {
            "from_plan": self.source.path,
            "edits": self.edits.raw,
            "pool_from": self.pool_from,
            "done": [x.id for x in self.done],
            "rest": {"stations": s.rest_count, "bound": s.rest_bound, "bound_scope": "pool"},
            "removed_candidates": self.rest.removed,
            "hidden_pairs": self.rest.hidden_pairs,
            "walls_lost": self.rest.lost.to_dict(),
            "reachable_uncovered_m": round(self.unexpected_gaps_m, 3),
            "one_network": self.connected,
            "start": None if self.sheet is None else {"label": self.sheet.start_label, "xy": list(self.sheet.start_xy)},
            "changes": self.changes.to_dict(),
            "times_s": {k: round(v, 3) for k, v in self.times.items()},
        }


def replan(
    plan: str | Path,
    edits: str | Path | dict[str, Any] | Edits,
    *,
    site: str | Path | None = None,
    work_limit_s: float = REPLAN_WORK_S,
    field_options: FieldOptions | None = None,
) -> Replan:
    """Repair the plan.json at ``plan`` after ``edits`` (an edits file, its data, or :class:`Edits`); ``site``: the
    site file (default: the plan's). Raises InputError (exit 3) for bad edits, InfeasibleError (exit 4) where the
    rest has no plan."""
    times: dict[str, float] = {}
    t0 = time.process_time()
    source = plan_source(plan, site)
    checked = edits_of(source, edits)
    problem = source.options_of(edited_site(source.site, checked))
    times["read"] = time.process_time() - t0
    t0 = time.process_time()
    data, pool_from = _pool(source)
    times["pool"] = time.process_time() - t0
    t0 = time.process_time()
    by_id = {s.id: s for s in source.planned}
    done = tuple(replace(by_id[e.station.id], x=e.xy[0], y=e.xy[1]) for e in checked.done)
    rest = rest_problem(problem, data, checked, done, source.planned)
    times["filter"] = time.process_time() - t0
    t0 = time.process_time()
    solution = solve_rest(rest, problem, (source.meta.get("parameters") or {}).get("milp") or {}, work_limit_s)
    times["solve"] = time.process_time() - t0
    _refuse_none(solution, rest, source)
    t0 = time.process_time()
    done_rows = set(rest.done_rows)
    new = tuple(rest.coverage.candidates[r] for r in solution.selected if r not in done_rows)
    stations = done + new
    registration, _ = problem.registration.check(
        rest.coverage, [*rest.done_rows, *(r for r in solution.selected if r not in done_rows)]
    )
    verification = verify_stations(problem.sight, stations, problem.options.verify_spacing_m)
    times["verify"] = time.process_time() - t0
    t0 = time.process_time()
    sheet = _sheet(problem, new, checked, field_options) if new else None
    times["field"] = time.process_time() - t0
    changes = changes_of(source, checked, done, new, rest)
    return Replan(
        source=source,
        edits=checked,
        problem=problem,
        rest=rest,
        solution=solution,
        stations=stations,
        done=done,
        verification=verification,
        registration=registration,
        sheet=sheet,
        changes=changes,
        pool_from=pool_from,
        times=times,
    )


def _pool(source: PlanSource) -> tuple[ReplanData, str]:
    """The plan's pool from its replan.npz, else built again (said so on standard error by the command)."""
    problem = source.problem
    got = read_replan_data(source.folder / FILE_NAME, problem, problem.targets)
    if isinstance(got, ReplanData):
        return got, f"{FILE_NAME} of the plan ({len(got.coverage.candidates):,} candidates)"
    t0 = time.perf_counter()
    pool = build_problem(problem)
    data = make_replan_data(problem, pool, source.planned)
    took = time.perf_counter() - t0
    return data, f"built again in {took:.1f} s ({got})"


def _refuse_none(solution: RestSolution, rest: RestProblem, source: PlanSource) -> None:
    from planner.core.errors import InfeasibleError

    if not solution.selected:
        status = solution.result.status.value
        raise InfeasibleError(
            f"no plan of the rest ({status}): the done stations and the {rest.coverage.shape[0]:,} candidates left "
            "cannot cover the walls still reachable as one registration network",
            file=source.path,
        )


def _sheet(problem: Problem, new: tuple[Candidate, ...], edits: Edits, options: FieldOptions | None) -> FieldPlan:
    """The field sheet of the stations left, from the crew's position, in sessions of the time left today."""
    options = options or FieldOptions()
    start = options.start
    if edits.crew_xy is not None:
        start = f"{edits.crew_xy[0]!r},{edits.crew_xy[1]!r}"
    session = options.session_s if edits.time_left_h is None else edits.time_left_h * 3600.0
    return field_plan(problem, list(new), replace(options, start=start, session_s=session))
