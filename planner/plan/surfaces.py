"""Floors and ceilings as targets of a plan: what :func:`planner.plan.problem.resolve` records when the surfaces go
beyond walls, and the stations x patches columns the methods cover besides the wall pieces.

The wall coverage (:class:`~planner.coverage.matrix.CoverageProblem`), the registration relation and the precision
rule read walls only. The patches of :func:`planner.coverage.surfaces.make_surface_targets` (made once per run, at
the target spacing) are seen by the rules of :mod:`planner.coverage.surface_sight`; a patch no candidate sees is
reported and left out of the cover.
"""

from __future__ import annotations

import math
from collections.abc import Collection
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
import shapely
from numpy.typing import NDArray
from scipy import sparse

from planner.core.errors import UsageError
from planner.coverage.surface_sight import SurfaceLimits, standing_zone, surface_limits, surface_sight
from planner.coverage.surfaces import KIND_CODE, KIND_NAME, SurfaceTargets, make_surface_targets, open_area
from planner.plan.tripod import MIN_RADIUS_M, RIM_POINTS
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Site

if TYPE_CHECKING:
    from planner.coverage.visibility import SightLimits
    from planner.plan.options import PlanOptions
    from planner.plan.tripod import TripodDisc
    from planner.site.validate import ValidationReport

#: why pricing is off when surfaces go beyond walls (the bound over walls and surfaces together is formed after the
#: solve: :mod:`planner.plan.surfaces_bound`)
PLANE_OFF = "surfaces beyond walls: no pricing of the pool; the plane bound over walls and surfaces follows the solve"
#: the option that sets the instrument height (named by the refusal when none is known)
HEIGHT_FLAG = "--instrument-height"
#: the most floor candidates of one zone (a finer grid is coarsened to it)
MAX_FLOOR_CANDIDATES = 5_000
#: a zone's floor grid of more points than this is thinned (:func:`thinned`); a room's grid is kept whole
THIN_ABOVE = 1_000
#: how many of the grid points that see a patch whole the thinning keeps (all where fewer see it)
THIN_SEERS = 3


@dataclass(frozen=True, eq=False)
class SurfaceSetup:
    """The floors and ceilings of a run: ``kinds`` (``floor``, ``ceiling``), their ``patches``, the sight
    ``limits`` of a station on them and where the instrument height came from (``height_source``)."""

    kinds: tuple[str, ...]
    patches: SurfaceTargets
    limits: SurfaceLimits
    height_source: str

    @property
    def absent(self) -> tuple[str, ...]:
        """The kinds asked for that the site has no patch of (no zone scanned from inside, or no ceiling height)."""
        return tuple(k for k in self.kinds if not np.any(self.patches.kind == KIND_CODE[k]))

    def line(self) -> str:
        """The surfaces in one line: kinds, patches, area, instrument height and incidence limit."""
        lim = self.limits
        theta = lim.theta_for(0)
        return (
            f"surfaces: walls, {', '.join(k + 's' for k in self.kinds)}: {len(self.patches):,} patches of at most "
            f"{self.patches.spacing_m:g} m ({self.patches.total_area_m2():.1f} m2); instrument {lim.instrument_height_m:g} m "
            f"above the floor ({self.height_source}), incidence <= {theta:g} deg"
            + (f", blind cone {lim.nadir_blind_half_angle_deg:g} deg" if lim.nadir_blind_half_angle_deg else "")
        )


def surface_setup(
    site: Site, validation: ValidationReport, options: PlanOptions, limits: SightLimits
) -> SurfaceSetup | None:
    """The surfaces of a run beyond walls (None: walls only). The instrument height is the site's
    (``--instrument-height``, ``instrument_height_m``) where it is > 0, else the scanner model's
    ``instrument_height_3d_m``; UsageError where none is known, and with the closed form, recentring or combined
    precision, which plan walls only."""
    if not options.beyond_walls:
        return None
    if options.method == "closed-form":
        raise UsageError("the closed form plans walls only; floors and ceilings need milp or greedy", field="method")
    if options.recentre:
        raise UsageError(
            "recentring keeps each station's walls only; floors and ceilings keep the planned stations",
            field="--recentre",
        )
    if options.combined:
        raise UsageError(
            "combined precision is for walls only; floors and ceilings plan with single-view precision",
            field="precision",
        )
    scanner = validation.scanner
    ih_site = site.parameters.instrument_height_m
    if ih_site > 0:
        ih, source = ih_site, "the site's instrument height"
    elif scanner.instrument_height_3d_m is not None:
        ih, source = scanner.instrument_height_3d_m, f"{scanner.name}'s instrument_height_3d_m"
    else:
        raise UsageError(
            f"floors and ceilings need the instrument height: give {HEIGHT_FLAG} M "
            f"({scanner.name} has no instrument_height_3d_m)",
            field=HEIGHT_FLAG,
        )
    kinds = tuple(k for k in ("floor", "ceiling") if k + "s" in options.surfaces)
    sl = surface_limits(
        scanner, limits.max_slant_range_m, limits.theta_max_deg, ih, theta_max_floor_deg=options.theta_max_floor_deg
    )
    return SurfaceSetup(kinds, make_surface_targets(site, options.target_spacing_m, kinds), sl, source)


def standing_zones(site: Site, candidates: tuple[Candidate, ...] | list[Candidate]) -> NDArray[np.int64]:
    """For each candidate, the index of the inside zone of its frame on whose floor it stands (-1: none): the first
    zone of its frame scanned from inside whose floor (outline less its blocks) holds it, edge included; a candidate
    planned for a zone's outside sees no floor."""
    out = np.full(len(candidates), -1, dtype=np.int64)
    inside = np.flatnonzero([c.side is ScanSide.INSIDE for c in candidates])
    if inside.size == 0:
        return out
    xy = np.array([candidates[int(i)].xy for i in inside], dtype=float).reshape(-1, 2)
    frames = np.array([candidates[int(i)].frame for i in inside], dtype=object)
    out[inside] = standing_zone(site, xy, frames)
    return out


def floor_spacing(setup: SurfaceSetup) -> float:
    """The spacing of the floor candidates: half the width of the ring a station sees the floor in (from the blind
    disc's radius to the incidence reach), at least 0.5 m."""
    lim = setup.limits
    ih = lim.instrument_height_m
    reach = ih * math.tan(math.radians(min(lim.theta_for(0), 89.0)))
    reach = min(reach, lim.max_slant_range_m)
    blind = ih * math.tan(math.radians(lim.nadir_blind_half_angle_deg or 0.0))
    return max(0.5, (reach - blind) / 2)


def floor_candidates(site: Site, setup: SurfaceSetup, standoff_m: float) -> list[Candidate]:
    """Candidates on a square grid over each inside zone's floor (:func:`floor_spacing`, axes from the zone's first
    wall, so that moving the site moves the grid), at least ``standoff_m`` from its walls and blocks, so that every
    patch has stations near enough to see it (the wall pool's grid is coarser than a floor's reach); a large zone's
    grid is thinned (:func:`thinned`)."""
    spacing = floor_spacing(setup)
    out: list[Candidate] = []
    for zi, zone in enumerate(site.zones):
        if ScanSide.INSIDE not in zone.scan_side.sides:
            continue
        area = open_area(site, zi)
        inner = area.buffer(-standoff_m) if standoff_m > 0 else area
        if inner.is_empty:
            continue
        h = max(spacing, math.sqrt(area.area / MAX_FLOOR_CANDIDATES))
        xy = np.asarray(zone.xy, dtype=float)
        ux = (xy[1] - xy[0]) / np.hypot(*(xy[1] - xy[0]))
        uy = np.array([-ux[1], ux[0]])
        rel = np.asarray(shapely.get_coordinates(shapely.envelope(area))) - xy[0]
        u, v = rel @ ux, rel @ uy
        iu = np.arange(math.floor(u.min() / h), math.ceil(u.max() / h) + 1) * h
        iv = np.arange(math.floor(v.min() / h), math.ceil(v.max() / h) + 1) * h
        gu, gv = np.meshgrid(iu + h / 2, iv + h / 2)
        pts = xy[0] + np.outer(gu.ravel(), ux) + np.outer(gv.ravel(), uy)
        pts = pts[shapely.contains_xy(inner, pts[:, 0], pts[:, 1])]
        pts = thinned(site, setup, zi, pts)
        out += [
            Candidate(
                f"{zone.id}-in-F{k}", zone.id, ScanSide.INSIDE, zone.frame, float(x), float(y), CandidateKind.GRID
            )
            for k, (x, y) in enumerate(pts, 1)
        ]
    return out


def thinned(site: Site, setup: SurfaceSetup, zi: int, pts: NDArray[np.float64]) -> NDArray[np.float64]:
    """Zone ``zi``'s floor grid ``pts`` as it is up to :data:`THIN_ABOVE` points; beyond, the points a greedy
    multi-cover keeps: each patch that some grid point sees whole keeps min(:data:`THIN_SEERS`, its seers) of them,
    the point that serves most patches still short first (ties: grid order). The grid is denser than any plan needs
    (a point per cell of the width of the ring a station sees), and every candidate of a dense pool is a row of the
    plan's quadratic steps (the registration relation): a zone of 10,000 m2 keeps about 40 % of its grid, and loses
    no patch any grid point sees."""
    if len(pts) <= THIN_ABOVE:
        return pts
    seen = surface_sight(site, setup.patches, pts, np.full(len(pts), zi), setup.limits)
    by_patch = seen.tocsc()
    need = np.minimum(np.diff(by_patch.indptr), THIN_SEERS)
    gain = np.asarray(seen.astype(np.int64) @ (need > 0).astype(np.int64)).ravel()
    keep = np.zeros(len(pts), dtype=bool)
    while True:
        gain[keep] = -1
        c = int(np.argmax(gain))
        if gain[c] <= 0:
            break
        keep[c] = True
        cols = seen.indices[seen.indptr[c] : seen.indptr[c + 1]]
        cols = cols[need[cols] > 0]
        need[cols] -= 1
        for j in cols[need[cols] == 0]:  # a patch served: it counts no more for its other seers
            gain[by_patch.indices[by_patch.indptr[j] : by_patch.indptr[j + 1]]] -= 1
    return pts[keep]


def patch_matrix(
    site: Site,
    setup: SurfaceSetup,
    candidates: tuple[Candidate, ...] | list[Candidate],
    excluded: Collection[int] = (),
) -> sparse.csr_matrix:
    """Boolean CSR, candidates x patches: True where the candidate sees the whole patch
    (:func:`planner.coverage.surface_sight.surface_sight`, the candidate in the zone it stands in); the
    ``excluded`` candidates (where no station may stand: the wall coverage's) see none."""
    n, p = len(candidates), len(setup.patches)
    zone = standing_zones(site, candidates)
    zone[np.asarray(list(excluded), dtype=np.int64)] = -1
    rows = np.flatnonzero(zone >= 0)
    if rows.size == 0 or p == 0:
        return sparse.csr_matrix((n, p), dtype=bool)
    xy = np.array([candidates[int(i)].xy for i in rows], dtype=float).reshape(-1, 2)
    sub = surface_sight(site, setup.patches, xy, zone[rows], setup.limits).tocoo()
    return sparse.csr_matrix((np.ones(sub.nnz, dtype=bool), (rows[sub.row], sub.col)), shape=(n, p), dtype=bool)


@dataclass(frozen=True, eq=False)
class SurfaceCover:
    """The patch columns of a cover: ``matrix`` (candidates x the patches some candidate sees), ``seen`` those
    patches' indices, ``unseen`` the patches no candidate sees (left out of the cover, reported)."""

    matrix: sparse.csr_matrix
    seen: NDArray[np.int64]
    unseen: NDArray[np.int64]

    def unseen_dict(self, setup: SurfaceSetup) -> dict[str, object]:
        """The unseen patches: count, area and zones with their kinds."""
        p = setup.patches
        zones = sorted({f"{p.zone_ids[int(p.zone[t])]}/{KIND_NAME[int(p.kind[t])]}" for t in self.unseen})
        return {"count": int(self.unseen.size), "area_m2": float(p.area_m2[self.unseen].sum()), "zones": zones}

    def line(self, setup: SurfaceSetup) -> str:
        """The patches covered, and those left out (no candidate sees them), in one line."""
        u = self.unseen_dict(setup)
        left = (
            f"; {u['count']} patch(es) ({u['area_m2']:.2f} m2) seen by no candidate, left out (NOT covered): "
            f"{', '.join(u['zones'])}"  # type: ignore[arg-type]
            if u["count"]
            else ""
        )
        none = "".join(f"; the site has no {k}s: --surfaces {k}s plans nothing" for k in setup.absent)
        return f"surface cover: {len(self.seen):,} patches as {self.matrix.nnz:,} candidate-patch pairs{left}{none}"


def surface_cover(
    site: Site,
    setup: SurfaceSetup,
    candidates: tuple[Candidate, ...] | list[Candidate],
    excluded: Collection[int] = (),
) -> SurfaceCover:
    """The patch columns for ``candidates`` (``excluded``: those that may not stand where they are): the seen
    patches kept, the unseen ones set apart."""
    full = patch_matrix(site, setup, candidates, excluded)
    counts = np.diff(full.tocsc().indptr)
    seen, unseen = np.flatnonzero(counts > 0), np.flatnonzero(counts == 0)
    return SurfaceCover(full[:, seen].tocsr(), seen.astype(np.int64), unseen.astype(np.int64))


def _margins(site: Site, setup: SurfaceSetup, xy: NDArray, zone: NDArray, pid: NDArray) -> NDArray[np.float64]:
    """How far each station (``xy``, standing in ``zone``) may move and still see all of patch ``pid``, by range,
    incidence and the blind cone: the reach less the farthest corner, and the nearest point less the blind radius."""
    lim, p = setup.limits, setup.patches
    floor = np.array([z.floor_level_m for z in site.zones])[zone]
    dz = np.abs(p.height_m[pid] - (floor + lim.instrument_height_m))
    kind = p.kind[pid]
    theta = np.where(kind == 0, lim.theta_for(0), lim.theta_for(1))
    reach = np.minimum(np.sqrt(np.maximum(lim.max_slant_range_m**2 - dz**2, 0.0)), dz * np.tan(np.radians(theta)))
    far = np.hypot(*(p.corners[pid] - xy[:, None, :]).transpose(2, 0, 1)).max(axis=1)
    half = np.where(kind == 0, lim.nadir_blind_half_angle_deg or 0.0, lim.zenith_blind_half_angle_deg or 0.0)
    near = shapely.distance(shapely.points(xy), p.polygon[pid])
    return np.asarray(np.minimum(reach - far, near - dz * np.tan(np.radians(half))), dtype=np.float64)


def surface_discs(
    site: Site,
    setup: SurfaceSetup,
    cover: SurfaceCover,
    selected: tuple[int, ...],
    stations: list[Candidate],
    discs: tuple[TripodDisc, ...],
) -> tuple[tuple[TripodDisc, ...], int]:
    """The tripod discs shrunk so that each keeps the floor and ceiling patches its station answers for (each
    seen patch answers to the chosen station that sees it with the largest margin), and how many were shrunk. The
    radius is the smallest margin (:func:`_margins`) of the station's patches, checked with the full sight test at
    :data:`~planner.plan.tripod.RIM_POINTS` points of the rim and halved (three times at most, then 0) until none
    is lost; below :data:`~planner.plan.tripod.MIN_RADIUS_M` it is 0. Each halving step tests the rims of every
    station still unsettled in one sight test (a pair's answer does not depend on the pairs tested with it)."""
    if not discs or cover.matrix.shape[1] == 0:
        return discs, 0
    m = cover.matrix[list(selected)].tocoo()
    rows, pid = m.row.astype(np.int64), cover.seen[m.col]
    xy = np.array([s.xy for s in stations], dtype=float).reshape(-1, 2)
    zone = standing_zones(site, stations)
    margin = _margins(site, setup, xy[rows], zone[rows], pid)
    order = np.lexsort((-margin, pid))
    first = order[np.r_[True, pid[order][1:] != pid[order][:-1]]]  # the best station of each patch
    first = first[np.argsort(rows[first], kind="stable")]  # grouped by station
    owner, need = rows[first], pid[first]
    ks, starts = np.unique(owner, return_index=True)
    ends = np.r_[starts[1:], owner.size]
    radius = np.array([discs[int(k)].radius_m for k in ks], dtype=float)
    radius = np.minimum(radius, np.minimum.reduceat(margin[first], starts))
    todo = np.flatnonzero(radius >= MIN_RADIUS_M)
    for step in range(4):
        if todo.size == 0:
            break
        kept = _rims_keep(site, setup, xy[ks[todo]], zone[ks[todo]], radius[todo], need, starts[todo], ends[todo])
        radius[todo[~kept]] /= 2
        if step == 3:  # the fourth test failed too: 0
            radius[todo[~kept]] = 0.0
        todo = todo[~kept & (radius[todo] >= MIN_RADIUS_M)]
    radius[radius < MIN_RADIUS_M] = 0.0
    out, shrunk = list(discs), 0
    for i, k in enumerate(ks.tolist()):
        if radius[i] < discs[k].radius_m:
            out[k], shrunk = replace(discs[k], radius_m=float(radius[i])), shrunk + 1
    return tuple(out), shrunk


def _rims_keep(
    site: Site,
    setup: SurfaceSetup,
    xy: NDArray[np.float64],
    zone: NDArray[np.int64],
    radius: NDArray[np.float64],
    need: NDArray[np.int64],
    starts: NDArray[np.int64],
    ends: NDArray[np.int64],
) -> NDArray[np.bool_]:
    """For each disc (centre ``xy`` standing in ``zone``, ``radius``), whether every one of the
    :data:`~planner.plan.tripod.RIM_POINTS` points of its rim sees all of its patches ``need[starts:ends]``: one
    sight test for all the rims."""
    angles = np.linspace(0.0, 2 * math.pi, RIM_POINTS, endpoint=False)
    ring = np.column_stack([np.cos(angles), np.sin(angles)])
    rim = (xy[:, None, :] + radius[:, None, None] * ring[None, :, :]).reshape(-1, 2)
    seen = surface_sight(site, setup.patches, rim, np.repeat(zone, RIM_POINTS), setup.limits).tocsr()
    counts = ends - starts
    disc = np.repeat(np.arange(len(xy)), counts)  # each (disc, patch) needed
    patch = need[np.concatenate([np.arange(a, b) for a, b in zip(starts, ends)])] if len(xy) else need[:0]
    point = np.repeat(disc * RIM_POINTS, RIM_POINTS) + np.tile(np.arange(RIM_POINTS), disc.size)
    asked = sparse.csr_matrix(
        (np.ones(point.size, dtype=bool), (point, np.repeat(patch, RIM_POINTS))), shape=seen.shape, dtype=bool
    )
    got = np.asarray(asked.multiply(seen).sum(axis=1)).ravel().reshape(-1, RIM_POINTS).sum(axis=1)
    return np.asarray(got == counts * RIM_POINTS, dtype=bool)
