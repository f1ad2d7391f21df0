"""Which candidate sees which wall piece: range, incidence, precision and sight, vectorised.

A piece a-b is seen from station c when, for the WHOLE piece: - c stands in front of the face (perpendicular distance >
``EPS_FRONT_M``); - the slant range from the instrument (height IH) to the top and the foot of the wall at both ends is
<= S_max (distance to a segment is convex, so the ends bound the piece); - the incidence (horizontal, or 3-D to the top)
at both ends is <= theta_max (it grows with the distance from the foot of the perpendicular, so again the ends bound
it); - the sight lines c->a and c->b cross no wall or obstacle edge (touching within ``EPS_SIGHT_M`` counts; the piece's
own wall is skipped; each line stops ``EPS_SHORTEN_M`` before the wall), and no blocker vertex lies strictly inside the
triangle c-a-b (a thin column between the two lines).

Pairs come from STRtree queries, so the work grows with the pairs near a blocker, not pairs x blockers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.coverage.gram import cat
from planner.instrument.accuracy import ErrorBudget, RangeAngleSigma, max_slant_range_m, precision_ok

if TYPE_CHECKING:
    from planner.coverage.targets import Targets
    from planner.site.validate import ValidationReport

EPS_FRONT_M = 1e-6
EPS_RANGE_M = 1e-6
EPS_ANGLE_DEG = 1e-7
EPS_SIGHT_M = 1e-7
EPS_SHORTEN_M = 1e-5
#: blockers (segments, or vertices) at most for which :func:`sight_clear` tests each pair's box against every blocker's
#: box directly (a few array comparisons) instead of drawing the pairs' boxes and asking the blockers' STR-tree: the
#: same pairs (closed boxes that meet, as the tree's query of envelopes), without a polygon per pair
DENSE_BLOCKERS = 64
#: rows whose boxes go to the blockers' STR-tree as one box in :func:`runs_meeting`
BOX_RUN = 8
#: candidate-piece pairs near each other at most in one batch of :func:`geometric_pairs` (memory in proportion)
PAIR_BATCH = 2_000_000
#: slack of the near-pairs filter beyond the longest slant range (m): far above the rounding of the figures
NEAR_MARGIN_M = 1e-3

F64 = NDArray[np.float64]
Mask = NDArray[np.bool_]


@dataclass(frozen=True, eq=False)
class PrecisionRule:
    """How a view's point error is judged: e(S, theta) of :func:`planner.instrument.accuracy.view_error_m`.
    ``combined``: views add information (sum (sigma_req / e_j)^2 >= 1), so no single view is refused for precision;
    verification and the network check judge the sum."""

    scanner: RangeAngleSigma
    budget: ErrorBudget
    sigma_req_m: float
    incidence_model: str = "none"
    combined: bool = False


@dataclass(frozen=True)
class SightLimits:
    """The limits a pair must meet; ``precision_range_m`` is the range at which the predicted point error reaches the
    required accuracy at normal incidence (None: no precision model). With ``per_pair_precision`` each pair is also
    refused when the view of either end of the piece (the worst point of a piece is one of its ends) has e(S, theta) >
    sigma_req."""

    max_slant_range_m: float
    theta_max_deg: float
    instrument_height_m: float = 0.0
    incidence_3d: bool = False
    precision_range_m: float | None = None
    precision: PrecisionRule | None = None

    @property
    def per_pair_precision(self) -> bool:
        """True when each pair is also tested with the incidence-dependent view error."""
        p = self.precision
        return p is not None and not p.combined and p.incidence_model != "none" and self.precision_range_m is not None

    @property
    def effective_range_m(self) -> float:
        """The longest slant range a view may have: S_max, or the precision range where that is shorter."""
        p = self.precision_range_m
        return self.max_slant_range_m if p is None else min(self.max_slant_range_m, p)


@dataclass(frozen=True, eq=False)
class Blockers:
    """Segments that block sight (walls, obstacle edges) and their vertices, in one frame."""

    a: NDArray[np.float64]
    b: NDArray[np.float64]
    key: NDArray[np.int64]  # wall key (zone * 1e6 + wall) or -1 for obstacles
    vertices: NDArray[np.float64]

    def __post_init__(self) -> None:
        object.__setattr__(
            self,
            "_seg_tree",
            shapely.STRtree(shapely.linestrings(np.stack([self.a, self.b], axis=1))) if len(self.a) else None,
        )
        object.__setattr__(
            self, "_vtx_tree", shapely.STRtree(shapely.points(self.vertices)) if len(self.vertices) else None
        )


def wall_key(zone_index: NDArray | int, wall: NDArray | int) -> NDArray[np.int64]:
    return np.asarray(zone_index, dtype=np.int64) * 1_000_000 + np.asarray(wall, dtype=np.int64)


@dataclass(frozen=True, eq=False)
class PairGeometry:
    """Candidate-piece pairs that pass range, incidence and side tests, with their figures."""

    cand: NDArray[np.int64]
    target: NDArray[np.int64]
    slant_m: NDArray[np.float64]  # largest slant range over the piece
    incidence_deg: NDArray[np.float64]  # largest incidence over the piece


def geometric_pairs(
    cand_xy: F64,
    cand_inside: Mask,
    targets: Targets,
    ti: NDArray[np.int64],
    limits: SightLimits,
    chunk: int | None = None,
) -> PairGeometry:
    """All (candidate, piece) pairs of the pieces ``targets[ti]`` meeting the range and incidence limits (``target`` of
    the result indexes ``ti``), ordered by candidate, then piece. A candidate sees a piece only from the piece's side of
    its zone: ``cand_inside[c, z]`` (candidate c inside zone z) must match the piece's side for its zone. Each candidate
    is matched only with the pieces whose middle lies within reach of it along both axes (:func:`near_pairs`: a pair in
    range has both ends, hence the middle, within reach), so the work grows with the pairs in range, not with C x T;
    each figure is the same elementwise formula over the pairs kept. ``chunk``: candidates per batch (None: as many as
    keep a batch's near pairs under :data:`PAIR_BATCH`)."""
    t_zone, t_inside, normal = targets.zone[ti], targets.side[ti] == 0, targets.normal[ti]
    a, b, ha, hb = targets.a[ti], targets.b[ti], targets.ha_m[ti], targets.hb_m[ti]
    ih = limits.instrument_height_m
    mid = (a + b) / 2.0
    cos_max = math.cos(math.radians(limits.theta_max_deg + EPS_ANGLE_DEG))
    longest = limits.effective_range_m + EPS_RANGE_M
    dz_a = np.maximum(np.abs(ha - ih), ih)  # the farther of top and foot, vertically
    dz_b = np.maximum(np.abs(hb - ih), ih)
    sides = _zone_sides(t_zone, t_inside)
    groups = [np.flatnonzero((t_zone == z) & (t_inside == inside)) for z, inside in sides]
    orders = [g[np.argsort(mid[g, 0], kind="stable")] for g in groups]  # each zone-side's pieces in x order
    step = chunk if chunk is not None else max(1, PAIR_BATCH // max(len(ti), 1))
    bound = longest + NEAR_MARGIN_M
    out_c, out_t, out_s, out_i = [], [], [], []
    for c0 in range(0, len(cand_xy), step):
        cx = cand_xy[c0 : c0 + step]
        near = [  # the pairs on the piece's side, near each other: a zone-side's pieces with the candidates on it
            _near_on_side(cx, cand_inside[c0 : c0 + step, z] == inside, mid, by_x, bound)
            for (z, inside), by_x in zip(sides, orders)
        ]
        k, t = cat([p[0] for p in near], np.int64), cat([p[1] for p in near], np.int64)
        va = a[t] - cx[k]
        d = -np.einsum("ij,ij->i", va, normal[t])
        front = d > EPS_FRONT_M  # in front of it; then the range and incidence of those only
        k, t, dk, pa = k[front], t[front], d[front], va[front]
        pb = b[t] - cx[k]
        hd_a, hd_b = np.hypot(pa[:, 0], pa[:, 1]), np.hypot(pb[:, 0], pb[:, 1])
        sa, sb = np.hypot(hd_a, dz_a[t]), np.hypot(hd_b, dz_b[t])
        slant = np.maximum(sa, sb)
        with np.errstate(divide="ignore", invalid="ignore"):
            if limits.incidence_3d:
                cos_i = np.minimum(dk / sa, dk / sb)
            else:
                cos_i = np.minimum(dk / np.maximum(hd_a, 1e-300), dk / np.maximum(hd_b, 1e-300))
        ok = np.flatnonzero((slant <= longest) & (cos_i >= cos_max))
        k, t = k[ok], t[ok]
        inc = np.degrees(np.arccos(np.clip(cos_i[ok], -1.0, 1.0)))
        if limits.per_pair_precision and limits.precision is not None:  # e(S, theta) at each end, its worst points
            hd = (hd_a[ok], hd_b[ok]) if not limits.incidence_3d else (sa[ok], sb[ok])
            keep = _end_precision(sa[ok], dk[ok] / np.maximum(hd[0], 1e-300), limits.precision)
            keep &= _end_precision(sb[ok], dk[ok] / np.maximum(hd[1], 1e-300), limits.precision)
            k, t, inc, ok = k[keep], t[keep], inc[keep], ok[keep]
        order = np.lexsort((t, k))  # by candidate, then piece
        out_c.append(k[order] + c0)
        out_t.append(t[order])
        out_s.append(slant[ok][order])
        out_i.append(inc[order])
    return PairGeometry(cat(out_c, np.int64), cat(out_t, np.int64), cat(out_s, np.float64), cat(out_i, np.float64))


def _zone_sides(t_zone: NDArray, t_inside: NDArray[np.bool_]) -> list[tuple[int, bool]]:
    """The (zone, inside) of the pieces' zone-sides, in order."""
    code = np.unique(np.asarray(t_zone, dtype=np.int64) * 2 + ~t_inside)
    return [(int(c) // 2, int(c) % 2 == 0) for c in code]


def _near_on_side(
    cx: F64, on_side: NDArray[np.bool_], mid: F64, by_x: NDArray[np.intp], bound: float
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """:func:`near_pairs` of the candidates ``on_side`` (rows of ``cx``) and the pieces ``by_x`` (one zone-side's,
    in x order): (row of ``cx``, piece)."""
    rows = np.flatnonzero(on_side)
    if rows.size == 0 or by_x.size == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    k, j = near_pairs(cx[rows], mid[by_x], np.arange(by_x.size), bound)
    return rows[k].astype(np.int64), by_x[j].astype(np.int64)


def near_pairs(xy: F64, mid: F64, by_x: NDArray[np.intp], bound: float) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """(row of ``xy``, row of ``mid``) of every point and middle at most ``bound`` apart along both axes (all pairs
    where ``bound`` is not finite): the middles in x order (``by_x``) within the point's x band, then those within its
    y band."""
    n, m = len(xy), len(mid)
    if not math.isfinite(bound):
        return np.repeat(np.arange(n, dtype=np.int64), m), np.tile(np.arange(m, dtype=np.int64), n)
    mx = mid[by_x, 0]
    lo = np.searchsorted(mx, xy[:, 0] - bound, side="left")
    hi = np.searchsorted(mx, xy[:, 0] + bound, side="right")
    count = np.maximum(hi - lo, 0)
    k = np.repeat(np.arange(n, dtype=np.int64), count)
    first = np.cumsum(count) - count  # where each point's run starts
    pos = np.arange(len(k), dtype=np.int64) - np.repeat(first - lo, count)
    t = by_x[pos].astype(np.int64)
    keep = np.abs(mid[t, 1] - xy[k, 1]) <= bound
    return k[keep], t[keep]


def _end_precision(slant: NDArray, cos_i: NDArray, rule: PrecisionRule) -> NDArray[np.bool_]:
    """e(S, theta) <= sigma_req for the view of one end of each piece (slant range, cosine of its incidence)."""
    inc = np.degrees(np.arccos(np.clip(cos_i, -1.0, 1.0)))
    return precision_ok(slant, inc, rule.scanner, rule.budget, rule.sigma_req_m, rule.incidence_model)


def _signed(p: NDArray, q: NDArray, r: NDArray) -> NDArray:
    """Signed distance of r from the line p->q (positive to the left)."""
    d = q - p
    n = np.hypot(d[:, 0], d[:, 1])
    cross = d[:, 0] * (r[:, 1] - p[:, 1]) - d[:, 1] * (r[:, 0] - p[:, 0])
    return cross / np.where(n > 0, n, 1.0)


def _side(x: NDArray, eps_m: float) -> NDArray:
    """-1, 0 or +1: which side of a line, with |distance| <= eps_m counted as on it."""
    return np.where(np.abs(x) <= eps_m, 0.0, np.sign(x))


def _sides(p: NDArray, q: NDArray, points: tuple[NDArray, ...], eps_m: float) -> list[NDArray]:
    """:func:`_side` of each of ``points`` from the line p->q (row-wise): the elementwise figures of :func:`_signed`,
    the line's direction and length taken once for all."""
    d = q - p
    n = np.hypot(d[:, 0], d[:, 1])
    n = np.where(n > 0, n, 1.0)
    return [_side((d[:, 0] * (r[:, 1] - p[:, 1]) - d[:, 1] * (r[:, 0] - p[:, 0])) / n, eps_m) for r in points]


def segments_touch(p: NDArray, q: NDArray, r: NDArray, s: NDArray, eps_m: float = EPS_SIGHT_M) -> NDArray[np.bool_]:
    """Closed segments p-q and r-s (row-wise) meet, counting touching and collinear overlap within eps_m. The ends of
    r-s are placed on p-q only for the rows where p and q do not lie strictly on one side of r-s (the others cannot
    meet), and the collinear overlap is figured only for rows that meet otherwise: each row's figures are the same."""
    o1, o2 = _sides(r, s, (p, q), eps_m)
    cross = o1 * o2 <= 0
    rows = np.flatnonzero(cross)
    o3, o4 = _sides(p[rows], q[rows], (r[rows], s[rows]), eps_m)
    cross[rows] = o3 * o4 <= 0
    rows = rows[cross[rows] & (o1[rows] == 0) & (o2[rows] == 0)]  # collinear: they meet where they overlap
    if rows.size:
        pr, qr, rr, d = p[rows], q[rows], r[rows], s[rows] - r[rows]
        n2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
        tp = np.einsum("ij,ij->i", pr - rr, d) / n2
        tq = np.einsum("ij,ij->i", qr - rr, d) / n2
        lo, hi = np.minimum(tp, tq), np.maximum(tp, tq)
        tol = eps_m / np.sqrt(n2)
        cross[rows] = (lo <= 1 + tol) & (hi >= -tol)
    return cross


def boxes_meeting(lo: F64, hi: F64, blo: F64, bhi: F64) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """(row, blocker) of every row's closed box [lo, hi] that meets a blocker's closed box [blo, bhi], rows in order
    (what an STR-tree of the blockers' boxes answers for the rows' boxes, with predicate None)."""
    meet = (lo[:, None, 0] <= bhi[None, :, 0]) & (hi[:, None, 0] >= blo[None, :, 0])
    meet &= (lo[:, None, 1] <= bhi[None, :, 1]) & (hi[:, None, 1] >= blo[None, :, 1])
    rows, cols = np.nonzero(meet)
    return rows, cols


def runs_meeting(
    lo: F64, hi: F64, tree: shapely.STRtree, blo: F64, bhi: F64
) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """:func:`boxes_meeting` with an STR-tree of the blockers (their boxes [blo, bhi]): the tree asked once for each run
    of :data:`BOX_RUN` rows (the box round the run's boxes: a pair's neighbours in a batch share its station and wall),
    each blocker it gives then tested row by row. The same pairs (by run, then as the tree lists the blockers), without
    a polygon per row."""
    n = len(lo)
    start = np.arange(0, n, BOX_RUN)
    glo, ghi = np.minimum.reduceat(lo, start, axis=0), np.maximum.reduceat(hi, start, axis=0)
    gi, bi = tree.query(shapely.box(glo[:, 0], glo[:, 1], ghi[:, 0], ghi[:, 1]))
    size = np.minimum(start[gi] + BOX_RUN, n) - start[gi]
    first = np.cumsum(size) - size
    rows = np.repeat(start[gi] - first, size) + np.arange(int(size.sum()))
    cols = np.repeat(bi, size)
    meet = (lo[rows, 0] <= bhi[cols, 0]) & (hi[rows, 0] >= blo[cols, 0])
    meet &= (lo[rows, 1] <= bhi[cols, 1]) & (hi[rows, 1] >= blo[cols, 1])
    return rows[meet], cols[meet]


def sight_clear(c: F64, a: F64, b: F64, key: NDArray[np.int64], blockers: Blockers) -> Mask:
    """For each pair (row), True when nothing blocks the view from c to the whole piece a-b."""
    n = len(c)
    clear = np.ones(n, dtype=bool)
    if n == 0:
        return clear

    def shorten(e: NDArray) -> NDArray:
        v = c - e
        length = np.maximum(np.hypot(v[:, 0], v[:, 1]), 1e-300)
        return e + v * (np.minimum(EPS_SHORTEN_M, length / 2) / length)[:, None]

    a2, b2 = shorten(a), shorten(b)
    lo = np.minimum(np.minimum(c, a), b) - EPS_SIGHT_M
    hi = np.maximum(np.maximum(c, a), b) + EPS_SIGHT_M
    dense = len(blockers.a) <= DENSE_BLOCKERS and len(blockers.vertices) <= DENSE_BLOCKERS
    tree = blockers._seg_tree  # type: ignore[attr-defined]
    if tree is not None:
        blo, bhi = np.minimum(blockers.a, blockers.b), np.maximum(blockers.a, blockers.b)
        pi, bi = boxes_meeting(lo, hi, blo, bhi) if dense else runs_meeting(lo, hi, tree, blo, bhi)
        keep = key[pi] != blockers.key[bi]
        pi, bi = pi[keep], bi[keep]
        ra, rb = blockers.a[bi], blockers.b[bi]
        hit = segments_touch(c[pi], a2[pi], ra, rb)
        rest = np.flatnonzero(~hit)  # the line to b only where the line to a is clear
        hit[rest] = segments_touch(c[pi[rest]], b2[pi[rest]], ra[rest], rb[rest])
        clear[pi[hit]] = False
    vtree = blockers._vtx_tree  # type: ignore[attr-defined]
    wide = np.hypot(*(b - a).T) > EPS_SIGHT_M
    if vtree is not None and np.any(wide & clear):
        idx = np.flatnonzero(wide & clear)
        vx = blockers.vertices
        pi, vi = boxes_meeting(lo[idx], hi[idx], vx, vx) if dense else runs_meeting(lo[idx], hi[idx], vtree, vx, vx)
        pi = idx[pi]
        v = blockers.vertices[vi]
        ca, ab, bc = _signed(c[pi], a[pi], v), _signed(a[pi], b[pi], v), _signed(b[pi], c[pi], v)
        inside = ((ca > EPS_SIGHT_M) & (ab > EPS_SIGHT_M) & (bc > EPS_SIGHT_M)) | (
            (ca < -EPS_SIGHT_M) & (ab < -EPS_SIGHT_M) & (bc < -EPS_SIGHT_M)
        )
        clear[pi[inside]] = False
    return clear


def sight_limits(
    validation: ValidationReport, incidence_3d: bool, precision: bool, combined: bool = False
) -> SightLimits:
    """The pair limits for a validated site; the precision range is (3.1) for the scanner and sigma_req. ``combined``:
    no single view is refused for precision (no precision range, no per-pair test); the rule travels with the limits so
    that verification and the network check judge the information sum. With ``precision`` off there is no rule at
    all."""
    p = validation.site.parameters
    single = precision and not combined
    precision_range = max_slant_range_m(validation.scanner, validation.range_limit.sigma_instr_m) if single else None
    rule = (
        PrecisionRule(validation.scanner, p.budget, p.sigma_req_m, p.incidence_model, combined) if precision else None
    )
    return SightLimits(
        max_slant_range_m=validation.range_limit.max_slant_range_m,
        theta_max_deg=validation.theta_max_deg,
        instrument_height_m=p.instrument_height_m,
        incidence_3d=incidence_3d,
        precision_range_m=precision_range,
        precision=rule,
    )
