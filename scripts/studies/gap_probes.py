"""Probes of ``study_gap.py`` that tried to lift the bound or the plan past the tiled planner's, and did not
on the plant instances (docs/studies/plant-gap.md): each returns CSV rows of
``study_gap.FIELDS`` (less area and memory), every count re-checked here.

- ``highs_row``: the plain cover by HiGHS's MIP (``scipy.optimize.milp``), a time limit: its cover and bound;
- ``linked_lp_row``: the cover LP with each station needing a linked station beside it
  (``x_j <= sum_{i linked to j} x_i``, valid for every connected plan of two stations or more);
- ``rank_cut_row``: the cover LP with a local rank cut per disc: the pieces within ``radius`` of a grid point
  need at least ``k`` (their own integer optimum, or its proven bound) of the candidates that see one of them;
- ``merge_row``: the planner's connected MILP (as a window's, :mod:`planner.solve.windows`) over the union of
  some connected plans' stations: the best connected plan made of their stations.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.optimize import Bounds, LinearConstraint, linprog, milp


def disc(at: sp.csr_matrix, pts: np.ndarray, centre: np.ndarray, radius: float) -> tuple[np.ndarray, sp.csr_matrix]:
    """The pieces (rows of ``at``, pieces x candidates, at ``pts``) within ``radius`` of ``centre``: the
    candidates that see one of them, and those pieces x those candidates (float CSR)."""
    sub = at[np.flatnonzero(np.hypot(*(pts - centre).T) <= radius)].tocsc()
    cols = np.flatnonzero(np.diff(sub.indptr) > 0)
    return cols, sub[:, cols].tocsr().astype(np.float64)


def cover_ip(rows: sp.csr_matrix, time_s: float) -> tuple[Any, np.ndarray, int]:
    """The cover of ``rows`` (pieces x candidates) by HiGHS's MIP within ``time_s``: its result, the chosen
    columns (re-checked to cover every row), and the proven bound on the fewest columns (rounded up)."""
    n = rows.shape[1]
    r = milp(
        np.ones(n),
        constraints=LinearConstraint(rows, lb=1),
        integrality=np.ones(n),
        bounds=Bounds(0, 1),
        options={"time_limit": time_s},
    )
    chosen = np.flatnonzero(np.round(r.x) > 0) if r.x is not None else np.array([], dtype=int)
    assert chosen.size == 0 or np.all(rows[:, chosen].sum(axis=1) >= 1), "HiGHS cover does not cover"
    return r, chosen, round(r.fun) if r.status == 0 else math.ceil(r.mip_dual_bound - 1e-6)


def _rows_seen(a: sp.csr_matrix) -> sp.csr_matrix:
    """Pieces x candidates (float), the pieces some candidate sees."""
    at = a.T.tocsr().astype(np.float64)
    return at[np.diff(at.indptr) > 0]


def highs_row(a: sp.csr_matrix, time_s: float) -> dict:
    at = _rows_seen(a)
    t0 = time.perf_counter()
    r, chosen, _ = cover_ip(at, time_s)
    return {
        "what": "plain highs",
        "setting": f"{time_s:g} s, status {r.status}",
        "value": int(chosen.size) or "",
        "bound": round(float(r.mip_dual_bound), 3),
        "time_s": round(time.perf_counter() - t0, 1),
    }


def linked_lp_row(a: sp.csr_matrix, adj: sp.csr_matrix) -> dict:
    at = _rows_seen(a)
    n = a.shape[0]
    links = adj.astype(bool).astype(np.float64).tocsr()
    links.setdiag(0)
    links.eliminate_zeros()
    t0 = time.perf_counter()
    lhs = sp.vstack([-at, sp.identity(n, format="csr") - links]).tocsr()
    res = linprog(
        np.ones(n), A_ub=lhs, b_ub=np.concatenate([-np.ones(at.shape[0]), np.zeros(n)]), bounds=(0, 1), method="highs"
    )
    assert res.status == 0, res.message
    return {
        "what": "linked lp",
        "setting": "cover LP + a linked station beside each",
        "value": round(res.fun, 3),
        "bound": "",
        "time_s": round(time.perf_counter() - t0, 1),
    }


def rank_cut_row(a: sp.csr_matrix, mid: np.ndarray, radius: float, step: float, time_s: float) -> dict:
    at = _rows_seen(a)
    seen = np.diff(a.T.tocsr().indptr) > 0
    pts = mid[seen]
    t0 = time.perf_counter()
    cuts, rhs = [], []
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    for cx in np.arange(lo[0], hi[0] + step, step):
        for cy in np.arange(lo[1], hi[1] + step, step):
            cols, s = disc(at, pts, np.array([cx, cy]), radius)
            if cols.size == 0:
                continue
            k = cover_ip(s, time_s)[2]
            row = np.zeros(a.shape[0])
            row[cols] = 1.0
            cuts.append(row)
            rhs.append(k)
    lhs = sp.vstack([-at, -sp.csr_matrix(np.array(cuts))]).tocsr()
    res = linprog(
        np.ones(a.shape[0]), A_ub=lhs, b_ub=-np.concatenate([np.ones(at.shape[0]), rhs]), bounds=(0, 1), method="highs"
    )
    assert res.status == 0, res.message
    return {
        "what": "rank cuts",
        "setting": f"{len(cuts)} discs of {radius:g} m every {step:g} m",
        "value": round(res.fun, 3),
        "bound": "",
        "time_s": round(time.perf_counter() - t0, 1),
    }


def merge_row(
    a: sp.csr_matrix, adj: sp.csr_matrix, groups: tuple[str, ...], plans: list[tuple[int, ...]], work_s: float
) -> dict:
    from planner.solve.connectivity import components, group_members
    from planner.solve.windows import connected_cover_within

    union = np.array(sorted(set().union(*map(set, plans))), dtype=np.int64)
    rows = np.flatnonzero(np.asarray(a[union].sum(axis=0)).ravel() > 0)
    t0 = time.perf_counter()
    got, status, _ = connected_cover_within(
        a.astype(bool).tocsr(), adj.astype(bool).tocsr(), groups, union, rows, np.zeros(0, dtype=np.int64), work_s
    )
    assert got is not None, "no connected plan within the union"
    chosen = got.tolist()
    assert np.all(np.asarray(a[chosen].sum(axis=0)).ravel()[rows] >= 1), "merged plan does not cover"
    assert all(len(components(adj, m)) == 1 for m in group_members(groups, chosen).values()), "merged plan split"
    return {
        "what": "merge",
        "setting": f"union of {len(plans)} plans ({union.size} stations), {work_s:g} s work, "
        f"{status.value} within the union",
        "value": len(chosen),
        "bound": "",
        "time_s": round(time.perf_counter() - t0, 1),
    }
