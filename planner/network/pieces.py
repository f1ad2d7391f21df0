"""The accuracy check of every covered wall piece, from its stations' adjusted position errors.

For every target the plan covers, e = sqrt(sigma_0^2 + sigma_c^2 + sigma_g^2 + sigma_meas(S, theta)^2) (2.13, with the
site's incidence model, see :func:`planner.instrument.accuracy.view_error_m`) with sigma_0 the station's adjusted
position error; in single precision the best station seeing it, in combined precision all of them (1/e^2 = sum 1/e_j^2),
must stay within sigma_req (or the drawing scale's tolerance, table 1.1).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from planner.core.text import finite_or_none
from planner.instrument.accuracy import ErrorBudget, combined_error_m, view_error_m
from planner.site.candidate import Candidate
from planner.site.model import Site


def accuracy_check(
    site: Site,
    stations: Sequence[Candidate],
    problem: Any,
    sigma: dict[str, float],
    scanner: Any,
    combined: bool = False,
) -> dict[str, Any]:
    """Point error of every covered piece from its best station (or all its stations combined), against sigma_req (see
    module docstring)."""
    p = site.parameters
    t = problem.targets
    e_best, who, theta = _best_errors(site, stations, problem, sigma, scanner, combined)
    covered = who >= 0
    fail = covered & (e_best > p.sigma_req_m)
    bad_st = sorted({stations[w].id for w in who[fail]})
    finite = e_best[covered & np.isfinite(e_best)]
    return {
        "sigma_req_m": p.sigma_req_m,
        "drawing_scale": p.drawing_scale,
        "targets": int(covered.sum()),
        "precision": "combined" if combined else "single",
        "incidence_model": p.incidence_model,
        "failing_targets": int(fail.sum()),
        "unseen_targets": int((~covered).sum()),
        # a piece no station sees is no pass: the check is of the wall, not of the pieces that happen to be seen
        "pass": not bool(fail.any()) and bool(covered.all()),
        # the worst finite error; pieces seen by untied stations only have none and are counted apart
        "worst_e_m": float(finite.max()) if finite.size else None,
        "untied_targets": int((covered & ~np.isfinite(e_best)).sum()),
        "zones": _zones(t, covered, fail, e_best),
        "failing_stations": bad_st,
        "failing_target_ids": [t.label(i) for i in np.flatnonzero(fail)[:50]],
        "worst_targets": [
            {
                "target": t.label(i),
                "station": stations[who[i]].id,
                "e_m": finite_or_none(float(e_best[i])),
                "untied": not math.isfinite(e_best[i]),
                "incidence_deg": float(theta[i]),
            }
            for i in np.argsort(-np.where(covered, e_best, -1.0))[:20]
            if covered[i]
        ],
        "suggestions": _suggestions(bad_st, sigma, p.sigma_req_m),
    }


def _best_errors(
    site: Site, stations: Sequence[Candidate], problem: Any, sigma: dict[str, float], scanner: Any, combined: bool
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.float64]]:
    """Per target: its point error e (m; inf where no station sees it), the station that sees it best (-1: none) and
    that view's incidence angle (deg)."""
    p = site.parameters
    b = p.budget
    bt = problem.slant_m.T.tocsr()
    inc = problem.incidence_deg.T.tocsr()
    n = len(problem.targets)
    # the view error without the station term, for every pair at once; the station's own sigma_0 is added below
    rest = ErrorBudget(0.0, b.centring_m, b.graphical_m)
    e_view = view_error_m(bt.data, inc.data, scanner, rest, p.incidence_model)
    s0_all = np.array([sigma.get(s.id, np.inf) for s in stations] or [0.0])
    e_best = np.full(n, np.inf)
    who = np.full(n, -1)
    theta = np.full(n, np.nan)
    for k in range(n):
        lo, hi = bt.indptr[k], bt.indptr[k + 1]
        if hi == lo:
            continue
        cols = bt.indices[lo:hi]
        e = np.sqrt(s0_all[cols] ** 2 + e_view[lo:hi] ** 2)
        j = int(np.argmin(e))
        e_best[k], who[k] = (combined_error_m(e) if combined else e[j]), cols[j]
        theta[k] = inc.data[lo + j]
    return e_best, who, theta


def _zones(t: Any, covered: NDArray[np.bool_], fail: NDArray[np.bool_], e_best: NDArray[np.float64]) -> list[dict]:
    """The verdict of each zone-side with a covered piece."""
    zones = []
    for zi, zid in enumerate(t.zone_ids):
        for side in (0, 1):
            m = covered & (t.zone == zi) & (t.side == side)
            if m.any():
                worst = float(e_best[m].max())  # infinite: some piece is seen by untied stations only
                zones.append(
                    {
                        "zone": zid,
                        "side": ["inside", "outside"][side],
                        "pass": not bool((fail & m).any()),
                        "worst_e_m": finite_or_none(worst),
                        "untied": not math.isfinite(worst),
                    }
                )
    return zones


def _suggestions(bad_st: list[str], sigma: dict[str, float], sigma_req_m: float) -> list[str]:
    """What to change for (at most ten of) the stations whose pieces fail."""
    suggestions = []
    for sid in bad_st[:10]:
        s0_m = float(sigma.get(sid, float("inf")))
        if not math.isfinite(s0_m):
            suggestions.append(
                f"station {sid} is not tied to control: add a control point it sees, or a registration link"
            )
        elif s0_m > sigma_req_m / 2:
            suggestions.append(
                f"station {sid} position error {s0_m * 1000:.1f} mm: add a control point near it or shorten its chain"
            )
        else:
            suggestions.append(f"targets of station {sid} are measured too far: add a station closer to them")
    return suggestions
