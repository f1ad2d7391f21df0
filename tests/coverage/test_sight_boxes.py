"""The sight test's box filter and the regions drawn on threads: the same answers as the plain ways.

:func:`planner.coverage.visibility.sight_clear` tests the pairs' boxes against every blocker's box directly where the
blockers are few (:data:`~planner.coverage.visibility.DENSE_BLOCKERS`): the pairs an STR-tree of the blockers gives;
:func:`planner.coverage.regions.coverage_regions` draws its chunks on a few threads: the regions drawn on one."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

import planner.coverage.threads as threads
import planner.coverage.visibility as vis
from planner.coverage.matrix import build_coverage
from planner.coverage.regions import coverage_regions
from planner.coverage.targets import make_targets
from planner.coverage.threads import Background, ordered_map
from planner.coverage.visibility import SightLimits, boxes_meeting
from planner.site import ScanSide, Site, Zone
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import Obstacle

# coordinates on a 0.5 grid, so that boxes touch along edges and at corners often
coord = st.integers(0, 24).map(lambda k: k / 2)
box = st.tuples(coord, coord, st.integers(0, 6).map(lambda k: k / 2), st.integers(0, 6).map(lambda k: k / 2))


@settings(max_examples=150, deadline=None, derandomize=True, database=None)
@given(rows=st.lists(box, min_size=1, max_size=30), segs=st.lists(st.tuples(coord, coord, coord, coord), max_size=20))
def test_boxes_meeting_is_the_trees_query(rows, segs) -> None:
    lo = np.array([[x, y] for x, y, _, _ in rows], float)
    hi = lo + np.array([[w, h] for _, _, w, h in rows], float)
    a = np.array([[x, y] for x, y, _, _ in segs], float).reshape(-1, 2)
    b = np.array([[x, y] for _, _, x, y in segs], float).reshape(-1, 2)
    for tree_geoms, blo, bhi in (
        (shapely.linestrings(np.stack([a, b], axis=1)) if len(a) else [], np.minimum(a, b), np.maximum(a, b)),
        (shapely.points(a) if len(a) else [], a, a),
    ):
        want = set()
        if len(a):
            got = shapely.STRtree(tree_geoms).query(shapely.box(lo[:, 0], lo[:, 1], hi[:, 0], hi[:, 1]))
            want = set(zip(*got.tolist()))
        rows_, cols = boxes_meeting(lo, hi, blo, bhi)
        assert set(zip(rows_.tolist(), cols.tolist())) == want


def _site() -> Site:
    """A room with a column and a thin pin, seen from inside, and the blockers a little many."""
    zone = Zone("R", ScanSide.INSIDE, ((0, 0), (20, 0), (20, 14), (9, 14), (9, 20), (0, 20)), (3.0,) * 6)
    col = Obstacle("column", ((9, 5), (11, 5), (11, 7), (9, 7)), 5.0)
    pin = Obstacle("pin", ((4.95, 8.95), (5.05, 8.95), (5.05, 9.05), (4.95, 9.05)), 5.0)
    return Site("boxes", (zone,), obstacles=(col, pin))


def test_sight_with_and_without_the_tree(monkeypatch: pytest.MonkeyPatch) -> None:
    site = _site()
    t = make_targets(site, 1.0)
    xy = [(x + 0.25, y + 0.25) for x in range(1, 20, 2) for y in range(1, 20, 2)]
    cands = [Candidate(f"c{k}", "R", ScanSide.INSIDE, "site", x, y, CandidateKind.GRID) for k, (x, y) in enumerate(xy)]
    limits = SightLimits(30.0, 80.0)
    dense = build_coverage(site, cands, t, limits)
    monkeypatch.setattr(vis, "DENSE_BLOCKERS", -1)  # every batch through the STR-tree
    tree = build_coverage(site, cands, t, limits)
    assert dense.by_candidate.nnz > 0 and (dense.by_candidate != tree.by_candidate).nnz == 0


@pytest.mark.parametrize("outer", [False, True])
def test_regions_on_threads_are_the_regions_on_one(outer: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    site = _site()
    t = make_targets(site, 0.5)
    limits = SightLimits(30.0, 70.0)
    monkeypatch.setattr("planner.coverage.regions.CHUNK", 16)  # several chunks
    monkeypatch.setattr(threads, "thread_count", lambda: 3)
    many = coverage_regions(site, t, limits, outer=outer)
    monkeypatch.setattr(threads, "thread_count", lambda: 1)
    one = coverage_regions(site, t, limits, outer=outer)
    assert list(many) == list(one)
    assert all(shapely.to_wkb(many[k]) == shapely.to_wkb(one[k]) for k in one)


def test_ordered_map_and_background_keep_order_and_errors(monkeypatch: pytest.MonkeyPatch) -> None:
    for n in (1, 3):
        monkeypatch.setattr(threads, "thread_count", lambda n=n: n)
        assert ordered_map(lambda x: x * x, range(10)) == [x * x for x in range(10)]
        with pytest.raises(ZeroDivisionError):
            ordered_map(lambda x: 1 / x, [1, 0, 2])
        with Background() as later:
            done = [later.start(pow, k, 2) for k in range(5)]
            bad = later.start(divmod, 1, 0)
        assert [f.result() for f in done] == [0, 1, 4, 9, 16]
        with pytest.raises(ZeroDivisionError):
            bad.result()
