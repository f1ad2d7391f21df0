"""Area rows: the plain cover's minimum of each separate area of a block, as a row of the connected MILP.

A block under one registration group can still fall into *areas*: sets of targets no candidate sees across (the rooms
of a site whose openings link stations but let no station see into two rooms' walls). They are the components of the
graph that joins two targets when some candidate sees both; each candidate's targets then lie in one area. Any plan,
connected or not, covers each area A with A's own candidates, so

    sum_{j in A} c_j x_j >= m_A        (m_A: a lower bound on the cheapest plain cover of A alone)

is valid for every plan. The sum of the m_A is a bound on the block. The rows add nothing to the LP where it is
integral, but they tell the search how many stations each area needs, so under the connectivity cuts it stops
spending the last station of a tight plan in an area that is already covered and looks for the bridges instead.
Each m_A comes from one CP-SAT solve of A's plain cover on a count of deterministic work (the same rows under any
load); an unfinished solve gives its proven bound.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

Row = tuple[np.ndarray, np.ndarray, float]

#: CP-SAT deterministic seconds for one area's plain cover (small areas close in a few milliseconds)
AREA_WORK = 1.0


@dataclass(frozen=True, kw_only=True)
class AreaRows:
    """A block's areas: ``label[j]`` the area of candidate j (-1: it sees nothing), ``minimum[a]`` the proven lower
    bound on area a's plain cover, ``rows`` the rows ``sum_{j in a} c_j x_j >= minimum[a]``, ``work`` the CP-SAT
    deterministic seconds spent."""

    label: np.ndarray
    minimum: tuple[float, ...]
    rows: tuple[Row, ...]
    work: float

    @property
    def bound(self) -> float:
        """A lower bound on any cover of the block: the areas' minima added up."""
        return float(sum(self.minimum))


def target_areas(sub: sp.csr_matrix) -> tuple[int, np.ndarray]:
    """The number of areas of ``sub`` (candidates x targets) and each target's area."""
    b = sp.csr_matrix(sub, dtype=np.float64)
    return connected_components((b.T @ b) > 0, directed=False)  # type: ignore[no-any-return]


def area_rows(sub: sp.csr_matrix, cost: np.ndarray, k: int = 1, work: float = AREA_WORK) -> AreaRows | None:
    """The area rows of a block (``sub``: its candidates x targets, each target needing ``k`` views), or None where
    the block is one area (the row would be its own objective bound)."""
    from ortools.sat.python import cp_model

    sub = sp.csr_matrix(sub, dtype=bool)
    n_areas, t_label = target_areas(sub)
    if n_areas < 2:
        return None
    has = np.diff(sub.indptr) > 0
    label = np.full(sub.shape[0], -1, dtype=np.int64)
    label[has] = t_label[sub.indices[sub.indptr[:-1][has]]]
    integral = bool(np.all(cost == np.round(cost)))
    scale = 1 if integral else 10**6
    minima, rows, spent = [], [], 0.0
    for area in range(n_areas):
        cands, targets = np.flatnonzero(label == area), np.flatnonzero(t_label == area)
        part = sub[cands][:, targets].T.tocsr()
        model = cp_model.CpModel()
        x = [model.NewBoolVar(f"x{j}") for j in range(cands.size)]
        for t in range(targets.size):
            seen = part.indices[part.indptr[t] : part.indptr[t + 1]]
            model.Add(sum(x[j] for j in seen) >= k)
        model.Minimize(sum(int(c) * v for c, v in zip(np.round(cost[cands] * scale), x)))
        solver = cp_model.CpSolver()
        solver.parameters.num_workers = 1
        solver.parameters.linearization_level = 2  # the LP bound closes most areas at the root
        solver.parameters.max_deterministic_time = work
        solver.parameters.random_seed = 0
        status = solver.Solve(model)
        spent += float(solver.deterministic_time)
        low = solver.BestObjectiveBound() / scale if status in (cp_model.OPTIMAL, cp_model.FEASIBLE) else 0.0
        low = float(np.ceil(low - 1e-6)) if integral else low
        minima.append(low)
        # fractional costs: the row leaves room for the backends' rounding of coefficients (CP-SAT's floor at 1e-6)
        rhs = low if integral else low - (cands.size + 1) * 1e-6
        if rhs > 0:
            rows.append((cands.astype(np.int64), np.asarray(cost[cands], dtype=np.float64), rhs))
    return AreaRows(label=label, minimum=tuple(minima), rows=tuple(rows), work=spent)
