"""The ring walk over short arcs without forming their links: the relaxed links of
:func:`planner.bounds.plane_patches.arc_links` found afresh at each station of the walk, as dominance maxima.

A zone-side seen from outside (polygon A's) gives patches that each see one short run of wall, and its walk tightens as
the patches shrink (13 stations over 3.89-m patches, 14 over 1.94-m ones); there are 14,386 undominated patches at the
finer side, and their links, formed pairwise, are about 29 million. The walk by reach
(:class:`planner.solve.ring_unit.UnitRing`) only needs, per station, each arc's largest reach over its links. For arcs
[A, B) laid on the line (wall length, three turns of the ring) the rule links v and u where they share at least
t = share min(low_v, low_u), that is at least t_v or at least t_u (and more than nothing). Shared >= t_v is
B_u - A_v >= t_v and B_v - A_u >= t_v once u is no shorter than t_v; a u shorter than that lies inside v and then shares
all of itself, at least t_u (low_u is at most u's length): so

    u is linked to v  <=>  (A_u <= B_v - t_v and B_u >= A_v + t_v)  or  (A_u + t_u <= B_v and B_u - t_u >= A_v),

two dominance queries over the copies of the arcs one turn back, none and one on
(:class:`planner.solve.dominance.DominanceMax`). Where every arc spans fewer than (n - 2) / 2 pieces, two arcs meet at
one turn at most (they would otherwise together pass the ring), so each link has one turn, the one at which it shares.
Longer arcs: None, and the caller forms the links.

Thresholds are taken 2e-9 m lower than the rule's own float slack (1e-9 m): a link more only weakens the bound.
Property test: ``tests/bounds/test_arc_reach.py`` (the same walk as the links formed, on random rings).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from planner.solve.dominance import DominanceMax
from planner.solve.ring_unit import UnitRing

#: each threshold lowered by this (m), and at least this (a link shares more than nothing)
_SLACK_M = 2e-9
_SOME_M = 1e-12


def short_arc_ring(
    start: NDArray[np.int64],
    span: NDArray[np.int64],
    low: NDArray[np.float64],
    lengths: NDArray[np.float64],
    required: NDArray[np.bool_],
    share: float,
) -> UnitRing | None:
    """The ring walk over arcs [start, start + span] (start in [0, n)) whose links are those
    :func:`~planner.bounds.plane_patches.arc_links` forms; None where an arc spans (n - 2) / 2 pieces or more, or
    nothing is required."""
    n = lengths.size
    if not required.any() or start.size == 0 or 2 * int(span.max()) + 2 >= n:
        return None
    cum = np.concatenate([[0.0], np.cumsum(np.tile(lengths, 4))])  # turn 0 at index n: copies one turn back stay >= 0
    a, b = cum[start + n], cum[start + span + 1 + n]
    t = np.maximum(share * low - _SLACK_M, _SOME_M)
    # the copies one turn back that reach past the ring's start, all at turn 0, those one turn on that begin before the
    # last arc's end: no other copy shares wall with an arc at turn 0
    back, on = np.flatnonzero(start + span + 1 > n), np.flatnonzero(cum[start + 2 * n] < b.max())
    ua = np.concatenate([cum[start[back]], a, cum[start[on] + 2 * n]])
    ub = np.concatenate([cum[start[back] + span[back] + 1], b, cum[start[on] + span[on] + 1 + 2 * n]])
    ut = np.concatenate([t[back], t, t[on]])
    by_v = DominanceMax(ua, ub, b - t, a + t)  # shares at least t_v
    by_u = DominanceMax(ua + ut, ub - ut, b, a)  # shares at least t_u
    copies = np.concatenate([back, np.arange(start.size), on])
    turns = np.repeat(np.arange(-1, 2, dtype=np.int64) * n, [back.size, start.size, on.size])

    def linked(reach: NDArray[np.int64]) -> NDArray[np.int64]:
        w = reach[copies] + turns
        low_ = np.iinfo(np.int64).min
        return np.maximum(by_v(w, low_), by_u(w, low_))

    return UnitRing(start, start + span, required, linked)
