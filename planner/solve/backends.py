"""Interchangeable 0-1 solvers behind one interface.

Each backend holds one model (binary x, minimise cost . x, rows ``sum coef * x >= lb``), accepts more rows between
solves (the lazy connectivity cuts) and solves with a thread count, seed, warm-start hint and an optional wall-clock
cap (``None``: none): OR-Tools CP-SAT; OR-Tools' linear solver with SCIP, HiGHS or CBC; PuLP with CBC; PySCIPOpt.

Work limits, which make a solve's answer independent of the machine's load: CP-SAT stops on deterministic time
(:attr:`CpSatBackend.work_limit`); SCIP (both ways) and PuLP's CBC on branch-and-bound nodes per solve
(``node_limit``). HiGHS and CBC through OR-Tools take no node limit in this build: they run to their optimum unless
the user's wall-clock cap stops them.
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
import tempfile
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from enum import Enum
from typing import Any, Protocol

import numpy as np

from planner.core.errors import UsageError

Row = tuple[np.ndarray, np.ndarray, float]
#: a warm start: the chosen candidates, or a value for each variable (added variables included)
Hint = list[int] | dict[int, float]
#: called with each improving solution found during a solve (chosen candidates, objective); True stops the solve
Watch = Callable[[tuple[int, ...], float], bool]


@dataclass(frozen=True)
class Capabilities:
    """What a backend can do, by which the solver tells backends apart (never by name): ``work_limit``, it stops on
    deterministic work (an answer independent of the load); ``node_limit``, on branch-and-bound nodes per solve;
    ``watch``, it hands each improving solution to a callback; ``branch_and_cut``, connectivity inside one search
    tree; ``hints``, it takes a warm start; ``banner``, its native code prints to stdout on every solve."""

    work_limit: bool = False
    node_limit: bool = False
    watch: bool = False
    branch_and_cut: bool = False
    hints: bool = True
    banner: bool = False


#: every backend by name, with its capabilities
CAPABILITIES = {
    "cpsat": Capabilities(work_limit=True, watch=True),
    "scip": Capabilities(node_limit=True),
    "highs": Capabilities(hints=False, banner=True),  # SetHint crashes HiGHS 1.12 in OR-Tools 9.15 (segfault)
    "cbc": Capabilities(),
    "pulp-cbc": Capabilities(node_limit=True),
    "pyscipopt": Capabilities(node_limit=True, branch_and_cut=True),
}
BACKENDS = tuple(CAPABILITIES)
#: the backends a node limit per solve stops (the others: CP-SAT's work, or nothing but the user's wall cap)
NODE_LIMITED = tuple(name for name, c in CAPABILITIES.items() if c.node_limit)
#: CP-SAT needs integer coefficients: fractional ones are scaled by this and rounded down (a row sum(floor(s*a) x) >=
#: ceil(s*lb) implies the original, so solutions stay feasible).
CP_SCALE = 10**6
#: CP-SAT's workers, in order, for ``threads`` > 1: the full-LP worker first, then the core-based bound
CP_PORTFOLIO = tuple(
    "max_lp core quick_restart default_lp reduced_costs pseudo_costs no_lp lb_tree_search probing fixed".split()
)


class Outcome(str, Enum):
    OPTIMAL = "optimal"
    FEASIBLE = "feasible"
    INFEASIBLE = "infeasible"
    UNKNOWN = "unknown"


@dataclass(frozen=True)
class BackendResult:
    outcome: Outcome
    selected: tuple[int, ...]
    objective: float | None
    bound: float | None


class Backend(Protocol):
    """One 0-1 model on a solver (module docstring)."""

    name: str
    capabilities: Capabilities

    def add_rows(self, rows: list[Row]) -> None: ...

    def fix(self, idx: list[int]) -> None: ...

    def add_vars(self, count: int, upper: float, binary: bool) -> None:
        """Append ``count`` variables in [0, upper], binary or continuous, at zero cost."""

    def solve(self, time_limit_s: float | None, threads: int, seed: int, hint: Hint | None) -> BackendResult: ...


@contextlib.contextmanager
def _quiet_stdout_fd() -> Iterator[None]:
    """Silence what native code writes straight to file descriptor 1 (HiGHS prints a banner on every solve whatever
    SuppressOutput says); library code must not print."""
    try:
        sys.stdout.flush()
        saved = os.dup(1)
    except (OSError, ValueError):
        yield
        return
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 1)
            yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)


def wall_cap(time_limit_s: float | None) -> float | None:
    """The user's wall-clock cap, if any, in seconds (at least 0.01)."""
    return max(time_limit_s, 0.01) if time_limit_s is not None and math.isfinite(time_limit_s) else None


def hint_values(hint: Hint, n: int) -> dict[int, float]:
    """Every one of the first ``n`` (candidate) variables' value, 0 unless chosen, plus the hint's other values."""
    values = dict.fromkeys(range(n), 0.0)
    values.update({int(i): 1.0 for i in hint} if isinstance(hint, list) else hint)
    return values


def is_integral(a: np.ndarray) -> bool:
    """Every value within 1e-12 of an integer."""
    return bool(np.all(np.abs(a - np.round(a)) < 1e-12))


class CpSatBackend:
    name = "cpsat"
    capabilities = CAPABILITIES[name]

    def __init__(self, n: int, cost: np.ndarray) -> None:
        from ortools.sat.python import cp_model

        self._cp = cp_model
        self.model = cp_model.CpModel()
        self.x = [self.model.NewBoolVar(f"x{i}") for i in range(n)]
        self.n = n
        self.watch: Watch | None = None
        #: CP-SAT deterministic time this model may spend in all (None: wall clock only), and what it spent
        self.work_limit: float | None = None
        self.work_used = 0.0
        self.scale = 1 if is_integral(cost) else CP_SCALE
        c = np.round(cost * self.scale).astype(np.int64)
        self.model.Minimize(sum(int(ci) * self.x[i] for i, ci in enumerate(c) if ci))

    def add_rows(self, rows: list[Row]) -> None:
        """Add ``sum coef * x >= lb`` rows. Rows ``x_i <= sum_{v in N} x_v`` that share N (the region cuts of one
        component) become one literal y_N with y_N => OR(N) and x_i => y_N: the same linear relaxation, one long
        clause instead of |R| long rows."""
        shared: dict[tuple[int, ...], list[int]] = {}
        for idx, coef, lb in rows:
            neg = np.flatnonzero(coef < 0)
            if lb == 0.0 and neg.size == 1 and coef[neg[0]] == -1.0 and np.count_nonzero(coef == 1.0) == coef.size - 1:
                # the key sorted in numpy (a region cut lists hundreds of neighbours): the same tuple of ints
                key = np.sort(np.delete(idx, neg).astype(np.int64)).tolist()
                shared.setdefault(tuple(key), []).append(int(idx[neg[0]]))
            elif lb == 1.0 and np.all(coef == 1.0):
                self.model.AddBoolOr([self.x[i] for i in idx])
            elif is_integral(coef) and float(lb).is_integer():
                self.model.Add(sum(int(a) * self.x[i] for i, a in zip(idx, coef)) >= int(lb))
            else:
                a = np.floor(coef * CP_SCALE).astype(np.int64)
                self.model.Add(sum(int(v) * self.x[i] for i, v in zip(idx, a)) >= math.ceil(lb * CP_SCALE))
        for nb, heads in shared.items():
            lits = [self.x[v] for v in nb]
            if len(heads) == 1:
                self.model.AddBoolOr(lits + [self.x[heads[0]].Not()])
                continue
            y = self.model.NewBoolVar(f"y{len(self.x)}_{len(heads)}")
            self.model.AddBoolOr(lits + [y.Not()])
            for i in heads:
                self.model.AddImplication(self.x[i], y)

    def fix(self, idx: list[int]) -> None:
        for i in idx:
            self.model.Add(self.x[i] == 1)

    def add_vars(self, count: int, upper: float, binary: bool) -> None:
        """Integer variables here: CP-SAT has no continuous ones; the flow models that use them have integral optima."""
        k0 = len(self.x)
        ub = int(math.floor(upper))
        self.x += [
            self.model.NewBoolVar(f"y{k0 + k}") if binary else self.model.NewIntVar(0, ub, f"f{k0 + k}")
            for k in range(count)
        ]

    def solve(self, time_limit_s: float | None, threads: int, seed: int, hint: Hint | None) -> BackendResult:
        self.model.ClearHints()
        if hint is not None:
            for i, val in hint_values(hint, self.n).items():
                self.model.AddHint(self.x[i], int(round(val)))
        solver = self._cp.CpSolver()
        if (cap := wall_cap(time_limit_s)) is not None:
            solver.parameters.max_time_in_seconds = cap
        if self.work_limit is not None:  # a work budget makes one worker's answer independent of the load
            solver.parameters.max_deterministic_time = max(self.work_limit - self.work_used, 1e-3)
        # one worker with the full LP relaxation is deterministic and proves set-cover optima quickly
        solver.parameters.num_workers = threads
        if threads > 1:  # CP-SAT's own choice for 2 workers has no full-LP worker (and often no bound)
            solver.parameters.subsolvers.extend(CP_PORTFOLIO[:threads])
        solver.parameters.linearization_level = 2
        solver.parameters.random_seed = seed
        status = solver.Solve(self.model, self._callback() if self.watch is not None else None)
        self.work_used += float(solver.deterministic_time)
        cp = self._cp
        if status in (cp.OPTIMAL, cp.FEASIBLE):
            sel = tuple(i for i, v in enumerate(self.x[: self.n]) if solver.BooleanValue(v))
            outcome = Outcome.OPTIMAL if status == cp.OPTIMAL else Outcome.FEASIBLE
            return BackendResult(
                outcome, sel, solver.ObjectiveValue() / self.scale, solver.BestObjectiveBound() / self.scale
            )
        if status == cp.INFEASIBLE:
            return BackendResult(Outcome.INFEASIBLE, (), None, None)
        return BackendResult(Outcome.UNKNOWN, (), None, solver.BestObjectiveBound() / self.scale)

    def _callback(self) -> Any:
        watch, n, scale, x = self.watch, self.n, self.scale, self.x

        class _Seen(self._cp.CpSolverSolutionCallback):  # type: ignore[name-defined,misc]
            def on_solution_callback(self) -> None:
                sel = tuple(i for i in range(n) if self.BooleanValue(x[i]))
                if watch is not None and watch(sel, self.ObjectiveValue() / scale):
                    self.StopSearch()

        return _Seen()


class MipBackend:
    """OR-Tools' linear solver (pywraplp) with SCIP, HiGHS or CBC."""

    SOLVERS = {"scip": "SCIP", "highs": "HIGHS", "cbc": "CBC"}

    def __init__(self, name: str, n: int, cost: np.ndarray) -> None:
        from ortools.linear_solver import pywraplp

        self._lp = pywraplp
        self.name = name
        self.capabilities = CAPABILITIES[name]
        self.solver = pywraplp.Solver.CreateSolver(self.SOLVERS[name])
        if self.solver is None:
            raise UsageError("solver not available in this OR-Tools build", field="backend", value=name)
        self.solver.SuppressOutput()
        self.x = [self.solver.BoolVar(f"x{i}") for i in range(n)]
        self.n = n
        #: branch-and-bound nodes per solve (where ``capabilities.node_limit``; None: no limit)
        self.node_limit: int | None = None
        obj = self.solver.Objective()
        for i, c in enumerate(cost):
            obj.SetCoefficient(self.x[i], float(c))
        obj.SetMinimization()

    def add_rows(self, rows: list[Row]) -> None:
        for idx, coef, lb in rows:
            ct = self.solver.RowConstraint(float(lb), self.solver.infinity(), "")
            for i, a in zip(idx, coef):
                ct.SetCoefficient(self.x[int(i)], float(a))

    def fix(self, idx: list[int]) -> None:
        for i in idx:
            self.x[i].SetLb(1.0)

    def add_vars(self, count: int, upper: float, binary: bool) -> None:
        k0 = len(self.x)
        self.x += [
            self.solver.BoolVar(f"y{k0 + k}") if binary else self.solver.NumVar(0.0, float(upper), f"f{k0 + k}")
            for k in range(count)
        ]

    def solve(self, time_limit_s: float | None, threads: int, seed: int, hint: Hint | None) -> BackendResult:
        s = self.solver
        if (cap := wall_cap(time_limit_s)) is not None:
            s.SetTimeLimit(int(cap * 1000))
        s.SetNumThreads(threads)
        if self.capabilities.node_limit:  # SCIP: its seed and node limit as its own parameters
            nodes = f"limits/nodes = {self.node_limit}\n" if self.node_limit is not None else ""
            s.SetSolverSpecificParametersAsString(f"randomization/randomseedshift = {seed}\n{nodes}")
        if hint is not None and self.capabilities.hints:
            values = hint_values(hint, self.n)
            s.SetHint([self.x[i] for i in values], list(values.values()))
        with _quiet_stdout_fd() if self.capabilities.banner else contextlib.nullcontext():
            status = s.Solve()
        lp = self._lp
        if status in (lp.Solver.OPTIMAL, lp.Solver.FEASIBLE):
            sel = tuple(i for i, v in enumerate(self.x[: self.n]) if v.solution_value() > 0.5)
            bound = s.Objective().BestBound()
            outcome = Outcome.OPTIMAL if status == lp.Solver.OPTIMAL else Outcome.FEASIBLE
            return BackendResult(outcome, sel, s.Objective().Value(), bound if math.isfinite(bound) else None)
        if status == lp.Solver.INFEASIBLE:
            return BackendResult(Outcome.INFEASIBLE, (), None, None)
        return BackendResult(Outcome.UNKNOWN, (), None, None)


class PulpBackend:
    """PuLP with its bundled CBC; the model is rebuilt on each solve (PuLP writes an MPS file)."""

    name = "pulp-cbc"
    capabilities = CAPABILITIES[name]

    def __init__(self, n: int, cost: np.ndarray) -> None:
        import pulp

        self._pulp = pulp
        self.cost = np.asarray(cost, dtype=float)
        self.rows: list[Row] = []
        self.fixed: list[int] = []
        self.n = len(self.cost)
        self.extra: list[tuple[float, bool]] = []  # (upper, binary) of each added variable
        #: branch-and-bound nodes per solve (None: no limit)
        self.node_limit: int | None = None

    def add_vars(self, count: int, upper: float, binary: bool) -> None:
        self.extra += [(float(upper), binary)] * count

    def add_rows(self, rows: list[Row]) -> None:
        self.rows += rows

    def fix(self, idx: list[int]) -> None:
        self.fixed += idx

    def solve(self, time_limit_s: float | None, threads: int, seed: int, hint: Hint | None) -> BackendResult:
        # PuLP 3 announces its 4.0 API with a DeprecationWarning per variable; the project pins pulp < 4
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            pulp = self._pulp
            prob = pulp.LpProblem("cover", pulp.LpMinimize)
            x = [pulp.LpVariable(f"x{i}", cat="Binary") for i in range(len(self.cost))]
            x += [
                pulp.LpVariable(f"y{k}", cat="Binary") if b else pulp.LpVariable(f"f{k}", 0, ub)
                for k, (ub, b) in enumerate(self.extra)
            ]
            prob += pulp.lpSum(float(c) * x[i] for i, c in enumerate(self.cost) if c)
            for k, (idx, coef, lb) in enumerate(self.rows):
                prob += pulp.lpSum(float(a) * x[int(i)] for i, a in zip(idx, coef)) >= float(lb), f"r{k}"
            for i in self.fixed:
                x[i].lowBound = 1
            if hint is not None:
                for i, val in hint_values(hint, self.n).items():
                    x[i].setInitialValue(val)
            with tempfile.TemporaryDirectory() as tmp:
                options = [f"randomSeed {seed + 1}", f"randomCbcSeed {seed + 1}"]
                options += [f"maxNodes {self.node_limit}"] if self.node_limit is not None else []
                cap = wall_cap(time_limit_s)
                warm = hint is not None
                cmd = pulp.PULP_CBC_CMD(
                    msg=False, timeLimit=cap, threads=threads, warmStart=warm, options=options, keepFiles=False
                )
                cmd.tmpDir = tmp
                prob.solve(cmd)
            sol = prob.sol_status
            if sol in (pulp.LpSolutionOptimal, pulp.LpSolutionIntegerFeasible):
                sel = tuple(i for i, v in enumerate(x[: self.n]) if (v.value() or 0) > 0.5)
                obj = float(self.cost[list(sel)].sum())
                optimal = sol == pulp.LpSolutionOptimal
                outcome = Outcome.OPTIMAL if optimal else Outcome.FEASIBLE
                return BackendResult(outcome, sel, obj, obj if optimal else None)
            if sol == pulp.LpSolutionInfeasible or prob.status == pulp.LpStatusInfeasible:
                return BackendResult(Outcome.INFEASIBLE, (), None, None)
            return BackendResult(Outcome.UNKNOWN, (), None, None)
