"""Plans for the hours on site: point spacing as a coverage condition and a scan setting per station.

- **Point spacing** (``--max-point-spacing M``): a view covers a wall piece only where the spacing it gives the
  whole piece at the station's setting (:mod:`planner.coverage.spacing`) is at most M.
- **Columns are (station, setting) pairs** (:func:`planner.plan.hours.columns.setting_columns`): a candidate at
  each setting of the instrument's ``[field]`` table, costing set-up + scan time (s).
- **Objectives**: ``stations`` (the default) takes the fewest stations, each able to scan at the finest setting
  (a finer setting sees every piece a coarser one does, so the coarser pairs add nothing to a count), then the
  cheapest settings for them (:func:`assign_settings`, an exact cover of the chosen stations' pairs by scan time);
  ``field-time`` minimises set-up + scan over every pair with the registration and precision rules as for
  stations (:func:`field_time_method`). Registration is judged on what two stations see (the sight coverage), not
  on the spacing: a coarse scan registers as well as a fine one.
"""

from __future__ import annotations

from collections.abc import Hashable
from dataclasses import replace

import numpy as np
import scipy.sparse as sp

from planner.coverage.matrix import CoverageProblem
from planner.coverage.overlap import overlap_adjacency
from planner.coverage.relation import Registration
from planner.instrument.field_table import DEFAULT_FIELD, FieldProperties
from planner.plan.hours.columns import SettingColumns, setting_columns
from planner.plan.methods import MethodInput, MethodOutput
from planner.site.model import Site
from planner.solve.instance import CoverInstance
from planner.solve.milp import solve
from planner.solve.result import SolveResult, Status


def field_properties(site: Site) -> FieldProperties:
    """The ``[field]`` table of the site's instrument (the planner's stated defaults where it has none)."""
    from planner.instrument.models import Scanner, load_instrument

    inst = load_instrument(site.instrument)
    return inst.field_properties if isinstance(inst, Scanner) and inst.field_properties else DEFAULT_FIELD


def hours_method(run: MethodInput, props: FieldProperties) -> MethodOutput:
    """The plan of a run with point spacing or the field-time objective, by its objective (module docstring)."""
    if run.options.objective == "field-time":
        return field_time_method(run, props)
    name = _count_setting(props, run.options.max_point_spacing_m)
    out = field_time_method(run, props.only(name), unit=True)
    if not out.result.selected:
        return out
    settings, timing = assign_settings(run.problem, out.result.selected, props, run.options.max_point_spacing_m, run)
    info = {**out.result.info, "settings": [settings[c] for c in out.result.selected], "field_time": timing}
    how = f"no answer within its limits: all at {name}" if "fallback" in timing else f"{timing['status']}"
    line = f"settings for the chosen stations: set-up + scan {_hours(timing['objective_s'])} ({how})"  # type: ignore[arg-type]
    return replace(out, result=replace(out.result, info=info), log=(*out.log, line))


def _count_setting(props: FieldProperties, max_spacing_m: float | None) -> str:
    """The setting a stations plan is counted at: with a spacing the finest; without one the cheapest (every
    setting sees the same)."""
    if max_spacing_m is not None:
        return props.by_step()[-1][0]
    return min(props.settings, key=props.scan_time_s)


def field_time_method(run: MethodInput, props: FieldProperties, *, unit: bool = False) -> MethodOutput:
    """The plan of least set-up + scan time over (station, setting) pairs (``unit``: of fewest pairs), connected
    under the registration rule as the stations plan is; the result counts stations, its info holds the time, its
    bound and the setting of each station."""
    options, problem = run.options, run.problem
    groups, base = candidate_relation(run.registration, problem)
    # a count: relays at a finer setting cost as much as at the cheapest, so the fewer columns give the same plans
    cols = setting_columns(problem, props, options.max_point_spacing_m, all_relays=not unit)
    timed = _solve_columns(run, cols, groups, base, unit)
    whole = len(cols.candidate)
    if not unit and timed.status != Status.OPTIMAL:  # the model with a relay only where a candidate has no pair
        few = setting_columns(problem, props, options.max_point_spacing_m, all_relays=False)
        other = _solve_columns(run, few, groups, base, unit)
        if other.objective is not None and (timed.objective is None or other.objective < timed.objective - 1e-9):
            # its plan, the whole model's bound (over every pair; the smaller model's holds for its columns only)
            cols, timed = few, _bounded(other, timed.bound)
    chosen = _per_station(cols, timed.selected)
    selected = tuple(sorted(chosen))
    info = {
        **timed.info,
        "objective": "stations" if unit else "field-time",
        "settings": [cols.names[chosen[c]] for c in selected],
        "setting_columns": len(cols.candidate),
    }
    head = f"{len(cols.candidate):,} (station, setting) columns over {len(problem.candidates):,} candidates"
    if len(cols.candidate) != whole:
        head += f" (relays only where no other pair; the bound from the model of all {whole:,} columns)"
    if unit:  # the station count is the objective: the result as the MILP gives it, over the candidates
        result = replace(timed, selected=selected, objective=float(len(selected)) if selected else None, info=info)
        return MethodOutput(result, problem, problem, (f"point spacing: {head}",))
    info["field_time"] = _time_info(timed)
    # the status of what was minimised, set-up + scan over the pool: optimal exactly where its gap is 0 (the count has
    # no bound of its own here, so the headline's word and the time's gap line say the same)
    result = SolveResult(
        method=timed.method,
        status=timed.status,
        selected=selected,
        objective=float(len(selected)) if selected else None,
        time_s=timed.time_s,
        backend=timed.backend,
        info=info,
    )
    log = (
        f"field time: {head}; set-up + scan {_hours(timed.objective)}, bound {_hours(timed.bound)} over the pool "
        f"({timed.status.value})",
    )
    return MethodOutput(result, problem, problem, log)


def _solve_columns(
    run: MethodInput, cols: SettingColumns, groups: tuple[Hashable, ...], base: sp.csr_matrix | None, unit: bool
) -> SolveResult:
    """The MILP over the (station, setting) columns ``cols``: set-up + scan (``unit``: columns) under the run's
    registration rule, judged on what the columns' candidates see (``base``)."""
    problem = run.problem
    lengths = np.asarray(problem.targets.s1_m - problem.targets.s0_m, dtype=float)
    xy = np.array([c.xy for c in problem.candidates], dtype=float).reshape(-1, 2)
    p = sp.csr_matrix(
        (np.ones(len(cols.candidate)), (np.arange(len(cols.candidate)), cols.candidate)),
        shape=(len(cols.candidate), len(problem.candidates)),
    )
    relation = None if base is None else (p @ base.astype(float) @ p.T).tocsr().astype(bool)
    ids = tuple(f"{problem.candidates[c].id}@{cols.names[s]}" for c, s in zip(cols.candidate, cols.setting))
    inst = CoverInstance(
        by_candidate=cols.matrix,
        cost=np.ones(len(cols.cost_s)) if unit else cols.cost_s,
        name=run.site.name,
        groups=tuple(groups[c] for c in cols.candidate),
        target_length_m=lengths,
        xy=xy[cols.candidate],
        candidate_ids=ids,
        relation=relation,
    )
    return solve(inst, run.options.milp)


def _bounded(r: SolveResult, bound: float | None) -> SolveResult:
    """``r`` with ``bound`` (a bound over more columns than r's model had): optimal where its objective meets it."""
    done = bound is not None and r.objective is not None and r.objective <= bound + 1e-6
    return replace(r, bound=bound, status=Status.OPTIMAL if done else Status.FEASIBLE)


def candidate_relation(
    registration: Registration, problem: CoverageProblem
) -> tuple[tuple[Hashable, ...], sp.csr_matrix | None]:
    """The registration group of each candidate and the overlap relation between candidates (None without a rule):
    what both see, at any setting, under the run's rule, with the links through openings and stairs."""
    rule = registration.rule
    groups, links = registration.groups(problem.candidates)
    if rule is None:
        return groups, None
    lengths = np.asarray(problem.targets.s1_m - problem.targets.s0_m, dtype=float)
    xy = np.array([c.xy for c in problem.candidates], dtype=float).reshape(-1, 2)
    base, _ = overlap_adjacency(problem.by_candidate.astype(bool).tocsr(), lengths, rule, groups, xy, links)
    return groups, base.tocsr()


def assign_settings(
    problem: CoverageProblem,
    selected: tuple[int, ...],
    props: FieldProperties,
    max_spacing_m: float | None,
    run: MethodInput,
) -> tuple[dict[int, str], dict[str, object]]:
    """The cheapest setting of each chosen station (candidate index -> setting) that still covers every piece at the
    spacing: an exact cover of the chosen stations' (station, setting) pairs by set-up + scan time, each station at
    one setting at least (``selected`` sorted, as results hold them)."""
    rows = np.asarray(selected, dtype=np.int64)
    cols = setting_columns(problem, props, max_spacing_m, rows)
    # every chosen station stands, so it scans at some setting: a column "station k" each of its pairs covers
    stands = sp.csr_matrix(
        (
            np.ones(len(cols.candidate), dtype=bool),
            (np.arange(len(cols.candidate)), np.searchsorted(rows, cols.candidate)),
        ),
        shape=(len(cols.candidate), len(rows)),
    )
    inst = CoverInstance(
        by_candidate=sp.hstack([cols.matrix, stands], format="csr"), cost=cols.cost_s, name=run.site.name
    )
    timed = solve(inst, replace(run.options.milp, overlap=None))
    if not timed.selected:  # no answer within its limits: each station at the setting it was chosen at (a cover)
        name = _count_setting(props, max_spacing_m)
        info = {**_time_info(timed), "objective_s": len(rows) * (props.setup_time_s + props.scan_time_s(name))}
        return {int(c): name for c in rows}, {**info, "gap": None, "fallback": name}
    chosen = _per_station(cols, timed.selected)
    return {c: cols.names[s] for c, s in chosen.items()}, _time_info(timed)


def _per_station(cols: SettingColumns, picked: tuple[int, ...]) -> dict[int, int]:
    """Candidate -> setting index of the picked columns (the finest where a candidate was picked twice)."""
    out: dict[int, int] = {}
    for j in picked:
        c, s = int(cols.candidate[j]), int(cols.setting[j])
        out[c] = max(out.get(c, s), s)
    return out


def _time_info(r: SolveResult) -> dict[str, object]:
    return {"objective_s": r.objective, "bound_s": r.bound, "gap": r.gap, "status": r.status.value, "scope": "pool"}


def _hours(seconds: float | None) -> str:
    return "-" if seconds is None else f"{seconds / 3600:.2f} h ({seconds:,.0f} s)"
