"""The plain cover of a large matrix by CFT, through ``pycft``.

CFT (A. Caprara, M. Fischetti, P. Toth, "A heuristic method for the set covering problem", Operations Research 47(5),
1999; the C++ of Cavaliere and Accorsi, bound by Krupke as ``pycft``) works on a core of columns priced by Lagrangian
multipliers: subgradient optimisation of the multipliers, a greedy guided by the reduced costs, column fixing, and
refinement that unfixes and repeats. The large-site path uses it wherever it needs a plain cover: the ``--no-overlap``
plan, and the cover a connected plan is grown from (:mod:`planner.tiles.search`).

Determinism: CFT is run with its seed and no time limit, so it stops on its own rules (a count of heuristic
iterations, the refinement's cutoff): the same matrix and seed give the same cover under any load. ``time_cap_s`` is a
cap only a user sets.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np
import scipy.sparse as sp

from planner.core.errors import InfeasibleError

#: CFT's own default count of heuristic iterations per refinement round
HEUR_ITERS = 250


@dataclass(frozen=True, kw_only=True)
class CftCover:
    """``selected``: the cover (rows of the matrix, sorted); ``lower_bound``: CFT's Lagrangian lower bound (over the
    same matrix, unit costs unless costs were given); ``time_s``: wall seconds of the solve, one thread; ``capped``:
    the user's time cap stopped it."""

    selected: tuple[int, ...]
    lower_bound: float
    time_s: float
    capped: bool = False


def cft_cover(
    a: sp.csr_matrix,
    cost: np.ndarray | None = None,
    *,
    seed: int = 0,
    heur_iters: int = HEUR_ITERS,
    time_cap_s: float | None = None,
    start: tuple[int, ...] = (),
) -> CftCover:
    """A cover of every column of ``a`` by rows of least total ``cost`` (default 1 each: stations), found by CFT.
    ``start``: a cover to start from (its cost is the first upper bound). Raises :class:`InfeasibleError` when some
    target is seen by no row (CFT itself would return a non-cover), ``ValueError`` when ``start`` is not a cover."""
    a = sp.csr_matrix(a, dtype=bool)
    n_rows, n_cols = a.shape
    seen = np.bincount(a.indices, minlength=n_cols) > 0
    if not seen.all():
        unseen = int((~seen).sum())
        raise InfeasibleError(f"{unseen} of {n_cols} targets are seen by no candidate", field="cover", value=unseen)
    if n_cols == 0:  # nothing to cover: CFT is not called on an empty instance
        return CftCover(selected=(), lower_bound=0.0, time_s=0.0)
    cost = np.ones(n_rows) if cost is None else np.asarray(cost, dtype=float)
    rows = np.flatnonzero(np.diff(a.indptr) > 0)  # CFT numbers the sets it is given: empty rows left out
    from pycft import SetCoverSolver
    from pycft._bindings import Solution

    solver = SetCoverSolver()
    for r in rows:
        solver.add_set(a.indices[a.indptr[r] : a.indptr[r + 1]].tolist(), cost=float(cost[r]))
    if start:
        first = np.unique(np.asarray(start, dtype=np.int64))
        first = first[np.diff(a.indptr)[first] > 0]  # a row that sees nothing only adds cost
        if not (np.bincount(a[first].indices, minlength=n_cols) > 0).all():
            raise ValueError("start is not a cover: some target is seen by none of its rows")
        init = Solution()
        init.idxs = np.searchsorted(rows, first).tolist()  # the binding's idxs is a copy: assigned, never appended to
        init.cost = float(cost[first].sum())
        solver._result = SimpleNamespace(sol=init)  # what ``solve`` reads of a previous result: its solution
    t0 = time.perf_counter()
    limit = float("inf") if time_cap_s is None else time_cap_s
    solver.solve(seed=seed, time_limit=limit, verbose=0, heur_iters=heur_iters)
    elapsed = time.perf_counter() - t0
    chosen = np.sort(rows[np.asarray(solver.get_solution() or [], dtype=np.int64)])
    covered = np.bincount(a[chosen].indices, minlength=n_cols) > 0
    if not covered.all():  # CFT's answer is re-checked, never trusted
        raise RuntimeError(f"CFT returned a non-cover: {int((~covered).sum())} targets unseen")
    return CftCover(
        selected=tuple(int(i) for i in chosen),
        lower_bound=float(solver.get_lower_bound()),
        time_s=elapsed,
        capped=time_cap_s is not None and elapsed >= time_cap_s,
    )
