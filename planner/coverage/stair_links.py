"""Registration links through a stair: a station of the lower storey and one of the upper storey that both see the
stair.

The storeys of a building model stand in frames of their own, so no wall is seen from both and cloud-to-cloud
registration has nothing to work on across them. A stair is what both storeys share: targets set up on it are seen from
below, beside the flight, and from above, at the stairwell's edge; as for a door (:mod:`planner.coverage.links`),
target-based registration then needs both stations to see the same targets. So a stair link is measured as:

- station a stands in the stair's lower zone, station b in its upper zone (``Stair.lower_zone``, ``upper_zone``; each in
  its own frame);
- the stair's edge is the outline of its footprint moved ``EDGE_OFFSET_M`` outwards (beside the stair, in the room, not
  on the stair's own wall), with a point every ``EDGE_STEP_M`` along it;
- a station sees an edge point when it is at most ``reach_m`` away and the plan-view sight line to it is clear in the
  station's own frame (its walls, the stair's notch among them);
- a and b are linked when some edge point is seen by both: a target set there is in both fields of view.

The plan view does not check the height: the slab above the room below and the stair's own flight are not modelled (the
stair is a block of the lower room, the stairwell a void beside the upper room), so the rule says where targets on the
stair can be placed for both, not that a given step is seen from both.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp
import shapely
from numpy.typing import NDArray

from planner.coverage.matrix import blockers_for
from planner.coverage.visibility import sight_clear
from planner.site.model import Site
from planner.site.stairs import Stair

#: the stair's edge points stand this far outside its footprint (m)
EDGE_OFFSET_M = 0.1
#: and this far apart along it (m)
EDGE_STEP_M = 0.25
#: pair key of a station-to-point sight line (matches no wall key, and not the obstacles' -1)
NO_WALL = -2


def stair_edge(stair: Stair) -> NDArray[np.float64]:
    """The stair's edge points (P x 2): its footprint's outline moved ``EDGE_OFFSET_M`` outwards, a point every
    ``EDGE_STEP_M`` along it (at least 8)."""
    ring = shapely.Polygon(stair.footprint).buffer(EDGE_OFFSET_M, join_style="mitre").exterior
    n = max(8, int(np.ceil(ring.length / EDGE_STEP_M)))
    pts = shapely.line_interpolate_point(ring, np.linspace(0.0, ring.length, n, endpoint=False))
    return np.asarray(shapely.get_coordinates(pts), dtype=float)


def edge_seen(
    site: Site, frame: str, xy: NDArray[np.float64], edge: NDArray[np.float64], reach_m: float
) -> sp.csr_matrix:
    """S x P boolean: station s (``xy``, in ``frame``) sees edge point p (within ``reach_m``, sight clear)."""
    s, p = (g.ravel() for g in np.meshgrid(np.arange(len(xy)), np.arange(len(edge)), indexing="ij"))
    near = np.hypot(*(xy[s] - edge[p]).T) <= reach_m
    s, p = s[near], p[near]
    if s.size:
        ok = sight_clear(xy[s], edge[p], edge[p], np.full(len(s), NO_WALL), blockers_for(site, frame))
        s, p = s[ok], p[ok]
    return sp.csr_matrix((np.ones(len(s), dtype=bool), (s, p)), shape=(len(xy), len(edge)))


def stair_links(site: Site, xy: NDArray[np.float64], spaces: Sequence[object], reach_m: float) -> sp.csr_matrix:
    """Symmetric C x C boolean matrix: stations of a stair's lower and upper zone that see a common point of its edge
    (see the module docstring). ``spaces``: each station's space (``("in", zone id)`` inside)."""
    rows: list[NDArray[np.int64]] = []
    cols: list[NDArray[np.int64]] = []
    for stair in site.stairs:
        edge = stair_edge(stair)
        lo = np.array([k for k, s in enumerate(spaces) if s == ("in", stair.lower_zone)], dtype=np.int64)
        up = np.array([k for k, s in enumerate(spaces) if s == ("in", stair.upper_zone)], dtype=np.int64)
        if not lo.size or not up.size:
            continue
        a = edge_seen(site, site.zone(stair.lower_zone).frame, xy[lo], edge, reach_m)
        b = edge_seen(site, site.zone(stair.upper_zone).frame, xy[up], edge, reach_m)
        both = (a.astype(np.int32) @ b.T.astype(np.int32)).tocoo()
        rows.append(lo[both.row])
        cols.append(up[both.col])
    return link_matrix(rows, cols, len(xy))


def link_matrix(i: list[NDArray[np.int64]], j: list[NDArray[np.int64]], n: int) -> sp.csr_matrix:
    """Symmetric n x n boolean matrix of the pairs (i[k], j[k]) of every pair of arrays given."""
    r = np.concatenate([*i, *j]) if i else np.zeros(0, np.int64)
    c = np.concatenate([*j, *i]) if i else np.zeros(0, np.int64)
    out = sp.csr_matrix((np.ones(len(r), dtype=bool), (r, c)), shape=(n, n))
    out.sum_duplicates()
    return out
