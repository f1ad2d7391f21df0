"""Patches of the plane and arcs of a ring, for the connected plane bound (:mod:`planner.bounds.plane_ring`).

A patch is a square of side h on a grid over a zone-side's grown regions. :func:`patch_sets` gives what each may see (U,
the pieces whose grown outer region holds its centre) and what it surely sees (low, the wall length of the pieces whose
shrunk region holds it); :func:`planner.solve.ring.cyclic_arcs` the smallest arc of the ring that holds each U;
:func:`undominated` keeps the patches no other holds; :func:`arc_links` joins the arcs the overlap rule may join.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
import shapely
from numpy.typing import NDArray

from planner.coverage.arrangement import grown

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

    def shapes(self, h: float) -> tuple[list[Any], list[Any]]:
        """The outer regions grown (circumscribed) and the inner ones shrunk by their tolerance and half the diagonal of
        a patch of side ``h`` (the shrink divided by the cosine of its chord half-angle, so that it is never short)."""
        half = h * math.sqrt(0.5)
        d = (self.shrink_m + half) / math.cos(math.pi / (4 * _ERODE_SEGS))
        shrunk = shapely.buffer(np.asarray(self.inner, dtype=object), -d, quad_segs=_ERODE_SEGS)
        return grown(self.outer, self.grow_m + half), list(shrunk)


def live_box(geoms: list[Any]) -> NDArray[np.float64] | None:
    """(xmin, ymin, xmax, ymax) over the non-empty ``geoms``; None when all are empty."""
    b = np.array([shapely.bounds(g) for g in geoms if not g.is_empty])
    return None if b.size == 0 else np.array([b[:, 0].min(), b[:, 1].min(), b[:, 2].max(), b[:, 3].max()])


def grid_shape(box: NDArray[np.float64], h: float) -> tuple[int, int]:
    """Columns and rows of the grid of side ``h`` from the box's lower-left corner that covers it."""
    return math.ceil((box[2] - box[0]) / h) + 1, math.ceil((box[3] - box[1]) / h) + 1


def patch_sets(
    grow: list[Any], shrink: list[Any], lengths: NDArray[np.float64], h: float
) -> tuple[sp.csr_matrix, NDArray[np.float64]] | None:
    """U (patches x pieces) and l (per patch) on the grid of side ``h`` over the grown regions' bounds; None past
    ``MAX_PATCHES``. ``grow``/``shrink``: regions already grown / shrunk by the tolerance and half the diagonal."""
    box = live_box(grow)
    if box is None:
        return None
    x0, y0 = box[:2]
    nx_, ny_ = grid_shape(box, h)
    if nx_ * ny_ > MAX_PATCHES:
        return None
    rows, cols = [], []
    lsum = np.zeros(nx_ * ny_)
    for k in (k for k, g in enumerate(grow) if not g.is_empty):
        bx0, by0, bx1, by1 = shapely.bounds(grow[k])
        i0, i1 = int((bx0 - x0) // h), math.ceil((bx1 - x0) / h)
        j0, j1 = int((by0 - y0) // h), math.ceil((by1 - y0) / h)
        gi, gj = np.meshgrid(np.arange(i0, min(i1, nx_ - 1) + 1), np.arange(j0, min(j1, ny_ - 1) + 1), indexing="ij")
        ii, jj = gi.ravel(), gj.ravel()
        cx, cy = x0 + (ii + 0.5) * h, y0 + (jj + 0.5) * h
        inside = shapely.contains_xy(grow[k], cx, cy)
        cell = ii[inside] * ny_ + jj[inside]
        rows.append(cell)
        cols.append(np.full(cell.size, k, dtype=np.int64))
        if not shrink[k].is_empty:
            whole = shapely.contains_xy(shrink[k], cx[inside], cy[inside])
            lsum[cell[whole]] += lengths[k]
    r, c = np.concatenate(rows), np.concatenate(cols)
    u = sp.csr_matrix((np.ones(r.size, dtype=bool), (r, c)), shape=(nx_ * ny_, len(grow)))
    keep = np.flatnonzero(u.getnnz(axis=1))
    return u[keep].tocsr(), lsum[keep]


def undominated(
    start: NDArray[np.int64], span: NDArray[np.int64], low: NDArray[np.float64], n: int
) -> NDArray[np.int64]:
    """Indices of (start, span, low) triples no other holds: m holds p when m's arc holds p's on the ring and low[m] <=
    low[p] (of equal triples the first is kept). O(n^2) over a table of the arcs of the ring: the least ``low`` of every
    arc, with each arc also one turn back, minimised over starts <= s and ends >= e."""
    full = span >= n - 1
    start, span = np.where(full, 0, start), np.minimum(span, n - 1)  # one name for the whole ring
    table = np.full((2 * n + 1, 3 * n + 1), np.inf)  # [s + n, e + n]: arcs with start s in [-n, n), end e
    end = start + span
    np.minimum.at(table, (start + n, end + n), low)
    np.minimum.at(table, (start, end), low)  # the copy one turn back
    incl = np.minimum.accumulate(table[:, ::-1], axis=1)[:, ::-1]  # min over e' >= e
    incl = np.minimum.accumulate(incl, axis=0)  # ... and s' <= s
    s, e = start + n, end + n
    strict = np.minimum(incl[s - 1, e], incl[s, e + 1])  # another arc holding this one
    best = table[s, e]  # the least low of the same arc
    full_low = low[full].min() if full.any() else np.inf
    order = np.lexsort((np.arange(start.size), low, span, start))
    first = np.ones(start.size, dtype=bool)  # the first of each (start, span) with that arc's least low
    ss, sp_ = start[order], span[order]
    first[order[1:]] = (ss[1:] != ss[:-1]) | (sp_[1:] != sp_[:-1])
    keep = first & (low <= best) & (strict > low) & ((low < full_low) | full)
    return np.flatnonzero(keep)


def arc_links(start: Ints, span: Ints, low: Floats, cum: Floats, n: int, share: float) -> sp.csr_matrix:
    """Relaxed links: arcs sharing wall length > 0 and >= ``share`` min(low) (see the module docstring). ``cum``: prefix
    sums of the piece lengths over three turns (cum[0] = 0)."""
    end = start + span + 1  # exclusive
    rows, cols = [], []
    for lo in range(0, start.size, 512):
        s, e = start[lo : lo + 512, None], end[lo : lo + 512, None]
        shared = np.zeros((s.shape[0], start.size))
        for shift in (-n, 0, n):
            a = np.maximum(s, start[None, :] + shift)
            b = np.minimum(e, end[None, :] + shift)
            ok = b > a
            a, b = np.clip(a, 0, 3 * n), np.clip(b, 0, 3 * n)
            shared += np.where(ok, cum[np.maximum(b, a)] - cum[a], 0.0)
        need = share * np.minimum(low[lo : lo + 512, None], low[None, :])
        link = (shared > 1e-12) & (shared + 1e-9 >= need)
        link[np.arange(s.shape[0]), np.arange(lo, lo + s.shape[0])] = False
        r, c = np.nonzero(link)
        rows.append(r + lo)
        cols.append(c)
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
