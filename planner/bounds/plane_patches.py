"""Patches of the plane and arcs of a ring, for the connected plane bound (:mod:`planner.bounds.plane_ring`).

A patch is a square of side h on a grid over a zone-side's grown regions. :func:`patch_sets` gives what each may see (U,
the pieces whose grown outer region holds its centre) and what it surely sees (low, the wall length of the pieces whose
shrunk region holds it), by a scan line down each column of centres (:func:`interior_runs`, the sets
``shapely.contains_xy`` gives, in runs of centres); :func:`planner.solve.ring.cyclic_arcs` the smallest arc of the ring
that holds each U; :func:`undominated` keeps the patches no other holds; :func:`arc_links` joins the arcs the overlap
rule may join.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
import shapely
from numpy.typing import NDArray

from planner.coverage.arrangement import grown
from planner.coverage.threads import Background

Ints = NDArray[np.int64]
Floats = NDArray[np.float64]

#: the first patch side gives about this many patches over the zone-side's box; then halved, twice
FIRST_PATCHES = 20_000
#: no patch side below this (m)
MIN_PATCH_M = 0.02
#: at most this many patch centres (the grid over a zone-side's grown regions) per zone-side and patch side; past it
#: that side and the finer ones are skipped
MAX_PATCHES = 250_000
#: segments per quarter circle of the shrunk regions; the shrink is divided by cos(pi / (4 * this))
_ERODE_SEGS = 16
#: centres within this share of the coordinates' scale of a crossing are tested by GEOS (:func:`interior_runs`)
_TIE = 1e-12


@dataclass(frozen=True)
class SidePieces:
    """One zone-side's pieces in their cyclic order: their outer and inner regions as drawn (O_t, R_t), lengths, which
    of them a plan must cover, and the regions' tolerances (``grow_m`` outward, ``shrink_m`` inward)."""

    outer: list[Any]
    inner: list[Any]
    lengths: NDArray[np.float64]
    required: NDArray[np.bool_]
    grow_m: float
    shrink_m: float
    #: what :meth:`shapes` and :meth:`grid` drew for the first patch side asked (the ring walk's first side, which the
    #: cover over patches takes too)
    _memo: dict[tuple[str, float], Any] = field(default_factory=dict, init=False, repr=False, compare=False)

    def shapes(self, h: float) -> tuple[list[Any], list[Any]]:
        """The outer regions grown (circumscribed) and the inner ones shrunk by their tolerance and half the diagonal of
        a patch of side ``h`` (the shrink divided by the cosine of its chord half-angle, so that it is never short);
        those of the first side asked are kept."""
        if ("shapes", h) in self._memo:
            got: tuple[list[Any], list[Any]] = self._memo["shapes", h]
            return got
        drawn = self._shapes(h)
        if not any(k[0] == "shapes" for k in self._memo):  # the first side only, as :meth:`grid`
            self._memo["shapes", h] = drawn
        return drawn

    def grid(self, h: float) -> tuple[sp.csr_matrix, NDArray[np.float64], Floats, Floats] | None:
        """:func:`patch_grid` of the patches of side ``h`` over :meth:`shapes`. Only the first side asked is kept (the
        first, coarsest side the ring walk and the cover over patches both take; a finer side's sets run to tens of
        megabytes)."""
        got: tuple[sp.csr_matrix, NDArray[np.float64], Floats, Floats] | None
        if ("grid", h) in self._memo:
            got = self._memo["grid", h]
            return got
        got = patch_grid(*self.shapes(h), self.lengths, h)
        if not any(k[0] == "grid" for k in self._memo):
            self._memo["grid", h] = got
        return got

    def _shapes(self, h: float) -> tuple[list[Any], list[Any]]:
        half = h * math.sqrt(0.5)
        d = (self.shrink_m + half) / math.cos(math.pi / (4 * _ERODE_SEGS))
        inner = np.asarray(self.inner, dtype=object)
        with Background() as later:  # the two buffers side by side
            shrunk = later.start(shapely.buffer, inner, -d, quad_segs=_ERODE_SEGS)
            return grown(self.outer, self.grow_m + half), list(shrunk.result())


def live_box(geoms: list[Any]) -> NDArray[np.float64] | None:
    """(xmin, ymin, xmax, ymax) over the non-empty ``geoms``; None when all are empty."""
    b = shapely.bounds(np.asarray(geoms, dtype=object)).reshape(-1, 4)
    b = b[~shapely.is_empty(np.asarray(geoms, dtype=object)).reshape(-1)]
    return None if b.size == 0 else np.array([b[:, 0].min(), b[:, 1].min(), b[:, 2].max(), b[:, 3].max()])


def grid_shape(box: NDArray[np.float64], h: float) -> tuple[int, int]:
    """Columns and rows of the grid of side ``h`` from the box's lower-left corner that covers it."""
    return math.ceil((box[2] - box[0]) / h) + 1, math.ceil((box[3] - box[1]) / h) + 1


def patch_sets(
    grow: list[Any], shrink: list[Any], lengths: NDArray[np.float64], h: float
) -> tuple[sp.csr_matrix, NDArray[np.float64]] | None:
    """U (patches x pieces) and l (per patch) on the grid of side ``h`` over the grown regions' bounds; None past
    ``MAX_PATCHES``. ``grow``/``shrink``: regions already grown / shrunk by the tolerance and half the diagonal. A
    centre is in U's row of a piece when it lies in the interior of the piece's grown region, and adds the piece's
    length to l when it lies in the interiors of both regions (:func:`interior_runs`: as ``shapely.contains_xy``)."""
    got = patch_grid(grow, shrink, lengths, h)
    return None if got is None else got[:2]


def patch_grid(
    grow: list[Any], shrink: list[Any], lengths: NDArray[np.float64], h: float
) -> tuple[sp.csr_matrix, NDArray[np.float64], Floats, Floats] | None:
    """:func:`patch_sets` and the centres (x, y) of its patches, in its rows' order."""
    box = live_box(grow)
    if box is None:
        return None
    x0, y0 = box[:2]
    nx_, ny_ = grid_shape(box, h)
    if nx_ * ny_ > MAX_PATCHES:
        return None
    grid = _Grid(float(x0), float(y0), h, nx_, ny_)
    boxes = grid.boxes(grow)
    g0, g1 = interior_runs(grow, boxes, grid)
    s0, s1 = interior_runs(shrink, boxes, grid)
    # the runs of both: each shrunk run against the grown runs it meets (both sorted and disjoint)
    first, last = np.searchsorted(g1, s0, side="right"), np.searchsorted(g0, s1, side="left")
    r, at = _expand(first, np.maximum(last - first, 0))
    w0, w1 = np.maximum(s0[r], g0[at]), np.minimum(s1[r], g1[at])
    k, cell = _cells(g0, g1, grid)
    kw, cw = _cells(w0, w1, grid)
    # summed in order of k (bincount adds in its input's order), as a loop over the pieces adds them
    lsum = np.bincount(cw, weights=lengths[kw], minlength=grid.cells)
    seen = np.bincount(cell, minlength=grid.cells) > 0
    keep = np.flatnonzero(seen)  # the patches that may see a piece
    row = np.cumsum(seen) - 1
    indptr = np.concatenate([[0], np.cumsum(np.bincount(k, minlength=len(grow)))])
    u = sp.csc_matrix((np.ones(cell.size, dtype=bool), row[cell], indptr), shape=(keep.size, len(grow)))
    ci, cj = np.divmod(keep, grid.ny)
    return u.tocsr(), np.asarray(lsum[keep], dtype=np.float64), grid.cx(ci), grid.cy(cj)


def _cells(a: Ints, b: Ints, grid: _Grid) -> tuple[Ints, Ints]:
    """(k, cell) of every key in the runs [a, b) of keys k cells + cell, in order."""
    count = b - a
    k = np.repeat(a // grid.cells, count)
    return k, np.repeat(a % grid.cells - (np.cumsum(count) - count), count) + np.arange(k.size)


@dataclass(frozen=True)
class _Grid:
    """Patch centres x0 + (i + 1/2) h, y0 + (j + 1/2) h for i < nx, j < ny; cell i ny + j."""

    x0: float
    y0: float
    h: float
    nx: int
    ny: int

    @property
    def cells(self) -> int:
        return self.nx * self.ny

    def boxes(self, geoms: list[Any]) -> Ints:
        """Per geometry, the columns and rows (i0, i1, j0, j1, inclusive) whose centres may lie in it: its bounds on
        the grid, cut to the grid (empty geometries: an empty box)."""
        b = shapely.bounds(np.asarray(geoms, dtype=object))
        b = np.where(np.isnan(b), np.array([self.x0 + self.h, self.y0 + self.h, self.x0, self.y0]), b)
        i0, j0 = np.floor_divide(b[:, 0] - self.x0, self.h), np.floor_divide(b[:, 1] - self.y0, self.h)
        i1 = np.minimum(np.ceil((b[:, 2] - self.x0) / self.h), self.nx - 1)
        j1 = np.minimum(np.ceil((b[:, 3] - self.y0) / self.h), self.ny - 1)
        return np.stack([i0, i1, j0, j1], axis=1).astype(np.int64)

    def cx(self, i: Ints) -> Floats:
        return np.asarray(self.x0 + (i + 0.5) * self.h, dtype=np.float64)

    def cy(self, j: Ints) -> Floats:
        return np.asarray(self.y0 + (j + 0.5) * self.h, dtype=np.float64)


def interior_runs(geoms: list[Any], boxes: Ints, grid: _Grid) -> tuple[Ints, Ints]:
    """The centres within ``boxes[k]`` in the interior of ``geoms[k]`` (exactly ``shapely.contains_xy`` of each, for
    polygonal geometries whose parts do not overlap; others go to it whole), as sorted disjoint runs [a, b) of keys
    k cells + cell.

    A scan line along each column of centres: a polygon part's edges cross the column's line where one end lies at or
    right of it and the other left (a half-open rule, exact on the float centres), and the centres between the 1st and
    2nd, 3rd and 4th ... crossings (sorted) lie inside the part. That is the even-odd count of a ray, which decides
    every centre off the boundary as GEOS does (its ray-crossing count, exact), provided each crossing's y is on the
    right side of the centre: its rounding error is below 12 units in the last place of the coordinates' scale, so a
    centre farther than ``_TIE`` times that scale from every crossing is, and one on a column through a vertex (a
    vertical edge, a vertex touching the line) may be on the boundary. Those centres (none, mostly) are asked of GEOS."""
    arr = np.asarray(geoms, dtype=object)
    poly = np.flatnonzero(np.isin(shapely.get_type_id(arr), (3, 6)) & ~shapely.is_empty(arr))
    other = np.setdiff1d(np.flatnonzero(~shapely.is_empty(arr)), poly)
    parts, pk = shapely.get_parts(arr[poly], return_index=True)
    rings, rp = shapely.get_rings(parts, return_index=True)
    xy, rc = shapely.get_coordinates(rings, return_index=True)
    owner = poly[pk[rp[rc]]]  # the geometry of each vertex
    big = max(1.0, float(np.abs(xy).max(initial=0.0)), abs(grid.x0) + grid.nx * grid.h, abs(grid.y0) + grid.ny * grid.h)
    u = (xy[:, 0] - grid.x0) / grid.h - 0.5  # the column coordinate of each vertex (monotone in x)
    doubt = np.abs(u - np.rint(u)) < max(1e-6, 4 * _TIE * big / grid.h)  # within rounding of a column
    up = np.ceil(u).astype(np.int64)
    ia_v, ib_v = up - doubt, up - 1 + doubt  # columns from / to, one more where in doubt (decided exactly below)
    ia, ib = np.minimum(ia_v[:-1], ia_v[1:]), np.maximum(ib_v[:-1], ib_v[1:])
    a = np.flatnonzero((rc[1:] == rc[:-1]) & (ia <= ib))  # edges (vertex a to a + 1 of one ring) over a column
    part, k = rp[rc[a]], owner[a]
    x1, y1, x2, y2 = xy[a, 0], xy[a, 1], xy[a + 1, 0], xy[a + 1, 1]
    xlo, xhi = np.minimum(x1, x2), np.maximum(x1, x2)
    ia, ib = np.maximum(ia[a], boxes[k, 0]), np.minimum(ib[a], boxes[k, 1])
    e, i = _expand(ia, np.maximum(ib - ia + 1, 0))
    xc = grid.cx(i)
    ok = (xlo[e] <= xc) & (xc < xhi[e])  # the half-open rule, exact
    e, i, xc = e[ok], i[ok], xc[ok]
    yc = y1[e] + (xc - x1[e]) * (y2[e] - y1[e]) / (x2[e] - x1[e])
    order = np.lexsort((yc, i, part[e]))
    e, i, yc = e[order], i[order], yc[order]
    if not (np.array_equal(part[e][0::2], part[e][1::2]) and np.array_equal(i[0::2], i[1::2])):
        raise RuntimeError(
            "plane_patches: a column of centres crosses a ring an odd number of times (a ring not closed)"
        )
    k = k[e]
    first = np.ceil((yc - grid.y0) / grid.h - 0.5).astype(np.int64)  # the first centre above the crossing
    lo, hi = np.maximum(first[0::2], boxes[k[0::2], 2]), np.minimum(first[1::2], boxes[k[0::2], 3] + 1)
    base = (k[0::2] * grid.nx + i[0::2]) * grid.ny
    run0, run1 = (base + lo)[hi > lo], (base + hi)[hi > lo]
    # centres the rounding may put on the wrong side: near a crossing, or on a column through a vertex
    near = np.rint((yc - grid.y0) / grid.h - 0.5).astype(np.int64)
    tie = (np.abs(grid.cy(near) - yc) <= _TIE * big) & (near >= boxes[k, 2]) & (near <= boxes[k, 3])
    dv = np.flatnonzero(doubt)
    vi = np.rint(u[dv]).astype(np.int64)
    vcol = (np.abs(grid.cx(vi) - xy[dv, 0]) <= _TIE * big) & (vi >= boxes[owner[dv], 0]) & (vi <= boxes[owner[dv], 1])
    vi, vk = vi[vcol], owner[dv][vcol]
    wide = np.maximum(boxes[other, 1] - boxes[other, 0] + 1, 0)  # geometries not polygonal: every column
    cols_k = np.concatenate([vk, np.repeat(other, wide)])
    cols_i = np.concatenate([vi, _expand(boxes[other, 0], wide)[1]])
    ask = np.unique(
        np.concatenate([(k[tie] * grid.nx + i[tie]) * grid.ny + near[tie], _column_keys(cols_k, cols_i, boxes, grid)])
    )
    if ask.size == 0:
        return _merged(run0, run1)
    return _asked(run0, run1, ask, geoms, grid)


def _merged(a: Ints, b: Ints) -> tuple[Ints, Ints]:
    """Runs [a, b) sorted and joined where they meet or overlap (the parts of one geometry)."""
    if a.size == 0 or (np.all(a[1:] >= b[:-1]) and np.all(a[1:] > a[:-1])):
        return a, b
    order = np.argsort(a, kind="stable")
    a, b = a[order], b[order]
    reach = np.maximum.accumulate(b)
    new = np.concatenate([[True], a[1:] > reach[:-1]])
    ends = np.concatenate([np.flatnonzero(new)[1:] - 1, [a.size - 1]])
    return a[new], reach[ends]


def _asked(run0: Ints, run1: Ints, ask: Ints, geoms: list[Any], grid: _Grid) -> tuple[Ints, Ints]:
    """The runs with the centres ``ask`` (sorted keys) decided by ``shapely.contains_xy`` instead."""
    k, cell = _cells(run0, run1, grid)
    keys = np.sort(k * grid.cells + cell)
    keys = keys[~np.isin(keys, ask)]
    ak, ac = np.divmod(ask, grid.cells)
    yes = np.zeros(ask.size, dtype=bool)
    for kk in np.unique(ak).tolist():
        run = slice(*np.searchsorted(ak, [kk, kk + 1]))
        ii, jj = np.divmod(ac[run], grid.ny)
        yes[run] = shapely.contains_xy(geoms[kk], grid.cx(ii), grid.cy(jj))
    keys = np.sort(np.concatenate([keys, ask[yes]]))
    return _merged(keys, keys + 1)


def _expand(start: Ints, count: Ints) -> tuple[Ints, Ints]:
    """For runs of ``count[r]`` consecutive integers from ``start[r]``: (r, the integer) of each."""
    r = np.repeat(np.arange(start.size), count)
    step = np.arange(r.size) - np.repeat(np.cumsum(count) - count, count)
    return r, start[r] + step


def _column_keys(k: Ints, i: Ints, boxes: Ints, grid: _Grid) -> Ints:
    """The (k, cell) keys of every centre of column i within box k, for each pair."""
    r, j = _expand(boxes[k, 2], np.maximum(boxes[k, 3] - boxes[k, 2] + 1, 0))
    return (k[r] * grid.nx + i[r]) * grid.ny + j


def undominated(
    start: NDArray[np.int64], span: NDArray[np.int64], low: NDArray[np.float64], n: int
) -> NDArray[np.int64]:
    """Indices of (start, span, low) triples no other holds: m holds p when m's arc holds p's on the ring and low[m] <=
    low[p] (of equal triples the first is kept). O(n^2) over a table of the arcs of the ring: the least ``low`` of every
    arc, with each arc also one turn back, minimised over starts <= s and ends >= e. The table holds ranks of ``low``
    (equal values, equal ranks: the comparisons are those of ``low``) in 16 bits where they fit."""
    full = span >= n - 1
    start, span = np.where(full, 0, start), np.minimum(span, n - 1)  # one name for the whole ring
    order = np.argsort(low, kind="stable")
    distinct = np.concatenate([[True], low[order][1:] != low[order][:-1]])
    rank = np.empty(low.size, dtype=np.int64)
    rank[order] = np.cumsum(distinct) - 1
    top = int(rank.max(initial=0)) + 1  # above every rank: no arc
    kind = np.int16 if top < np.iinfo(np.int16).max else np.int32
    table = np.full((2 * n + 1, 3 * n + 1), top, dtype=kind)  # [s + n, e + n]: arcs with start s in [-n, n), end e
    end = start + span
    s, e = start + n, end + n
    np.minimum.at(table, (s, e), rank.astype(kind))
    np.minimum.at(table, (start, end), rank.astype(kind))  # the copy one turn back
    best = table[s, e]  # the least low of the same arc
    incl = table[:, ::-1]
    np.minimum.accumulate(incl, axis=1, out=incl)  # min over e' >= e
    for row in range(1, table.shape[0]):  # ... and s' <= s, row by row (contiguous)
        np.minimum(table[row - 1], table[row], out=table[row])
    strict = np.minimum(table[s - 1, e], table[s, e + 1])  # another arc holding this one
    full_low = rank[full].min() if full.any() else top
    order = np.lexsort((np.arange(start.size), low, span, start))
    first = np.ones(start.size, dtype=bool)  # the first of each (start, span) with that arc's least low
    ss, sp_ = start[order], span[order]
    first[order[1:]] = (ss[1:] != ss[:-1]) | (sp_[1:] != sp_[:-1])
    keep = first & (rank <= best) & (strict > rank) & ((rank < full_low) | full)
    return np.flatnonzero(keep)


def arc_links(
    start: Ints, span: Ints, low: Floats, cum: Floats, n: int, share: float, most: int | None = None
) -> sp.csr_matrix | None:
    """Relaxed links: arcs sharing wall length > 0 and >= ``share`` min(low) (see the module docstring). ``cum``: prefix
    sums of the piece lengths over three turns (cum[0] = 0), non-decreasing: the shared length of [a, b) and [c, d)
    at a turn, cum[min(b, d)] - cum[max(a, c)] where they overlap, is min(cum[b], cum[d]) - max(cum[a], cum[c]), and
    that is <= 0 where they do not; so it is taken as that difference and 0 if below, summed over the turns in order.
    None once more than ``most`` links are found (the caller gives up past that many)."""
    end = start + span + 1  # exclusive
    top = 3 * n
    turns = [(cum[np.clip(start + k, 0, top)], cum[np.clip(end + k, 0, top)]) for k in (-n, 0, n)]
    order = np.argsort(start, kind="stable")  # blocks of near starts: a turn back or on meets few of them
    rows, cols, found = [], [], 0
    for lo in range(0, start.size, 512):
        blk = order[lo : lo + 512]
        s, e = cum[start[blk, None]], cum[end[blk, None]]
        shared = np.zeros((blk.size, start.size))
        # the arcs a turn back that may reach past the block's first start, and those a turn on that may begin
        # before its last end: elsewhere those turns add 0 (no overlap)
        back = np.flatnonzero(end - n > start[blk].min())
        on = np.flatnonzero(start + n < end[blk].max())
        for (cs, ce), at in zip(turns, (back, None, on)):
            if at is None:
                d = np.minimum(e, ce[None, :])
                d -= np.maximum(s, cs[None, :])
                shared += np.maximum(d, 0.0, out=d)
            elif at.size:
                d = np.minimum(e, ce[None, at])
                d -= np.maximum(s, cs[None, at])
                shared[:, at] += np.maximum(d, 0.0, out=d)
        need = share * np.minimum(low[blk, None], low[None, :])
        link = (shared > 1e-12) & (shared + 1e-9 >= need)
        link[np.arange(blk.size), blk] = False
        r, c = np.nonzero(link)
        rows.append(blk[r])
        cols.append(c)
        found += r.size
        if most is not None and found > most:
            return None
    r, c = np.concatenate(rows), np.concatenate(cols)
    return sp.csr_matrix((np.ones(r.size, dtype=bool), (r, c)), shape=(start.size, start.size))


def patch_sides(outer: list[Any]) -> tuple[float, ...]:
    """The patch sides to try on a zone-side: about ``FIRST_PATCHES`` over its regions' box, then halved twice."""
    b = live_box(outer)
    if b is None:
        return ()
    area = (b[2] - b[0]) * (b[3] - b[1])
    h0 = max(math.sqrt(area / FIRST_PATCHES), MIN_PATCH_M)
    return (h0, h0 / 2, h0 / 4)
