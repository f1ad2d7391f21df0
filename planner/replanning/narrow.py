"""Two helpers that keep a re-plan's solve within seconds: the shortlist of candidates the MILP chooses from
(:func:`shortlist`: for each piece still to cover, the few candidates that see the most of what is left, with the
done stations and the repaired previous plan, so that a plan is always among them) and the bound of the rest over
every candidate left (:func:`lp_bound`: the cover LP, a relaxation of the connected cover, so a valid lower bound
over the whole pool left after the edits, whatever the shortlist holds)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from planner.solve.instance import CoverInstance

#: candidates kept per piece still to cover, those that see the most of what is left
TOP_PER_PIECE = 8
#: the LP's value is rounded up after this much is taken off (HiGHS' feasibility tolerance is far below it)
LP_TOL = 1e-4


def shortlist(inst: CoverInstance, keep: Sequence[int], n_real: int, per_piece: int = TOP_PER_PIECE) -> np.ndarray:
    """Rows of ``inst``: for each of its first ``n_real`` columns the ``per_piece`` rows that see most of those
    columns among the rows that see it, and ``keep``; sorted."""
    a = inst.by_candidate[:, :n_real].tocsr()
    size = np.diff(a.indptr)
    bt = a.T.tocsr()
    chosen = np.zeros(a.shape[0], dtype=bool)
    chosen[list(keep)] = True
    for t in range(bt.shape[0]):
        rows = bt.indices[bt.indptr[t] : bt.indptr[t + 1]]
        if rows.size <= per_piece:
            chosen[rows] = True
        else:
            chosen[rows[np.argpartition(-size[rows], per_piece - 1)[:per_piece]]] = True
    return np.flatnonzero(chosen)


def restricted(inst: CoverInstance, rows: np.ndarray) -> CoverInstance:
    """``inst`` with only ``rows`` as candidates."""

    def sub(m: sp.csr_matrix | None, both: bool = False) -> sp.csr_matrix | None:
        if m is None:
            return None
        m = sp.csr_matrix(m)[rows]
        return m[:, rows].tocsr() if both else m.tocsr()

    return replace(
        inst,
        by_candidate=sub(inst.by_candidate),
        cost=np.asarray(inst.cost)[rows],
        groups=None if inst.groups is None else tuple(inst.groups[r] for r in rows),
        xy=None if inst.xy is None else inst.xy[rows],
        info=sub(inst.info),
        candidate_ids=None if inst.candidate_ids is None else tuple(inst.candidate_ids[r] for r in rows),
        links=sub(inst.links, True),
        relation=sub(inst.relation, True),
    )


def lp_bound(inst: CoverInstance, done: Sequence[int], n_real: int, k: int) -> int | None:
    """The least number of stations besides the ``done`` rows that cover the first ``n_real`` columns of ``inst``
    ``k`` times, by the cover LP rounded up (None where the LP is not solved)."""
    if n_real == 0:
        return 0
    rows = np.setdiff1d(np.arange(inst.shape[0]), np.asarray(done, dtype=np.int64))
    a = inst.by_candidate[rows][:, :n_real].astype(np.float64).T.tocsr()
    res = linprog(c=np.ones(len(rows)), A_ub=-a, b_ub=-float(k) * np.ones(n_real), bounds=(0.0, 1.0), method="highs")
    if res.status != 0:
        return None
    return max(0, int(np.ceil(float(res.fun) - LP_TOL)))
