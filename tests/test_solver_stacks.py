"""Every solver stack loads and solves in one process, in both import orders.

ortools 9.15 bundles HiGHS 1.12.0; cvxpy 1.9 needs highspy >= 1.14, and once both load in
one process an import fails (undefined symbol). The project pins cvxpy 1.8 with
highspy 1.12.0; this test guards that pin. Each order runs in a fresh interpreter, because
the clash only shows when both libraries load into the same process. PySCIPOpt (its own SCIP,
beside the SCIP and HiGHS that ortools bundles) is loaded first in one order and last in the other;
pycft (CFT's C++, with its own fmt) is loaded last in one order and before ortools in the other.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

ORTOOLS = """
from ortools.linear_solver import pywraplp
from ortools.sat.python import cp_model
for backend in ("SCIP", "HIGHS", "CBC"):
    s = pywraplp.Solver.CreateSolver(backend)
    assert s is not None, backend
    x, y = s.BoolVar("x"), s.BoolVar("y")
    s.Add(x + y >= 1)
    s.Minimize(2 * x + 3 * y)
    assert s.Solve() == pywraplp.Solver.OPTIMAL and s.Objective().Value() == 2.0, backend
m = cp_model.CpModel()
a, b = m.NewBoolVar("a"), m.NewBoolVar("b")
m.AddBoolOr([a, b])
m.Minimize(2 * a + 3 * b)
solver = cp_model.CpSolver()
solver.parameters.num_workers = 1
assert solver.Solve(m) == cp_model.OPTIMAL and solver.ObjectiveValue() == 2
"""

CVXPY = """
import cvxpy as cp
import highspy
import numpy as np
# largest disc in the unit square: a second-order cone program, radius 0.5
c, r = cp.Variable(2), cp.Variable()
cons = [c - r >= 0, c + r <= 1]
prob = cp.Problem(cp.Maximize(r), cons + [cp.norm(c - np.array([0.5, 0.5])) <= 1])
prob.solve(solver=cp.CLARABEL)
assert abs(r.value - 0.5) < 1e-6
# an LP through cvxpy's HiGHS interface, i.e. highspy in the same process as ortools' HiGHS
z = cp.Variable(2)
lp = cp.Problem(cp.Minimize(z[0] + 2 * z[1]), [z >= 0, z[0] + z[1] >= 1])
lp.solve(solver=cp.HIGHS)
assert abs(lp.value - 1.0) < 1e-9 and highspy.Highs is not None
"""

PULP = """
import pulp
p = pulp.LpProblem("t", pulp.LpMinimize)
x, y = pulp.LpVariable("x", cat="Binary"), pulp.LpVariable("y", cat="Binary")
p += 2 * x + 3 * y
p += x + y >= 1
p.solve(pulp.PULP_CBC_CMD(msg=False, threads=1))
assert pulp.value(p.objective) == 2
"""

PYSCIPOPT = """
import pyscipopt
m = pyscipopt.Model()
m.hideOutput()
x, y = m.addVar(vtype="B"), m.addVar(vtype="B")
m.addCons(x + y >= 1)
m.setObjective(2 * x + 3 * y)
m.optimize()
assert m.getStatus() == "optimal" and m.getObjVal() == 2
"""

PYCFT = """
from pycft import SetCoverSolver
s = SetCoverSolver()
for elements, cost in (([0, 1], 2.0), ([1, 2], 3.0), ([0, 1, 2], 6.0), ([2], 1.0)):
    s.add_set(elements, cost=cost)
s.solve(seed=0, verbose=0)
assert sorted(s.get_solution()) == [0, 3] and s.get_cost() == 3.0  # {0, 1} and {2}: 2 + 1
"""


@pytest.mark.slow
@pytest.mark.parametrize(
    "order",
    [(ORTOOLS, CVXPY, PULP, PYSCIPOPT, PYCFT), (PYSCIPOPT, CVXPY, PYCFT, ORTOOLS, PULP)],
    ids=["ortools-first", "pyscipopt-first"],
)
def test_solver_stacks_load_in_both_orders(order):
    code = "\n".join(textwrap.dedent(part) for part in order) + "\nprint('ok')\n"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and done.stdout.strip().endswith("ok"), done.stderr[-2000:]
