"""The pair tests' shortcuts give the plain tests' answers bit for bit.

:func:`planner.coverage.visibility.geometric_pairs` figures only the pairs on the piece's side whose middle lies within
reach (:func:`~planner.coverage.visibility.near_pairs`); :func:`~planner.coverage.visibility.segments_touch` places
r-s on p-q only where p-q may meet it. Both are compared with the plain all-pairs formulas written out here.
:func:`~planner.coverage.visibility.runs_meeting` asks the blockers' tree once per run of rows: the pairs of
:func:`~planner.coverage.visibility.boxes_meeting`."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from planner.coverage.targets import make_targets
from planner.coverage.visibility import (
    EPS_ANGLE_DEG,
    EPS_FRONT_M,
    EPS_RANGE_M,
    SightLimits,
    boxes_meeting,
    geometric_pairs,
    near_pairs,
    runs_meeting,
    segments_touch,
)
from planner.site import ScanSide, Site, Zone


def _signed(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
    d = q - p
    n = np.hypot(d[:, 0], d[:, 1])
    return (d[:, 0] * (r[:, 1] - p[:, 1]) - d[:, 1] * (r[:, 0] - p[:, 0])) / np.where(n > 0, n, 1.0)


def _side(x: np.ndarray, eps: float) -> np.ndarray:
    return np.where(np.abs(x) <= eps, 0.0, np.sign(x))


def plain_touch(p, q, r, s, eps: float = 1e-7) -> np.ndarray:
    """Every row's four sides, then the collinear overlap of every row."""
    o1, o2 = _side(_signed(r, s, p), eps), _side(_signed(r, s, q), eps)
    o3, o4 = _side(_signed(p, q, r), eps), _side(_signed(p, q, s), eps)
    cross = (o1 * o2 <= 0) & (o3 * o4 <= 0)
    collinear = (o1 == 0) & (o2 == 0)
    d = s - r
    n2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    tp, tq = np.einsum("ij,ij->i", p - r, d) / n2, np.einsum("ij,ij->i", q - r, d) / n2
    tol = eps / np.sqrt(n2)
    overlap = (np.minimum(tp, tq) <= 1 + tol) & (np.maximum(tp, tq) >= -tol)
    return cross & (~collinear | overlap)


@pytest.mark.parametrize("jitter", [0.0, 1e-7])
def test_segments_touch_is_the_plain_test(jitter: float) -> None:
    # ends on a coarse grid: crossings, touching ends, collinear overlaps and gaps, degenerate segments, all often
    rng = np.random.default_rng(7)
    p, q, r, s = (rng.integers(0, 5, (20_000, 2)) * 0.5 + rng.normal(0.0, jitter, (20_000, 2)) for _ in range(4))
    assert np.array_equal(segments_touch(p, q, r, s), plain_touch(p, q, r, s))


def plain_pairs(cx, inside, targets, ti, limits: SightLimits):
    """Every candidate with every piece: side, front, range and incidence (horizontal incidence, no precision)."""
    a, b, normal = targets.a[ti], targets.b[ti], targets.normal[ti]
    ih = limits.instrument_height_m
    dz_a = np.maximum(np.abs(targets.ha_m[ti] - ih), ih)
    dz_b = np.maximum(np.abs(targets.hb_m[ti] - ih), ih)
    va = a[None] - cx[:, None, :]
    d = -np.einsum("ktj,tj->kt", va, normal)
    side_ok = inside[:, targets.zone[ti]] == (targets.side[ti] == 0)[None, :]
    k, t = np.nonzero(side_ok & (d > EPS_FRONT_M))
    pa, pb = va[k, t], b[t] - cx[k]
    hd_a, hd_b = np.hypot(pa[:, 0], pa[:, 1]), np.hypot(pb[:, 0], pb[:, 1])
    slant = np.maximum(np.hypot(hd_a, dz_a[t]), np.hypot(hd_b, dz_b[t]))
    cos_i = np.minimum(d[k, t] / np.maximum(hd_a, 1e-300), d[k, t] / np.maximum(hd_b, 1e-300))
    ok = (slant <= limits.effective_range_m + EPS_RANGE_M) & (
        cos_i >= math.cos(math.radians(limits.theta_max_deg + EPS_ANGLE_DEG))
    )
    inc = np.degrees(np.arccos(np.clip(cos_i[ok], -1.0, 1.0)))
    return k[ok], t[ok], slant[ok], inc


def two_rooms() -> Site:
    """Two rooms side by side, one scanned inside and out: pieces of three zone-sides."""
    a = Zone("A", ScanSide.BOTH, ((0, 0), (30, 0), (30, 12), (0, 12)), (3.0,) * 4)
    b = Zone("B", ScanSide.INSIDE, ((40, 0), (70, 0), (70, 25), (40, 25)), (4.0,) * 4)
    return Site("two", (a, b))


@pytest.mark.parametrize("reach", [9.0, 25.0, 1e9])
@pytest.mark.parametrize("chunk", [None, 1, 37])
def test_geometric_pairs_are_the_plain_pairs(reach: float, chunk: int | None) -> None:
    site = two_rooms()
    targets = make_targets(site, 1.0)
    rng = np.random.default_rng(3)
    cx = np.column_stack([rng.uniform(-15, 85, 300), rng.uniform(-15, 40, 300)])
    inside = np.column_stack([shapely.contains_xy(z.polygon, cx[:, 0], cx[:, 1]) for z in site.zones])
    ti = np.arange(len(targets))
    limits = SightLimits(reach, 70.0, instrument_height_m=1.5)
    got = geometric_pairs(cx, inside, targets, ti, limits, chunk)
    want = plain_pairs(cx, inside, targets, ti, limits)
    for g, w in zip((got.cand, got.target, got.slant_m, got.incidence_deg), want):
        assert g.tobytes() == np.asarray(w, g.dtype).tobytes()
    assert len(got.cand) > 0


def test_near_pairs_keeps_every_pair_within_the_bound() -> None:
    rng = np.random.default_rng(5)
    xy, mid = rng.uniform(0, 100, (200, 2)), rng.uniform(0, 100, (300, 2))
    k, t = near_pairs(xy, mid, np.argsort(mid[:, 0], kind="stable"), 12.5)
    near = np.all(np.abs(xy[:, None, :] - mid[None, :, :]) <= 12.5, axis=2)
    assert sorted(zip(k.tolist(), t.tolist())) == sorted(zip(*map(np.ndarray.tolist, np.nonzero(near))))


def test_runs_meeting_gives_the_pairs_of_boxes_meeting() -> None:
    # boxes on a coarse grid (edges and corners touch often), some long (a far station), rows in runs and a short tail
    rng = np.random.default_rng(11)
    lo = rng.integers(0, 40, (1003, 2)) * 0.5
    hi = lo + rng.integers(0, 12, (1003, 2)) * 0.5 * rng.integers(1, 4, (1003, 1))
    a, b = rng.integers(0, 50, (90, 2)) * 0.5, rng.integers(0, 50, (90, 2)) * 0.5
    blo, bhi = np.minimum(a, b), np.maximum(a, b)
    tree = shapely.STRtree(shapely.linestrings(np.stack([a, b], axis=1)))
    got = set(zip(*(x.tolist() for x in runs_meeting(lo, hi, tree, blo, bhi))))
    want = set(zip(*(x.tolist() for x in boxes_meeting(lo, hi, blo, bhi))))
    assert got == want and len(want) > 100
