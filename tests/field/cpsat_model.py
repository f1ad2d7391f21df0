"""The visiting order as a CP-SAT position model: the tests' independent cross-check of the branch-and-cut
(:mod:`planner.field.scip_order`), whose LP relaxation is far stronger. An exact answer (or a certified lower
bound) in both modes.

Nodes 0..n-1, node 0 the start. A Boolean ``x_ij`` per arc and one ``AddCircuit``: a closed tour runs
through the nodes; an open path through the nodes and a dummy end node E (arcs i -> E at cost 0, the arc
E -> 0 fixed), so the path ends anywhere. Positions ``u_i`` (``u_0 = 0``, ``x_ij`` with j != 0 forces
``u_j = u_i + 1``) give the visiting rank. In ``registration`` mode every node j > 0 of a part with other
members must have an overlap neighbour i with ``u_i < u_j``, or be the first of its part (``u_j < u_k`` for
every other member k; not open to a node of the start's part when the start is a station): exactly the rule
of :func:`planner.field.order.registration_violations`. A redundant bound helps the search: a station of
the start's part stands at least as far down the order as its hop distance from the start in the relation.

Costs are the walking distances in cm rounded **down**, so every order costs at least the model's cost, and
the solver's proven objective bound / 100 is a lower bound in metres on the real optimum. The search starts
from a hint (the routing answer). Determinism: one worker, seed 0, and a limit on CP-SAT's *deterministic*
time (a count of work, the same on every machine); a wall-clock cap applies only where the caller sets one, and
:attr:`~planner.field.scip_order.ExactResult.capped` says when it was reached.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence

import networkx as nx
import numpy as np
from numpy.typing import NDArray

from planner.core.errors import InternalError
from planner.field.order import order_length
from planner.field.scip_order import ExactResult

#: distances go to CP-SAT in centimetres, rounded down
SCALE = 100.0
#: CP-SAT's deterministic time limit (about seconds of one core; machine-independent)
WORK_LIMIT = 20.0


def cpsat_order(
    d: NDArray[np.float64],
    registration: bool,
    neighbours: Sequence[set[int]],
    parts: Sequence[int],
    start_is_station: bool = True,
    closed: bool = False,
    hint: Sequence[int] | None = None,
    work_limit: float = WORK_LIMIT,
    wall_cap_s: float | None = None,
) -> ExactResult:
    """Solve the model of the module text on walking distances ``d`` (finite, m); ``hint``: an order from node 0
    (honouring the rule in ``registration`` mode) to start from."""
    from ortools.sat.python import cp_model

    t0 = time.perf_counter()
    n = len(d)
    if n <= 1:
        return ExactResult((0,) if n else (), 0.0, 0.0, True, False, 0.0)
    cost = np.floor(np.asarray(d, dtype=float) * SCALE).astype(np.int64)
    m = cp_model.CpModel()
    u = [m.NewIntVar(0, n - 1, f"u{i}") for i in range(n)]
    m.Add(u[0] == 0)
    x: dict[tuple[int, int], cp_model.IntVar] = {}
    arcs = []
    for i in range(n):
        for j in range(n):
            if i != j and (j != 0 or closed):
                x[i, j] = m.NewBoolVar(f"x{i}_{j}")
                arcs.append((i, j, x[i, j]))
                if j != 0:
                    m.Add(u[j] == u[i] + 1).OnlyEnforceIf(x[i, j])
    end = n
    if not closed:
        for i in range(1, n):
            x[i, end] = m.NewBoolVar(f"x{i}_end")
            arcs.append((i, end, x[i, end]))
        arcs.append((end, 0, m.NewConstant(1)))
    m.AddCircuit(arcs)
    if registration:
        _add_rule(m, u, neighbours, parts, start_is_station)
    m.Minimize(sum(int(cost[i, j]) * v for (i, j), v in x.items() if j != end))
    if hint is not None:
        pos = {node: k for k, node in enumerate(hint)}
        nxt = dict(zip(hint, [*hint[1:], 0 if closed else end]))
        for i, v in enumerate(u):
            m.AddHint(v, pos[i])
        for (i, j), v in x.items():
            m.AddHint(v, int(nxt[i] == j))
    solver = cp_model.CpSolver()
    solver.parameters.num_workers = 1
    solver.parameters.random_seed = 0
    solver.parameters.linearization_level = 2
    solver.parameters.max_deterministic_time = work_limit
    if wall_cap_s is not None:
        solver.parameters.max_time_in_seconds = wall_cap_s
    status = solver.Solve(m)
    wall = time.perf_counter() - t0
    capped = wall_cap_s is not None and wall >= 0.98 * wall_cap_s
    if status == cp_model.INFEASIBLE:
        raise InternalError("the visiting-order model has no solution (the registration rule cannot be kept)")
    bound = max(0.0, float(solver.BestObjectiveBound()) / SCALE)
    if status not in (cp_model.OPTIMAL, cp_model.FEASIBLE):
        return ExactResult(None, math.inf, bound, False, capped, wall)
    order, at = [0], 0
    for _ in range(n - 1):
        at = next(j for j in range(1, n) if (at, j) in x and solver.Value(x[at, j]))
        order.append(at)
    return ExactResult(tuple(order), order_length(d, order, closed), bound, status == cp_model.OPTIMAL, capped, wall)


def _add_rule(
    m,
    u: list,
    nbrs: Sequence[set[int]],
    parts: Sequence[int],  # type: ignore[no-untyped-def]
    start_is_station: bool,
) -> None:
    """The registration rule on the positions (see the module text)."""
    n = len(u)
    members: dict[int, list[int]] = {}
    for j in range(n):
        members.setdefault(parts[j], []).append(j)
    for j in range(1, n):
        others = [i for i in members[parts[j]] if i != j]
        if not others:
            continue
        lits = []
        for i in sorted(nbrs[j]):
            b = m.NewBoolVar(f"r{i}_{j}")
            m.Add(u[i] < u[j]).OnlyEnforceIf(b)
            lits.append(b)
        if not (start_is_station and parts[j] == parts[0]):
            first = m.NewBoolVar(f"f{j}")
            for k in others:
                m.Add(u[j] < u[k]).OnlyEnforceIf(first)
            lits.append(first)
        if not lits:
            raise InternalError(f"node {j} has no registration neighbour in its part")
        m.AddBoolOr(lits)
    if start_is_station:
        g = nx.Graph()
        g.add_nodes_from(range(n))
        g.add_edges_from((i, j) for j in range(n) for i in nbrs[j])
        for j, hops in nx.single_source_shortest_path_length(g, 0).items():
            if j and parts[j] == parts[0]:
                m.Add(u[j] >= hops)
