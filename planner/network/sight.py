"""Many sight lines at once: for each pair p-q, the answer of :func:`planner.network.graph.intervisible`.

1. a segment that crosses or touches an edge (GEOS, exact, against all edges at once, prepared) is blocked:
   :func:`planner.coverage.visibility.segments_touch` says so too, its tolerance (``EPS_SIGHT_M``) only adding touches;
2. any other segment is tested with ``segments_touch`` itself, against only the edges that could touch it: those within
   ``MARGIN_M`` of it, and those whose LINE passes within the tolerance of an end of the segment (its side rule counts
   such an end as on the line).

Any other edge gives no touch: the segment's ends lie strictly on one side of its line, or it crosses the segment (step
1) or comes within the tolerance of it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
import shapely
from numpy.typing import NDArray

from planner.coverage.matrix import blockers_for
from planner.coverage.visibility import EPS_SIGHT_M, _side, _signed, segments_touch
from planner.site.model import Site

#: an edge this close to a segment is tested (the test's tolerance, with room for rounding)
MARGIN_M = 2 * EPS_SIGHT_M + 1e-6
#: entries of the (points x edges) table of distances to the edges' lines formed at a time
CHUNK = 4_000_000
#: pairs tested at a time
PAIRS = 200_000
#: blockers of the last sites asked, by site and frame
_BLOCKERS: dict[tuple[int, str], tuple[Site, Any]] = {}
#: the edges' search trees, by the blockers they index (kept with them: ids are reused)
_TREES: dict[int, tuple[Any, shapely.STRtree, Any]] = {}


def blockers(site: Site, frame: str) -> Any:
    """The walls and obstacle edges of a frame (:func:`planner.coverage.matrix.blockers_for`), built once per site and
    frame (a site is immutable)."""
    hit = _BLOCKERS.get((id(site), frame))
    if hit is None or hit[0] is not site:
        if len(_BLOCKERS) > 32:
            _BLOCKERS.clear()
        hit = _BLOCKERS[(id(site), frame)] = (site, blockers_for(site, frame))
    return hit[1]


def _index(b: Any) -> tuple[shapely.STRtree, Any]:
    """The edges' search tree, and all edges as one prepared geometry."""
    hit = _TREES.get(id(b))
    if hit is None or hit[0] is not b:
        if len(_TREES) > 32:
            _TREES.clear()
        lines = shapely.linestrings(np.stack([b.a, b.b], axis=1))
        every = shapely.multilinestrings(lines)
        shapely.prepare(every)
        hit = _TREES[id(b)] = (b, shapely.STRtree(lines), every)
    return hit[1], hit[2]


def _near_lines(pts: NDArray[np.float64], b: Any) -> sp.csr_matrix:
    """(points x edges): True where the point lies within the tolerance of the edge's line."""
    n_edges = len(b.a)
    step = max(1, CHUNK // max(n_edges, 1))
    rows, cols = [np.zeros(0, dtype=np.int64)], [np.zeros(0, dtype=np.int64)]
    for k0 in range(0, len(pts), step):
        chunk = pts[k0 : k0 + step]
        p = np.repeat(chunk, n_edges, axis=0)
        r, s = np.tile(b.a, (len(chunk), 1)), np.tile(b.b, (len(chunk), 1))
        on = np.flatnonzero(_side(_signed(r, s, p), EPS_SIGHT_M) == 0)
        rows.append(k0 + on // n_edges)
        cols.append(on % n_edges)
    r_, c_ = np.concatenate(rows), np.concatenate(cols)
    return sp.csr_matrix((np.ones(len(r_), dtype=bool), (r_, c_)), shape=(len(pts), n_edges))


def sight_clear(site: Site, frame: str, p: NDArray[np.float64], q: NDArray[np.float64]) -> NDArray[np.bool_]:
    """``intervisible(site, frame, p[k], q[k])`` for every row k of the segments' ends ``p``, ``q`` (m x 2): True when
    no wall or obstacle edge of ``frame`` touches the segment."""
    p = np.asarray(p, dtype=float).reshape(-1, 2)
    q = np.asarray(q, dtype=float).reshape(-1, 2)
    m = len(p)
    clear = np.ones(m, dtype=bool)
    b = blockers(site, frame)
    if m == 0 or len(b.a) == 0:
        return clear
    tree, every = _index(b)
    n_edges = len(b.a)
    for k0 in range(0, m, PAIRS):
        k1 = min(m, k0 + PAIRS)
        lines = shapely.linestrings(np.stack([p[k0:k1], q[k0:k1]], axis=1))
        crossed = shapely.intersects(every, lines)
        clear[k0:k1] = ~crossed
        rest = k0 + np.flatnonzero(~crossed)
        close = rest[shapely.dwithin(every, lines[rest - k0], MARGIN_M)]
        seg, edge = tree.query(lines[close - k0], predicate="dwithin", distance=MARGIN_M)
        pts, inv = np.unique(np.vstack([p[rest], q[rest]]), axis=0, return_inverse=True)
        inv = inv.ravel()
        near = _near_lines(pts, b)
        on_line = (near[inv[: len(rest)]] + near[inv[len(rest) :]]).tocoo()
        key = np.unique(
            np.concatenate(
                [
                    close[seg].astype(np.int64) * n_edges + edge,
                    rest[on_line.row].astype(np.int64) * n_edges + on_line.col,
                ]
            )
        )
        k, e = key // n_edges, key % n_edges
        hit = segments_touch(p[k], q[k], b.a[e], b.b[e])
        clear[k[hit]] = False
    return clear
