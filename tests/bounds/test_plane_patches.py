"""The fast parts of the connected plane bound equal their plain versions (kept here as references), on small random
inputs: the bound's values must not move when they are sped up.

- ``patch_sets`` (a column scan line over the grid, centres in doubt asked of GEOS) gives the same U and the same
  float low as ``shapely.contains_xy`` per piece and centre, on random polygons, holes, multipolygons, empty regions
  and regions whose vertices sit on patch centres (the boundary cases the scan line hands to GEOS).
- ``undominated`` (a table of 16-bit ranks) keeps the same triples as the float table it replaced.
- ``arc_links`` (shared lengths from the order of ``cum``) gives the same links as the clipped index sums.

(The unit-cost walk by reach against ``RingGraph.walk`` at unit costs: ``tests/solve/test_ring_unit.py``.)
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
import scipy.sparse as sp
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from planner.bounds.plane_patches import MAX_PATCHES, arc_links, grid_shape, live_box, patch_sets, undominated
from tests.bounds.test_plane_ring import QUICK

# ---- references: the implementations the fast ones replaced, verbatim but for names ----


def ref_patch_sets(
    grow: list[Any], shrink: list[Any], lengths: NDArray[np.float64], h: float
) -> tuple[sp.csr_matrix, NDArray[np.float64]] | None:
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


def ref_undominated(
    start: NDArray[np.int64], span: NDArray[np.int64], low: NDArray[np.float64], n: int
) -> NDArray[np.int64]:
    full = span >= n - 1
    start, span = np.where(full, 0, start), np.minimum(span, n - 1)
    table = np.full((2 * n + 1, 3 * n + 1), np.inf)
    end = start + span
    np.minimum.at(table, (start + n, end + n), low)
    np.minimum.at(table, (start, end), low)
    incl = np.minimum.accumulate(table[:, ::-1], axis=1)[:, ::-1]
    incl = np.minimum.accumulate(incl, axis=0)
    s, e = start + n, end + n
    strict = np.minimum(incl[s - 1, e], incl[s, e + 1])
    best = table[s, e]
    full_low = low[full].min() if full.any() else np.inf
    order = np.lexsort((np.arange(start.size), low, span, start))
    first = np.ones(start.size, dtype=bool)
    ss, sp_ = start[order], span[order]
    first[order[1:]] = (ss[1:] != ss[:-1]) | (sp_[1:] != sp_[:-1])
    keep = first & (low <= best) & (strict > low) & ((low < full_low) | full)
    return np.flatnonzero(keep)


def ref_arc_links(start, span, low, cum, n, share) -> sp.csr_matrix:
    end = start + span + 1
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


# ---- random regions ----

H = 0.5  # patch side of the random grids; vertices snapped to multiples of H / 2 land on centres and patch edges


def _region(draw: Any, snap: bool) -> Any:
    """A polygon, a polygon with a hole, a multipolygon, a buffered line or an empty region, in [0, 6]^2."""
    kind = draw(st.sampled_from(["poly", "hole", "multi", "line", "empty", "box"]))
    coord = st.floats(0.0, 6.0, allow_nan=False)
    if snap:
        coord = st.integers(0, 24).map(lambda v: v * H / 4)

    def points(k: int) -> list[tuple[float, float]]:
        return [(draw(coord), draw(coord)) for _ in range(k)]

    if kind == "empty":
        return shapely.Polygon()
    if kind == "box":
        (a, b), (c, d) = points(2)
        return shapely.box(min(a, c), min(b, d), max(a, c) + H / 2, max(b, d) + H / 2)
    if kind == "line":
        return shapely.LineString(points(3)).buffer(draw(st.sampled_from([0.3, H / 2, 0.7])), quad_segs=2)
    g = shapely.make_valid(shapely.Polygon(points(draw(st.integers(3, 7))))).buffer(0)
    if kind == "hole" and not g.is_empty:
        g = g.difference(g.centroid.buffer(0.4, quad_segs=2))
    if kind == "multi":
        g = g.union(shapely.Point(points(1)[0]).buffer(0.6, quad_segs=3))
    return g


@st.composite
def regions(draw: Any) -> tuple[list[Any], list[Any], NDArray[np.float64]]:
    snap = draw(st.booleans())
    n = draw(st.integers(1, 6))
    grow = [_region(draw, snap) for _ in range(n)]
    shrink = [g.buffer(-draw(st.sampled_from([0.0, 0.1, H / 2]))) if not g.is_empty else g for g in grow]
    if draw(st.booleans()):  # a shrunk region that is not inside its grown one
        shrink[0] = _region(draw, snap)
    lengths = np.array([draw(st.sampled_from([0.1, 0.2, 0.3, 1.0 / 3.0, 2.5])) for _ in range(n)])
    return grow, shrink, lengths


@settings(QUICK, max_examples=50)
@given(case=regions(), h=st.sampled_from([H, 0.3, 0.7]))
def test_patch_sets_equal_contains_xy(case: tuple[list[Any], list[Any], NDArray[np.float64]], h: float) -> None:
    grow, shrink, lengths = case
    want, got = ref_patch_sets(grow, shrink, lengths, h), patch_sets(grow, shrink, lengths, h)
    assert (want is None) == (got is None)
    if want is None or got is None:
        return
    (uw, lw), (ug, lg) = want, got
    assert uw.shape == ug.shape and (uw != ug).nnz == 0
    assert np.array_equal(lw, lg)  # the same floats: summed in the same order


# the full-strength run is in the slow tier, marked here rather than by a decorator: hypothesis derandomises
# a property by its source, decorators included, so a marker line would change the cases it has always run
test_patch_sets_equal_contains_xy = pytest.mark.slow(test_patch_sets_equal_contains_xy)


@settings(QUICK, max_examples=12)
@given(case=regions(), h=st.sampled_from([H, 0.3, 0.7]))
def test_patch_sets_equal_contains_xy_on_fewer_cases(case, h):
    # the quick twin: the body of the test above on 12 cases (the test above runs 50, in the slow tier)
    test_patch_sets_equal_contains_xy.hypothesis.inner_test(case=case, h=h)


def test_patch_sets_on_centres_and_edges_of_the_grid() -> None:
    # centres at 0.5, 1.0, 1.5, 2.0 each way (the grid starts at the regions' corner, 0.25): the first square holds all
    # 16; the diamond's sides run through 8 centres (on its boundary: outside, as contains_xy) and it holds 4; the
    # second square's sides run along columns and rows of centres (vertex columns, asked of GEOS): 4 inside
    sq = shapely.box(0.25, 0.25, 2.25, 2.25)
    diamond = shapely.Polygon([(1.25, 0.25), (2.25, 1.25), (1.25, 2.25), (0.25, 1.25)])
    edges = shapely.box(0.5, 0.5, 2.0, 2.0)
    grow = [sq, diamond, edges]
    lengths = np.array([1.0, 2.0, 4.0])
    want, got = ref_patch_sets(grow, grow, lengths, H), patch_sets(grow, grow, lengths, H)
    assert want is not None and got is not None
    assert (want[0] != got[0]).nnz == 0 and np.array_equal(want[1], got[1])
    assert want[0].getnnz(axis=0).tolist() == [16, 4, 4]


@settings(QUICK, max_examples=150)
@given(
    n=st.integers(2, 20),
    items=st.lists(st.tuples(st.integers(0, 19), st.integers(0, 19), st.integers(0, 5)), min_size=1, max_size=40),
)
def test_undominated_equals_the_float_table(n: int, items: list[tuple[int, int, int]]) -> None:
    start = np.array([s % n for s, _, _ in items])
    span = np.array([k % n for _, k, _ in items])
    low = np.array([w / 3.0 for _, _, w in items])
    assert np.array_equal(undominated(start, span, low, n), ref_undominated(start, span, low, n))


# the full-strength run is in the slow tier, marked here rather than by a decorator: hypothesis derandomises
# a property by its source, decorators included, so a marker line would change the cases it has always run
test_undominated_equals_the_float_table = pytest.mark.slow(test_undominated_equals_the_float_table)


@settings(QUICK, max_examples=40)
@given(
    n=st.integers(2, 20),
    items=st.lists(st.tuples(st.integers(0, 19), st.integers(0, 19), st.integers(0, 5)), min_size=1, max_size=40),
)
def test_undominated_equals_the_float_table_on_fewer_cases(n, items):
    # the quick twin: the body of the test above on 40 cases (the test above runs 150, in the slow tier)
    test_undominated_equals_the_float_table.hypothesis.inner_test(n=n, items=items)


@settings(QUICK, max_examples=120)
@given(
    n=st.integers(2, 20),
    items=st.lists(st.tuples(st.integers(0, 19), st.integers(0, 19), st.integers(0, 5)), min_size=1, max_size=30),
    lengths=st.lists(st.sampled_from([0.0, 0.1, 0.2, 0.3, 1.0 / 3.0, 1.5]), min_size=20, max_size=20),
    share=st.sampled_from([0.0, 0.1, 0.3, 0.5]),
)
def test_arc_links_equal_the_index_sums(
    n: int, items: list[tuple[int, int, int]], lengths: list[float], share: float
) -> None:
    start = np.array([s % n for s, _, _ in items])
    span = np.array([k % n for _, k, _ in items])
    low = np.array([w / 3.0 for _, _, w in items])
    cum = np.concatenate([[0.0], np.cumsum(np.tile(np.array(lengths[:n]), 3))])
    got, want = arc_links(start, span, low, cum, n, share), ref_arc_links(start, span, low, cum, n, share)
    assert (got != want).nnz == 0


# the full-strength run is in the slow tier, marked here rather than by a decorator: hypothesis derandomises
# a property by its source, decorators included, so a marker line would change the cases it has always run
test_arc_links_equal_the_index_sums = pytest.mark.slow(test_arc_links_equal_the_index_sums)


@settings(QUICK, max_examples=30)
@given(
    n=st.integers(2, 20),
    items=st.lists(st.tuples(st.integers(0, 19), st.integers(0, 19), st.integers(0, 5)), min_size=1, max_size=30),
    lengths=st.lists(st.sampled_from([0.0, 0.1, 0.2, 0.3, 1.0 / 3.0, 1.5]), min_size=20, max_size=20),
    share=st.sampled_from([0.0, 0.1, 0.3, 0.5]),
)
def test_arc_links_equal_the_index_sums_on_fewer_cases(n, items, lengths, share):
    # the quick twin: the body of the test above on 30 cases (the test above runs 120, in the slow tier)
    test_arc_links_equal_the_index_sums.hypothesis.inner_test(n=n, items=items, lengths=lengths, share=share)
