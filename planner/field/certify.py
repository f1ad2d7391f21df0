"""The lower bound printed beside the route, and the better of the routing and branch-and-cut orders.

Bounds, each valid for the mode's optimum:

* ``exact (Held-Karp dynamic programme)``: the shortest order, up to :data:`EXACT_MAX_NODES` nodes;
* ``Held-Karp 1-tree, subgradient ascent``: a bound on the shortest order, above that;
* ``branch-and-cut``: the dual bound of :func:`planner.field.scip_order.scip_order` (SCIP, subtour and
  registration cuts), in the mode's own model (so in registration mode it holds the price of the rule).

The shortest order's bounds are bounds on the registration order too (the rule only removes orders). The
largest bound is printed, named by its method. The branch-and-cut runs in registration mode always, and in
shortest mode only where the Held-Karp bound leaves a gap above :data:`GAP_TOLERANCE`; where its order is
shorter than the routing answer, it is taken. (A CP-SAT position model of the same problem, with a far weaker
bound, is kept in the tests as an independent cross-check.)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from planner.field.bound import EXACT_MAX_NODES, exact_order, held_karp_bound
from planner.field.order import TIME_CAP_S, OrderResult
from planner.field.scip_order import NODE_LIMIT, scip_order

GAP_TOLERANCE = 1e-4
HK_EXACT = "exact (Held-Karp dynamic programme)"
HK_TREE = "Held-Karp 1-tree, subgradient ascent"
BC_OPT = "branch-and-cut (SCIP), proven optimal"
BC_BOUND = "branch-and-cut (SCIP), dual bound"


@dataclass(frozen=True)
class Certified:
    """The order (possibly the branch-and-cut one), the bound printed, its method, and every bound computed (method, m)."""

    result: OrderResult
    bound_m: float
    method: str
    bounds: tuple[tuple[str, float], ...]
    scope: str


def certify(
    d: NDArray[np.float64],
    result: OrderResult,
    mode: str,
    neighbours: Sequence[set[int]],
    parts: Sequence[int],
    start_is_station: bool,
    closed: bool,
    node_limit: int = NODE_LIMIT,
    wall_cap_s: float | None = TIME_CAP_S,
) -> Certified:
    """Bound ``result`` (the routing answer) and improve it by branch-and-cut where it helps (see the module text)."""
    n = len(d)
    exact = n <= EXACT_MAX_NODES
    bounds = [
        (HK_EXACT, exact_order(d, closed)[0]) if exact else (HK_TREE, held_karp_bound(d, result.length_m, closed))
    ]
    registration = mode == "registration"
    if n > 2 and (registration or bounds[0][1] < (1.0 - GAP_TOLERANCE) * result.length_m):
        ex = scip_order(
            d, registration, neighbours, parts, start_is_station, closed, result.order, node_limit, wall_cap_s
        )
        bounds.append((BC_OPT if ex.optimal else BC_BOUND, ex.bound_m))
        if ex.order is not None and ex.length_m < result.length_m - 1e-9:
            result = replace(result, order=ex.order, length_m=ex.length_m)
        if ex.capped:
            result = replace(result, capped=True)
    method, bound = max(bounds, key=lambda mb: mb[1])
    scope = "registration-order route" if method.startswith("branch-and-cut") and registration else "shortest route"
    if registration and scope == "shortest route":
        scope += " (a bound on the registration order too)"
    return Certified(result, min(bound, result.length_m), method, tuple(bounds), scope)
