"""The visiting order by branch-and-cut (SCIP through PySCIPOpt): an exact answer, or a certified lower bound,
in both modes.

Nodes 0..n-1, node 0 the start; a Boolean ``x_ij`` per arc. A closed tour: every node has one arc out and
one in. An open path: node 0 has one arc out and none in, every other node one in and one out, where "out"
may be the arc to the dummy end node E. The rows the search adds (a constraint handler):

* subtour cuts ``x(delta_in(S)) >= 1`` for a set S of stations without the start;
* registration cuts ``x(arcs from outside S into R(S)) >= 1``, where R(S) holds the nodes b of S that have an
  overlap neighbour outside S, or whose whole registration part lies in S (b may be that part's first).
  Valid: the first node of S the order reaches is entered from outside S and must register on an earlier
  node (outside S) or be the first of its part. Exact: an order that breaks the rule at b violates the cut
  of S = {b and every node after it} (the only arc into S enters b, and b is not in R(S)).

Integral points are checked exactly (follow the arcs from 0; the first subtour or rule break gives a cut);
fractional LP points get the cuts of the suffixes of a greedy order read from the LP (from 0, next the node
with the most LP flow in from the nodes taken) and of the components of the LP's support.

Costs are the walking distances in mm rounded **down**, so SCIP's dual bound / 1000 is a lower bound in metres.
Determinism: one thread, seed 0, a limit on branch-and-bound nodes; a wall-clock cap applies only where the user
sets one (:attr:`ExactResult.capped`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from planner.field.order import SCALE, TIME_CAP_S, order_length, registration_violations

#: branch-and-bound nodes SCIP may open (deterministic work limit)
NODE_LIMIT = 2000
#: a fractional cut is added when violated by more than this
MIN_VIOLATION = 1e-3
#: the constraint handler's priorities: it separates every round, enforces and checks after SCIP's own
HANDLER = {"sepapriority": 10, "enfopriority": -10, "chckpriority": -10, "sepafreq": 1, "needscons": False}
#: the handler declares no variable locks, so dual reductions would be unsafe; one LP thread, seed 0
SETTINGS = {
    "misc/allowstrongdualreds": False,
    "misc/allowweakdualreds": False,
    "randomization/randomseedshift": 0,
    "lp/threads": 1,
}


@dataclass(frozen=True)
class ExactResult:
    """The best order found (None: none), its real length in m, the lower bound in m on the optimum of the
    model's mode, whether the bound is proven tight, and whether the wall-clock cap was hit."""

    order: tuple[int, ...] | None
    length_m: float
    bound_m: float
    optimal: bool
    capped: bool
    wall_s: float


def _eligible(nbrs_mat: NDArray[np.bool_], part_mat: NDArray[np.bool_], inside: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """R(S) of the module text for the set ``inside`` (a mask over the n nodes)."""
    out = ~inside
    has_out_nbr = (nbrs_mat & out[None, :]).any(axis=1)
    part_inside = ~(part_mat & out[None, :]).any(axis=1)
    return inside & (has_out_nbr | part_inside)


class _Cuts:
    """The two cut families on an n x n matrix of arc values (arcs into the dummy end left out)."""

    def __init__(
        self, n: int, nbrs: Sequence[set[int]], parts: Sequence[int], start_is_station: bool, registration: bool
    ) -> None:
        self.registration = registration
        self.nbrs = np.zeros((n, n), dtype=bool)
        for j in range(n):
            self.nbrs[j, sorted(nbrs[j])] = True
        p = np.asarray(parts)
        self.part = p[:, None] == p[None, :]
        np.fill_diagonal(self.part, False)
        # a part holding the start (a station) has its first node already: nobody else of it is free
        if start_is_station:
            self.part[p == p[0], 0] = True

    def rows(self, inside: NDArray[np.bool_]) -> list[tuple[NDArray[np.bool_], NDArray[np.bool_]]]:
        """(source mask, target mask) of the cuts of set ``inside``: the arcs from sources to targets sum >= 1."""
        out = [(~inside, inside)]
        if self.registration:
            elig = _eligible(self.nbrs, self.part, inside)
            if elig.sum() < inside.sum():
                out.append((~inside, elig))
        return out

    def violated(self, x: NDArray[np.float64], sets: list[NDArray[np.bool_]], tol: float) -> list:
        """The rows of the proper ``sets`` without the start (each set once) that ``x`` violates by more than tol."""
        proper = {inside.tobytes(): inside for inside in sets if inside.any() and not (inside[0] or inside.all())}
        rows = [row for inside in proper.values() for row in self.rows(inside)]
        return [(src, dst) for src, dst in rows if float(x[np.ix_(src, dst)].sum()) < 1.0 - tol]


def _suffixes(x: NDArray[np.float64]) -> list[NDArray[np.bool_]]:
    """The suffix sets of a greedy order read from arc values ``x`` (from 0, the most inflow from the taken)."""
    n = len(x)
    taken = np.zeros(n, dtype=bool)
    taken[0] = True
    inflow = x[0].copy()
    sets = []
    for _ in range(n - 1):
        k = int(np.argmax(np.where(taken, -np.inf, inflow)))
        sets.append(~taken)
        taken[k] = True
        inflow += x[k]
    return sets


def _components(x: NDArray[np.float64]) -> list[NDArray[np.bool_]]:
    """The components of the support graph of ``x`` (arcs above 1e-6) that do not hold the start."""
    from scipy.sparse.csgraph import connected_components

    _, lab = connected_components(x > 1e-6, directed=True, connection="weak")
    return [lab == c for c in np.unique(lab) if c != lab[0]]


def _walk(x: NDArray[np.float64]) -> list[int]:
    """The nodes an integral point reaches from 0 (arcs above 0.5), in order, until it closes or ends."""
    order, at, seen = [0], 0, {0}
    while True:
        nxt = np.flatnonzero(x[at] > 0.5)
        if nxt.size == 0 or int(nxt[0]) in seen:
            return order
        at = int(nxt[0])
        order.append(at)
        seen.add(at)


def scip_order(
    d: NDArray[np.float64],
    registration: bool,
    neighbours: Sequence[set[int]],
    parts: Sequence[int],
    start_is_station: bool = True,
    closed: bool = False,
    hint: Sequence[int] | None = None,
    node_limit: int = NODE_LIMIT,
    wall_cap_s: float | None = TIME_CAP_S,
) -> ExactResult:
    """Solve the model of the module text on walking distances ``d`` (finite, m); ``hint``: an order from node 0
    (honouring the rule in ``registration`` mode) given to SCIP as its first solution."""
    import pyscipopt

    t0 = time.perf_counter()
    n = len(d)
    if n <= 2:
        order = tuple(range(n))
        length = order_length(d, order, closed) if n else 0.0
        return ExactResult(order, length, length, True, False, 0.0)
    m, x, ends = _model(pyscipopt, np.floor(np.asarray(d, dtype=float) * SCALE), closed)
    cuts = _Cuts(n, neighbours, parts, start_is_station, registration)
    handler = _handler(pyscipopt)(x, cuts, n, (registration, neighbours, parts, start_is_station))
    m.includeConshdlr(handler, "route", "subtours and the registration rule", **HANDLER)
    m.setParams({**SETTINGS, "limits/nodes": node_limit} | ({} if wall_cap_s is None else {"limits/time": wall_cap_s}))
    if hint is not None:
        _start_from(m, x, ends, hint, closed)
    m.optimize()
    return _result(m, x, d, closed, time.perf_counter() - t0)


def _model(scip: Any, cost: NDArray[np.float64], closed: bool) -> tuple[Any, dict[tuple[int, int], Any], dict]:
    """The SCIP model of the module text without its cuts: the arc variables ``x``, the variables ``ends`` of
    the arcs into the dummy end (open path), one arc out of and into every node, 2-cycles forbidden."""
    n = len(cost)
    m = scip.Model("order")
    m.hideOutput()
    arcs = [(i, j) for i in range(n) for j in range(n) if i != j and (j != 0 or closed)]
    x = {(i, j): m.addVar(f"x{i}_{j}", vtype="B", obj=float(cost[i, j])) for i, j in arcs}
    ends = {i: m.addVar(f"e{i}", vtype="B", obj=0.0) for i in range(1, n)} if not closed else {}
    q = scip.quicksum
    for i in range(n):
        m.addCons(q(x[i, j] for j in range(n) if (i, j) in x) + ends.get(i, 0.0) == 1)
    for j in range(n):
        if j or closed:
            m.addCons(q(x[i, j] for i in range(n) if (i, j) in x) == 1)
    if ends:
        m.addCons(q(ends.values()) == 1)
    for i in range(n):
        for j in range(i + 1, n):
            if (i, j) in x and (j, i) in x:
                m.addCons(x[i, j] + x[j, i] <= 1)
    m.setObjIntegral()
    return m, x, ends


def _start_from(m: Any, x: dict[tuple[int, int], Any], ends: dict, hint: Sequence[int], closed: bool) -> None:
    """Give SCIP the order ``hint`` as its first solution."""
    sol = m.createSol()
    nxt = dict(zip(hint, [*hint[1:], 0 if closed else -1]))
    for (i, j), v in x.items():
        m.setSolVal(sol, v, float(nxt[i] == j))
    for i, v in ends.items():
        m.setSolVal(sol, v, float(nxt[i] == -1))
    m.addSol(sol)


def _result(m: Any, x: dict[tuple[int, int], Any], d: NDArray[np.float64], closed: bool, wall: float) -> ExactResult:
    """The solved model's best order (None where it has none), its length, the dual bound and the status."""
    n = len(d)
    capped = m.getStatus() == "timelimit"
    dual = m.getDualbound()
    bound = max(0.0, float(dual) / SCALE) if math.isfinite(dual) and abs(dual) < 1e19 else 0.0
    order = tuple(_walk(_arc_values(m, x, n, m.getBestSol()))) if m.getNSols() else ()
    if len(order) != n:
        return ExactResult(None, math.inf, bound, False, capped, wall)
    return ExactResult(order, order_length(d, order, closed), bound, m.getStatus() == "optimal", capped, wall)


def _arc_values(m: Any, x: dict[tuple[int, int], Any], n: int, sol: Any) -> NDArray[np.float64]:
    """The arc values of solution ``sol`` (None: the current LP point) as an n x n matrix."""
    v = np.zeros((n, n))
    for (i, j), var in x.items():
        v[i, j] = m.getSolVal(sol, var)
    return v


def _broken(xv: NDArray[np.float64], rule: tuple) -> NDArray[np.bool_] | None:
    """The set S of an integral point's first subtour or rule break (None: a valid order); ``rule``:
    (registration, neighbours, parts, start_is_station)."""
    n = len(xv)
    order = _walk(xv)
    if len(order) < n:
        inside = np.ones(n, dtype=bool)
        inside[order] = False
        return inside
    registration, nbrs, parts, start_is_station = rule
    bad = registration_violations(order, nbrs, parts, start_is_station) if registration else []
    if not bad:
        return None
    inside = np.zeros(n, dtype=bool)
    inside[order[order.index(bad[0]) :]] = True
    return inside


def _add_rows(scip: Any, model: Any, x: dict[tuple[int, int], Any], rows: list, cut: bool) -> int:
    """Add the rows ``(source mask, target mask)``: as cuts to the LP (``cut``) or as constraints."""
    for src, dst in rows:
        terms = [x[i, j] for i in np.flatnonzero(src).tolist() for j in np.flatnonzero(dst).tolist() if (i, j) in x]
        if not cut:
            model.addCons(scip.quicksum(terms) >= 1, removable=False)
            continue
        row = model.createEmptyRowUnspec(name="c", lhs=1.0, rhs=None, local=False, removable=True)
        model.cacheRowExtensions(row)
        for v in terms:
            model.addVarToRow(row, v, 1.0)
        model.flushRowExtensions(row)
        model.addCut(row, forcecut=False)
        model.addPoolCut(row)
        model.releaseRow(row)
    return len(rows)


def _handler(scip: Any) -> type:
    """The constraint handler class (PySCIPOpt is imported lazily). SCIP passes the callbacks' arguments by
    position; those the handler does not read are taken as ``*_``."""
    result = scip.SCIP_RESULT

    class Route(scip.Conshdlr):  # type: ignore[misc, name-defined]
        def __init__(self, x: dict, cuts: _Cuts, n: int, rule: tuple) -> None:
            self.x, self.cuts, self.n, self.rule = x, cuts, n, rule

        def conscheck(self, _constraints: Any, solution: Any, *_: Any) -> dict:
            broken = _broken(_arc_values(self.model, self.x, self.n, solution), self.rule) is not None
            return {"result": result.INFEASIBLE if broken else result.FEASIBLE}

        def consenfolp(self, *_: Any) -> dict:
            xv = _arc_values(self.model, self.x, self.n, None)
            inside = _broken(xv, self.rule)
            if inside is None:
                return {"result": result.FEASIBLE}
            rows = self.cuts.violated(xv, [inside], 0.5)
            if not rows:  # cannot happen for an integral point; be safe
                return {"result": result.INFEASIBLE}
            _add_rows(scip, self.model, self.x, rows, cut=False)
            return {"result": result.CONSADDED}

        consenfops = consenfolp

        def conslock(self, *_: Any) -> None:
            pass

        def conssepalp(self, *_: Any) -> dict:
            xv = _arc_values(self.model, self.x, self.n, None)
            rows = self.cuts.violated(xv, _components(xv) + _suffixes(xv), MIN_VIOLATION)
            found = _add_rows(scip, self.model, self.x, rows, cut=True)
            return {"result": result.SEPARATED if found else result.DIDNOTFIND}

    return Route
