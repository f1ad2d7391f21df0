"""The plane bound for k views: every piece seen by k distinct stations.

A plan that gives every piece k views from distinct stations is, with x_p = 1 at its stations, a solution of the
cover LP over all positions with right-hand side k (sum over the positions that see t of x_p >= k). That LP is the
k = 1 LP scaled by k: its value is k L1, and any dual y feasible for k = 1 (no position collects more than 1) gives
k sum(y) for k. So k times the plane LP bound that pricing established for k = 1 (the converged LP, or Farley's bound
sum(y) / max(1, w*)) bounds every k-view plan over the plane, before rounding: ceil(k L1 - tolerance). It assumes
what the k = 1 certificate assumes (walls cut into pieces, regions exact to within their tolerance) and uses no
registration rule; the scope is said as ``plane, k = K``.
"""

from __future__ import annotations

import math
from dataclasses import replace

from planner.bounds.plane import ASSUMES, PricingReport
from planner.solve.result import SolveResult, Status

#: the slack of the rounding (as for k = 1)
ROUND_TOL = 1e-6


def k_plane_bound(plane_lp_bound: float, k: int) -> int:
    """ceil(k L1 - tolerance): no plan giving every piece k views from distinct stations anywhere has fewer."""
    if k < 1:
        raise ValueError(f"k must be at least 1, got {k}")
    return math.ceil(k * plane_lp_bound - ROUND_TOL)


def scope_words(k: int) -> str:
    """The scope of the plane bound as printed: ``plane`` for k = 1, ``plane, k = K`` else."""
    return "plane" if k == 1 else f"plane, k = {k}"


def with_k_plane_bound(result: SolveResult, pricing: PricingReport, k: int) -> SolveResult:
    """The MILP result of a k-view plan with ``info['plane_bound']`` = :func:`k_plane_bound` of pricing's k = 1 bound,
    ``info['pool_bound']`` (the MILP's own), the certificate with its ``scope`` and ``k``, and ``bound_scope``:
    ``plane`` when the plan meets the bound (``bound`` becomes it), else ``pool``."""
    info = dict(result.info)
    info["pricing"] = pricing.to_dict()
    plane = k_plane_bound(pricing.plane_lp_bound, k)
    info["pool_bound"] = result.bound
    info["plane_bound"] = plane
    info["plane_bound_scope"] = scope_words(k)
    info["certificate"] = {
        "assumes": ASSUMES,
        "tolerance_m": pricing.tolerance_m,
        "scope": scope_words(k),
        "k": k,
        "plane_bound_from": f"{k} x the plane LP bound for one view ({pricing.plane_lp_bound:.6f}; Farley's bound on "
        "the cover LP's duals over the closed arrangement of the coverage regions grown by the tolerance), rounded up: "
        "a plan with k views of every piece from distinct stations solves the cover LP with right-hand side k "
        "(registration not used)",
    }
    proven = result.objective is not None and result.objective <= plane + 1e-9
    info["bound_scope"] = "plane" if proven else "pool"
    if proven:
        return replace(result, status=Status.OPTIMAL, bound=float(plane), info=info)
    return replace(result, info=info)
