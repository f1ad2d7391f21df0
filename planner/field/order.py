"""The visiting order of the stations: OR-Tools routing on the walking distances, in two modes.

``shortest``: the shortest open path from the start through every station (or tour, ``closed``). ``registration``: as
short as possible such that every station after the first is related by the overlap rule to one scanned before it, so
the crew registers on site as it goes. Where the plan's registration graph has several parts, the first station of each
part is free (no earlier station can be related to it). The rule is a constraint of the routing model (a rank dimension
and, per station, "some neighbour has a smaller rank, or none of its part has"), honoured by every solution.

Determinism: the search starts from the nearest-neighbour order (which honours the rule) and runs guided local search
for ``solution_limit`` solutions, one thread, with no time limit, so the same input gives the same order on every
machine and under any load; ``time_cap_s`` is a wall-clock cap only where the user sets one (when it is reached the
order may depend on the machine's speed, and :attr:`OrderResult.capped` says so).
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from planner.core.errors import InternalError, UsageError
from planner.core.settings import DEFAULTS

MODES = ("shortest", "registration")
#: guided local search stops after this many solutions (a count: deterministic)
SOLUTION_LIMIT: int = DEFAULTS["field.solution_limit"]
#: no wall-clock cap unless the user sets one
TIME_CAP_S: float | None = None
#: walking distances go to the solvers in millimetres (rounded to the nearest here, down for SCIP's bound)
SCALE = 1000.0


@dataclass(frozen=True)
class OrderResult:
    """An order of the nodes (node 0, the start, first) and its length in m, beside the nearest-neighbour
    order it started from."""

    order: tuple[int, ...]
    length_m: float
    nearest_neighbour: tuple[int, ...]
    nearest_neighbour_m: float
    capped: bool


def order_length(d: NDArray[np.float64], order: Sequence[int], closed: bool = False) -> float:
    """Length of ``order`` on distances ``d`` (back to the start when ``closed``)."""
    legs = sum(float(d[a, b]) for a, b in itertools.pairwise(order))
    return legs + (float(d[order[-1], order[0]]) if closed and len(order) > 1 else 0.0)


def registration_violations(
    order: Sequence[int], neighbours: Sequence[set[int]], parts: Sequence[int], start_is_station: bool
) -> list[int]:
    """The stations of ``order`` that break the registration rule (see the module text)."""
    seen: set[int] = set()
    started: set[int] = set()
    bad = []
    for k, node in enumerate(order):
        if node == 0 and not start_is_station:
            continue
        ok = node == 0 or bool(neighbours[node] & seen) or parts[node] not in started
        if k > 0 and not ok:
            bad.append(node)
        seen.add(node)
        started.add(parts[node])
    return bad


def nearest_neighbour(
    d: NDArray[np.float64], neighbours: Sequence[set[int]] | None, parts: Sequence[int], start_is_station: bool
) -> tuple[int, ...]:
    """Greedy order from node 0: the nearest node next (``neighbours`` given: the nearest that keeps the
    registration rule); ties to the lower index."""
    n = len(d)
    order, seen, started = [0], {0}, {parts[0]} if start_is_station else set()
    while len(order) < n:
        at = order[-1]
        ok = [
            j
            for j in range(n)
            if j not in seen and (neighbours is None or bool(neighbours[j] & seen) or parts[j] not in started)
        ]
        j = min(ok, key=lambda v: (float(d[at, v]), v))
        order.append(j)
        seen.add(j)
        started.add(parts[j])
    return tuple(order)


def solve_order(
    d: NDArray[np.float64],
    mode: str = "shortest",
    neighbours: Sequence[set[int]] | None = None,
    parts: Sequence[int] | None = None,
    start_is_station: bool = True,
    closed: bool = False,
    solution_limit: int = SOLUTION_LIMIT,
    time_cap_s: float | None = TIME_CAP_S,
) -> OrderResult:
    """The visiting order of nodes 0..n-1 from node 0 on walking distances ``d`` (finite, m). ``neighbours[j]``:
    the nodes related to j by the overlap rule; ``parts[j]``: its registration part (node 0, when it is no station,
    in a part of its own). Both are needed in ``registration`` mode."""
    if mode not in MODES:
        raise UsageError(f"unknown order mode (known: {', '.join(MODES)})", field="--mode", value=mode)
    n = len(d)
    parts = list(parts) if parts is not None else list(range(n))
    nbrs = [set(s) for s in neighbours] if neighbours is not None else [set() for _ in range(n)]
    rule = nbrs if mode == "registration" else None
    nn = nearest_neighbour(d, rule, parts, start_is_station)
    nn_m = order_length(d, nn, closed)
    if n <= 2:
        return OrderResult(nn, nn_m, nn, nn_m, False)
    from ortools.constraint_solver import pywrapcp, routing_enums_pb2

    open_path = not closed
    manager = pywrapcp.RoutingIndexManager(n + 1, 1, [0], [n]) if open_path else pywrapcp.RoutingIndexManager(n, 1, 0)
    routing = pywrapcp.RoutingModel(manager)
    cost = np.zeros((n + 1, n + 1), dtype=np.int64)
    cost[:n, :n] = np.rint(d * SCALE).astype(np.int64)
    # a matrix, not a Python callback: the search runs without calling back into Python
    routing.SetArcCostEvaluatorOfAllVehicles(routing.RegisterTransitMatrix(cost.tolist()))
    if rule is not None:
        _add_registration(routing, manager, rule, parts, start_is_station, n)
    params = pywrapcp.DefaultRoutingSearchParameters()
    params.local_search_metaheuristic = routing_enums_pb2.LocalSearchMetaheuristic.GUIDED_LOCAL_SEARCH
    params.solution_limit = solution_limit
    if time_cap_s is not None:  # the user's wall-clock cap; by default the solution limit alone stops the search
        params.time_limit.FromMilliseconds(int(time_cap_s * 1000))
    routing.CloseModelWithParameters(params)
    initial = routing.ReadAssignmentFromRoutes([list(nn[1:])], True)
    if initial is None:
        raise InternalError("the nearest-neighbour order was refused by the routing model")
    t0 = time.perf_counter()
    solution = routing.SolveFromAssignmentWithParameters(initial, params)
    capped = time_cap_s is not None and time.perf_counter() - t0 >= 0.98 * time_cap_s
    if solution is None:
        return OrderResult(nn, nn_m, nn, nn_m, capped)
    order, index = [], routing.Start(0)
    while not routing.IsEnd(index):
        order.append(manager.IndexToNode(index))
        index = solution.Value(routing.NextVar(index))
    best = tuple(order)
    length = order_length(d, best, closed)
    if length > nn_m:  # guided local search keeps the best it saw, but the model's costs are rounded to mm
        best, length = nn, nn_m
    return OrderResult(best, length, nn, nn_m, capped)


def _add_registration(
    routing: Any, manager: Any, nbrs: list[set[int]], parts: list[int], start_is_station: bool, n: int
) -> None:
    """The registration rule as constraints on a rank dimension (see the module text)."""
    one = routing.RegisterUnaryTransitVector([1] * (n + 1))
    routing.AddDimension(one, 0, n + 1, True, "rank")
    rank = routing.GetDimensionOrDie("rank")
    solver = routing.solver()

    def r(node: int) -> Any:
        return rank.CumulVar(manager.NodeToIndex(node))

    members: dict[int, list[int]] = {}
    for j in range(n):
        members.setdefault(parts[j], []).append(j)
    for j in range(1, n):
        terms = [solver.IsLessVar(r(i), r(j)) for i in sorted(nbrs[j])]
        others = [i for i in members[parts[j]] if i != j]
        if not others:
            continue
        holds_start = start_is_station and parts[j] == parts[0]
        if not holds_start:
            terms.append(solver.IsLessVar(r(j), solver.Min([r(i) for i in others])))
        if not terms:
            raise InternalError(f"node {j} has no registration neighbour in its part")
        solver.Add(solver.Sum(terms) >= 1)
