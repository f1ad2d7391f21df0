"""A search that shortens the walk of a plan with scan settings.

The MILP proves set-up + scan; walking is left to the field sheet's route. This search moves stations along
that route: station j, visited between stations p and n, moves to another candidate m of the pool (at a
setting no dearer, in j's registration group, not in the plan) when

- m, at its setting, covers every piece that j alone covers at the spacing (so the plan still covers every
  piece: pieces others cover stay covered);
- j's registration group stays connected under the overlap relation the MILP planned with (what both see);
- the straight-line detour p -> m -> n is shorter than p -> j -> n by more than :data:`MIN_GAIN_M`.

Moves are tried in visiting order, the best per station, for at most :data:`MOVES` stations (a count: the same
plan under any load). Then the plan is verified afresh (coverage, spacing, registration), the field sheet
re-optimises its route, and the moved plan is kept only where its total time (set-up, scan, walking,
targets) is shorter. Set-up + scan never grows (no move costs more), so the MILP's bound still holds for it.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from planner.coverage.matrix import CoverageProblem
from planner.field.run import FieldPlan
from planner.instrument.field_table import FieldProperties
from planner.plan.hours.columns import SettingColumns, setting_columns
from planner.plan.hours.field_time import candidate_relation
from planner.plan.hours.verify import verify_spacing
from planner.plan.run import build_problem
from planner.plan.verify import verify_stations

if TYPE_CHECKING:
    from planner.plan.result import Plan

#: stations the search tries to move, in visiting order (a count of work)
MOVES = 200
#: a move must shorten the straight-line detour by at least this much (m)
MIN_GAIN_M = 0.5


def shorter_walks(
    plan: Plan, fp: FieldPlan, props: FieldProperties, cov: CoverageProblem | None = None, moves: int = MOVES
) -> tuple[Plan, int] | None:
    """``plan`` with stations moved to shorten its walk (see the module text) and the number moved, or None
    where no move applies or the plan's stations are not columns of its pool. ``cov``: the coverage of the plan's
    pool where the caller has it (None: built here)."""
    h = plan.hours
    if h is None or len(h.settings) != len(plan.stations):
        return None
    problem = plan.problem
    cov = build_problem(problem) if cov is None else cov
    cols = setting_columns(cov, props, problem.options.max_point_spacing_m)
    index = {c.id: k for k, c in enumerate(cov.candidates)}
    column = {(int(c), cols.names[s]): j for j, (c, s) in enumerate(zip(cols.candidate, cols.setting))}
    chosen = []
    for st, setting in zip(plan.stations, h.settings):
        j = column.get((index.get(st.id, -1), setting))
        if j is None:
            return None
        chosen.append(j)
    groups, base = candidate_relation(problem.registration, cov)
    a = cols.matrix.tocsr()
    counts = np.asarray(a[chosen].sum(axis=0)).ravel()
    xy = np.array([c.xy for c in cov.candidates], dtype=float)[cols.candidate]
    group_of = np.array([hash(groups[c]) for c in cols.candidate])
    in_plan = set(int(c) for c in cols.candidate[chosen])
    order = [fp.order[k] for k in range(len(fp.order))]  # indices into plan.stations, visiting order
    moved = 0
    for pos, k in enumerate(order[:moves]):
        j = chosen[k]
        alone = np.flatnonzero((counts == 1) & (np.asarray(a[j].todense()).ravel() > 0))
        ok = np.asarray(a[:, alone].sum(axis=1)).ravel() == len(alone)
        ok &= (cols.cost_s <= cols.cost_s[j]) & (group_of == group_of[j])
        ok &= ~np.isin(cols.candidate, list(in_plan))
        near = [xy[chosen[order[q]]] for q in (pos - 1, pos + 1) if 0 <= q < len(order)]
        if not near or not ok.any():
            continue
        cand = np.flatnonzero(ok)
        here = sum(float(np.hypot(*(xy[j] - p))) for p in near)
        there = sum(np.hypot(xy[cand, 0] - p[0], xy[cand, 1] - p[1]) for p in near)
        for m in cand[np.argsort(there, kind="stable")]:
            if here - float(sum(np.hypot(*(xy[m] - p)) for p in near)) < MIN_GAIN_M:
                break
            trial = [*chosen[:k], int(m), *chosen[k + 1 :]]
            if base is None or _connected(base, cols.candidate, trial, group_of, group_of[j]):
                counts += np.asarray(a[m].todense()).ravel().astype(counts.dtype) - np.asarray(a[j].todense()).ravel()
                in_plan.discard(int(cols.candidate[j]))
                in_plan.add(int(cols.candidate[m]))
                chosen[k] = int(m)
                moved += 1
                break
    if moved == 0:
        return None
    found = _replanned(plan, cov, cols, chosen, props)
    return (found, moved) if _holds(found, plan) else None


def _holds(moved: Plan, plan: Plan) -> bool:
    """Whether the moved plan passes its own checks as ``plan`` does: coverage, the spacing, and no registration
    group in more parts (the moves keep all three by construction; this re-checks the verified plan)."""
    if plan.verification.complete and not moved.verification.complete:
        return False
    spacing = moved.hours.spacing if moved.hours is not None else None
    if spacing is not None and not spacing.complete:
        return False
    before, after = plan.registration or {}, moved.registration or {}
    return all(after.get(g, 1) <= max(before.get(g, 1), 1) for g in after)


def _connected(base: sp.csr_matrix, cand: np.ndarray, chosen: list[int], group_of: np.ndarray, g: int) -> bool:
    """Whether the chosen stations of group ``g`` form one component of the overlap relation."""
    nodes = [int(cand[j]) for j in chosen if group_of[j] == g]
    if len(nodes) <= 1:
        return True
    sub = base[nodes][:, nodes]
    return int(connected_components(sub, directed=False)[0]) == 1


def _replanned(
    plan: Plan, cov: CoverageProblem, cols: SettingColumns, chosen: list[int], props: FieldProperties
) -> Plan:
    """The plan of the moved stations, verified afresh (coverage, spacing, registration)."""
    problem = plan.problem
    o = problem.options
    chosen = sorted(chosen, key=lambda j: int(cols.candidate[j]))  # results hold their stations sorted
    selected = tuple(int(cols.candidate[j]) for j in chosen)
    stations = tuple(cov.candidates[c] for c in selected)
    settings = tuple(cols.names[int(cols.setting[j])] for j in chosen)
    registration, _ = problem.registration.check(cov, selected)
    spacing = None
    if o.max_point_spacing_m is not None:
        spacing = verify_spacing(problem.sight, stations, settings, props, o.max_point_spacing_m, o.verify_spacing_m)
    assert plan.hours is not None
    setup_s = len(settings) * props.setup_time_s
    scan_s = sum(props.scan_time_s(s) for s in settings)
    timing = dict(plan.hours.timing)
    bound = timing.get("bound_s")
    if isinstance(bound, (int, float)) and setup_s + scan_s > 0:  # the MILP's bound holds for any plan
        timing.update(objective_s=setup_s + scan_s, gap=max(0.0, (setup_s + scan_s - bound) / (setup_s + scan_s)))
    hours = replace(plan.hours, settings=settings, setup_s=setup_s, scan_s=scan_s, spacing=spacing, timing=timing)
    info = {**plan.result.info, "settings": list(settings), "field_time": timing}
    result = replace(plan.result, selected=selected, info=info)
    return replace(
        plan,
        result=result,
        stations=stations,
        verification=verify_stations(problem.sight, stations, o.verify_spacing_m),
        registration=registration,
        hours=hours,
    )
