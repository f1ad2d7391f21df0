"""SCIP through PySCIPOpt: a backend of its own, and branch-and-cut for registration connectivity.

With :meth:`PyScipBackend.connect` it gets a constraint handler, so connectivity is enforced inside one search tree
(no restarts, SCIP keeps its cut pool):

* ``conscheck`` rejects a solution whose chosen stations of some zone-side fall apart under the overlap relation;
* ``consenfolp`` / ``consenfops`` answer such an integral point with the region cuts of
  :func:`planner.solve.connectivity.connectivity_cuts`;
* ``conssepalp`` separates fractional LP points with minimum node-separator inequalities (:mod:`planner.solve.separators`).

PySCIPOpt is imported lazily, so that importing the planner does not load SCIP. SCIP solves on one thread
(deterministic).
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra

from planner.solve.backends import CAPABILITIES, BackendResult, Hint, Outcome, Row, hint_values, is_integral, wall_cap
from planner.solve.connectivity import connectivity_cuts, disconnected_groups, group_members
from planner.solve.separators import min_node_separator, nearest_seer, split_graph

#: fractional separation: sources tried per zone-side and round, least violation kept
MAX_SOURCES = 30
MIN_VIOLATION = 1e-3


class PyScipBackend:
    name = "pyscipopt"
    capabilities = CAPABILITIES[name]

    def __init__(self, n: int, cost: np.ndarray) -> None:
        import pyscipopt

        self._scip = pyscipopt
        self.model = pyscipopt.Model("cover")
        self.model.hideOutput()
        self.x = [self.model.addVar(f"x{i}", vtype="B", obj=float(c)) for i, c in enumerate(cost)]
        self.n = n
        self.model.setMinimize()
        if is_integral(cost):
            self.model.setObjIntegral()
        self.handler: Any = None
        #: branch-and-bound nodes per solve (None: no limit)
        self.node_limit: int | None = None

    def add_rows(self, rows: list[Row]) -> None:
        self.model.freeTransform()
        q = self._scip.quicksum
        for idx, coef, lb in rows:
            self.model.addCons(q(float(a) * self.x[int(i)] for i, a in zip(idx, coef)) >= float(lb))

    def fix(self, idx: list[int]) -> None:
        self.model.freeTransform()
        for i in idx:
            self.model.chgVarLb(self.x[i], 1.0)

    def add_vars(self, count: int, upper: float, binary: bool) -> None:
        self.model.freeTransform()
        k0 = len(self.x)
        self.x += [
            self.model.addVar(f"y{k0 + k}", vtype="B")
            if binary
            else self.model.addVar(f"f{k0 + k}", vtype="C", lb=0.0, ub=float(upper))
            for k in range(count)
        ]

    def connect(
        self,
        adj: sp.csr_matrix,
        groups: Sequence[Hashable],
        a: sp.csr_matrix,
        essential: dict[Hashable, np.ndarray],
    ) -> None:
        """Enforce connectivity of each group's chosen stations inside the search (branch-and-cut)."""
        self.handler = _handler(self._scip)(self.x[: self.n], adj, groups, a, essential)
        self.model.includeConshdlr(
            self.handler,
            "registration",
            "chosen stations of a zone-side connected",
            sepapriority=10,
            enfopriority=-10,
            chckpriority=-10,
            sepafreq=1,
            needscons=False,
        )
        # the handler declares no variable locks: dual reductions would be unsafe
        self.model.setBoolParam("misc/allowstrongdualreds", False)
        self.model.setBoolParam("misc/allowweakdualreds", False)

    @property
    def cuts(self) -> int:
        return 0 if self.handler is None else self.handler.n_int + self.handler.n_frac

    def solve(self, time_limit_s: float | None, threads: int, seed: int, hint: Hint | None) -> BackendResult:
        m = self.model
        m.freeTransform()
        if (cap := wall_cap(time_limit_s)) is not None:
            m.setParam("limits/time", cap)
        if self.node_limit is not None:
            m.setParam("limits/nodes", self.node_limit)
        m.setParam("randomization/randomseedshift", int(seed))
        m.setParam("lp/threads", 1)
        if hint is not None:
            sol = m.createSol()
            for i, val in hint_values(hint, self.n).items():
                m.setSolVal(sol, self.x[i], val)
            m.addSol(sol)
        m.optimize()
        status = m.getStatus()
        dual = m.getDualbound()
        bound = float(dual) if np.isfinite(dual) and abs(dual) < 1e19 else None
        if m.getNSols() > 0:
            best = m.getBestSol()
            sel = tuple(i for i, v in enumerate(self.x[: self.n]) if m.getSolVal(best, v) > 0.5)
            obj = float(m.getSolObjVal(best))
            return BackendResult(Outcome.OPTIMAL if status == "optimal" else Outcome.FEASIBLE, sel, obj, bound)
        if status == "infeasible":
            return BackendResult(Outcome.INFEASIBLE, (), None, None)
        return BackendResult(Outcome.UNKNOWN, (), None, bound)


def _handler(scip: Any) -> type:
    """The constraint handler class (built on first use)."""
    result = scip.SCIP_RESULT

    class Registration(scip.Conshdlr):  # type: ignore[misc, name-defined]
        def __init__(
            self,
            x: list,
            adj: sp.csr_matrix,
            groups: Sequence[Hashable],
            a: sp.csr_matrix,
            essential: dict[Hashable, np.ndarray],
        ) -> None:
            self.x, self.adj, self.groups, self.a, self.essential = x, adj.tocsr(), list(groups), a.tocsr(), essential
            self.n_int = self.n_frac = 0
            self.seers = a.T.tocsr()  # target -> candidates that see it
            by_group = group_members(self.groups, range(len(self.groups)))
            self.members = {g: np.asarray(v) for g, v in by_group.items()}

        def _values(self, sol: Any) -> np.ndarray:
            return np.array([self.model.getSolVal(sol, v) for v in self.x])

        def _broken(self, vals: np.ndarray) -> dict:
            return disconnected_groups(self.adj, self.groups, np.flatnonzero(vals > 0.5).tolist())

        def conscheck(self, constraints, solution, checkintegrality, checklprows, printreason, completely):
            return {"result": result.INFEASIBLE if self._broken(self._values(solution)) else result.FEASIBLE}

        def _enforce(self) -> dict:
            broken = self._broken(self._values(None))
            if not broken:
                return {"result": result.FEASIBLE}
            q = scip.quicksum
            for g, comps in broken.items():
                for idx, coef, lb in connectivity_cuts(self.adj, comps, self.a, self.essential.get(g)):
                    self.model.addCons(
                        q(float(c) * self.x[int(i)] for i, c in zip(idx, coef)) >= float(lb), removable=False
                    )
                    self.n_int += 1
            return {"result": result.CONSADDED}

        def consenfolp(self, constraints, nusefulconss, solinfeasible):
            return self._enforce()

        def consenfops(self, constraints, nusefulconss, solinfeasible, objinfeasible):
            return self._enforce()

        def conslock(self, constraint, locktype, nlockspos, nlocksneg):
            pass

        def conssepalp(self, constraints, nusefulconss):
            vals = self._values(None)
            found = 0
            base = split_graph(self.adj, vals)
            for g, members in self.members.items():
                for i, nodes in _separations(self, self.essential.get(g), members, vals, base):
                    _add_separator_cut(self.model, self.x, i, nodes)
                    found += 1
            self.n_frac += found
            return {"result": result.SEPARATED if found else result.DIDNOTFIND}

    return Registration


def _add_separator_cut(model: Any, x: list, i: int, nodes: Sequence[int]) -> None:
    """The cut ``sum(x[nodes]) >= x[i]`` to the LP and the cut pool."""
    row = model.createEmptyRowUnspec(name="sep", lhs=0.0, rhs=None, local=False, removable=True)
    model.cacheRowExtensions(row)
    for v in nodes:
        model.addVarToRow(row, x[int(v)], 1.0)
    model.addVarToRow(row, x[int(i)], -1.0)
    model.flushRowExtensions(row)
    model.addCut(row, forcecut=False)
    model.addPoolCut(row)
    model.releaseRow(row)


def _separations(h: Any, ess: np.ndarray | None, members: np.ndarray, vals: np.ndarray, base: sp.csr_matrix):
    """The violated separator inequalities of one group (members ``members``, essential targets ``ess``) at the LP
    point ``vals``, for the handler ``h``: pairs (station i, separator nodes)."""
    if ess is None or not ess.any():
        return
    order = members[np.argsort(-vals[members], kind="stable")]
    sources = [int(i) for i in order[:MAX_SOURCES] if vals[i] > MIN_VIOLATION]
    if not sources:
        return
    hops = dijkstra(h.adj, directed=False, indices=sources, unweighted=True)
    ess_t = np.flatnonzero(ess)
    seers = h.seers
    for k, i in enumerate(sources):
        seen = np.zeros(h.a.shape[1], dtype=bool)
        seen[h.a.indices[h.a.indptr[i] : h.a.indptr[i + 1]]] = True
        need = ess_t[~seen[ess_t]]
        if need.size == 0:
            continue
        # the essential target whose nearest seer is farthest from i in overlap steps
        t = int(need[int(np.argmax(nearest_seer(hops[k], seers, need)))])
        value, nodes = min_node_separator(base, i, seers.indices[seers.indptr[t] : seers.indptr[t + 1]])
        if vals[i] - value > MIN_VIOLATION:
            yield i, nodes
