"""Refusing a connected plan over the plane: a registration group whose pieces no position can link.

Under an overlap rule two registered stations share wall (a shared length > 0), so every piece a connected plan of a
group covers lies in one component of the graph that joins two pieces when one station covers both. Over the plane that
graph is a subgraph of the one that joins two pieces when their outer coverage regions O_t (:mod:`planner.bounds.outer`;
every covering position lies in O_t) meet. When that graph splits a group's pieces into several components, no plan
from any positions in the plane covers the group connected: the refusal (:func:`link_refusal`) holds over the plane. It
is claimed only where the groups are linked by shared wall alone (no link through an opening or a stair).

Where the split falls at a corner (two pieces of different components meet at a wall end), the refusal names it and its
angle. **The corner condition.** Let the corner c of a zone have interior angle a, and let it be convex as seen from the
scan side (an outside corner of a block scanned from outside: a < 180 deg; a re-entrant corner of a room scanned from
inside: a > 180 deg). The walls' normals toward the scan side then turn away from each other by delta = |180 - a|. A
station p that covers a piece of each wall stands in front of both wall lines. Write p - c = d n1 + s (-e1) with n1 the
first wall's normal, e1 its direction away from c, d > 0. If s >= 0 (p is beyond the corner along the first wall), the
incidence at a point c + u e1 of the first wall, atan((s + u) / d), grows with u, so it is at least the incidence at c;
likewise on the second wall. At c the two incidences are the angles from the direction p - c to n1 and to n2, which sum
to at least the angle between n1 and n2, delta. So one of them is at least delta / 2. If s < 0 (p in front of the first
wall itself), p - c is turned from n1 away from n2, so its angle to n2 is delta plus its angle to n1, at least delta, and
p is beyond the corner along the second wall, where the incidence only grows from c. Either way the larger incidence is
at least delta / 2, with equality only at the corner point itself; a piece has points other than c. Hence:

    a station covers pieces of both walls of a convex corner within theta_max only if theta_max > |180 - a| / 2
    (an outside corner of a rectangle, a = 90 deg: theta_max > 45 deg).

The condition is necessary, not sufficient (range, stand-off, the boundary and sight must leave a place as well); the
refusal itself rests on the regions, and says which of the two failed.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Hashable, Sequence

import numpy as np
import scipy.sparse as sp
import shapely
from scipy.sparse.csgraph import connected_components

from planner.bounds.outer import OuterRegions
from planner.candidates.connect import piece_groups
from planner.coverage.matrix import CoverageProblem
from planner.coverage.targets import SIDE_NAME
from planner.coverage.visibility import SightLimits
from planner.site.candidate import Candidate
from planner.site.model import Site

#: a group with more pieces than this is not checked (its outer regions would cost more than the refusal is worth)
MAX_PIECES = 4000
#: piece ends closer than this meet
MEET_M = 1e-6
#: corners named in a refusal at most
SHOWN = 4


def plane_components(regions: Sequence[shapely.Geometry]) -> np.ndarray:
    """Component of each region in the graph joining two regions that meet (an empty region is alone)."""
    n = len(regions)
    tree = shapely.STRtree(list(regions))
    left, right = tree.query(list(regions), predicate="intersects")
    keep = left != right
    graph = sp.csr_matrix((np.ones(int(keep.sum()), dtype=bool), (left[keep], right[keep])), shape=(n, n))
    return connected_components(graph, directed=False)[1]


def corner_turn_deg(t: object, i: int, j: int) -> tuple[float, bool]:
    """The turn (deg) between the scan-side normals of pieces ``i`` and ``j`` that meet at a wall end, and whether
    the corner is convex as seen from the scan side (the normals turn away from each other)."""
    ta: np.ndarray = np.asarray(t.a)  # type: ignore[attr-defined]
    tb: np.ndarray = np.asarray(t.b)  # type: ignore[attr-defined]
    nrm: np.ndarray = np.asarray(t.normal)  # type: ignore[attr-defined]
    if np.hypot(*(ta[j] - tb[i])) >= MEET_M and np.hypot(*(ta[i] - tb[j])) < MEET_M:
        i, j = j, i
    along = tb[i] - ta[i]  # piece i toward the meeting point, then j away from it
    along = along / max(float(np.hypot(*along)), 1e-12)
    cos = float(np.clip(np.dot(nrm[i], nrm[j]), -1.0, 1.0))
    return math.degrees(math.acos(cos)), float(np.dot(along, nrm[j])) > 1e-9


def _meets(t: object, p: np.ndarray, comp: np.ndarray) -> list[tuple[int, int]]:
    """Pairs of pieces of different components that meet at a wall end."""
    a, b = np.asarray(t.a)[p], np.asarray(t.b)[p]  # type: ignore[attr-defined]
    out = []
    for i in range(p.size):
        for j in np.flatnonzero((comp != comp[i]) & (np.hypot(*(a - b[i]).T) < MEET_M)):
            out.append((int(p[i]), int(p[j])))
    return out


def corner_words(t: object, i: int, j: int, theta_max_deg: float) -> tuple[str, str]:
    """Where pieces ``i`` and ``j`` meet, as ``(x, y)``, and the corner's angle with what it asks of theta_max."""
    turn, convex = corner_turn_deg(t, i, j)
    ends = np.asarray(t.a), np.asarray(t.b)  # type: ignore[attr-defined]
    at = ends[0][j] if np.hypot(*(ends[0][j] - ends[1][i])) < MEET_M else ends[0][i]
    side = SIDE_NAME[int(t.side[i])]  # type: ignore[attr-defined]
    a = 180.0 - turn if (side == "outside") == convex else 180.0 + turn
    where, angle = f"({at[0]:.2f}, {at[1]:.2f})", f"interior angle {a:.0f} deg"
    if not convex:
        return where, f"{angle}: no position within the limits covers a piece of each of its walls"
    need = turn / 2.0
    if theta_max_deg <= need + 1e-9:
        return where, (
            f"{angle}: a station covers pieces of both walls of such a corner only if theta_max > |180 - a| / 2 = "
            f"{need:g} deg, and theta_max is {theta_max_deg:g} deg"
        )
    return where, (
        f"{angle}: theta_max {theta_max_deg:g} deg > |180 - a| / 2 = {need:g} deg would allow a link, but no position "
        "within the range limit, the stand area and sight covers a whole piece of each wall"
    )


def corners_line(words: Sequence[tuple[str, str]]) -> str:
    """The corners grouped by what keeps them from a link: ``the corner(s) at P, Q (why)``, at most :data:`SHOWN`
    places each."""
    by: dict[str, list[str]] = {}
    for where, why in words:
        by.setdefault(why, []).append(where)
    parts = []
    for why, places in by.items():
        shown = ", ".join(places[:SHOWN]) + (f" and {len(places) - SHOWN} more" if len(places) > SHOWN else "")
        parts.append(f"the corner{'s' if len(places) > 1 else ''} at {shown} ({why})")
    return "; ".join(parts)


def link_refusal(
    site: Site,
    problem: CoverageProblem,
    limits: SightLimits,
    groups: Callable[[Sequence[Candidate]], tuple[tuple[Hashable, ...], sp.csr_matrix | None]],
    outer: OuterRegions,
    theta_max_deg: float,
) -> str | None:
    """The refusal over the plane (module docstring) of the first registration group that no positions can cover
    connected, in one line; None where none is proven (or the groups are linked through openings)."""
    labels, links = groups(problem.candidates)
    if links is not None and links.nnz:
        return None
    t = problem.targets
    pg = piece_groups(problem.candidates, labels, problem)
    for g in range(int(pg.max()) + 1 if pg.size else 0):
        pieces = np.flatnonzero(pg == g)
        if pieces.size < 2 or pieces.size > MAX_PIECES:
            continue
        drawn = outer.of(site, t, limits, pieces)
        comp = plane_components([drawn[int(k)] for k in pieces])
        parts = int(np.unique(comp).size)
        if parts < 2:
            continue
        k0 = int(pieces[0])
        name = f"{t.zone_ids[int(t.zone[k0])]}/{SIDE_NAME[int(t.side[k0])]}"
        meets = _meets(t, pieces, comp)
        words = list(dict.fromkeys(corner_words(t, i, j, theta_max_deg) for i, j in meets))
        where = corners_line(words) or "pieces of separate walls that no one position covers together"
        return (
            f"no connected plan over the plane: the pieces of {name} fall into {parts} parts that no station anywhere "
            f"can link (no position covers a piece of two parts; outer coverage regions): {where}; try a larger "
            "theta_max, or plan without the overlap rule (--no-overlap)"
        )
    return None
