"""Which stations see which floor and ceiling patches: range, 3-D incidence, blind cones, plan-view sight.

A station of zone z stands on z's floor with the instrument ``IH`` above it. It sees a patch of
:mod:`planner.coverage.surfaces` when, for the WHOLE patch:

- the patch belongs to the station's own zone, and the station stands on its floor area;
- the slant range to every corner is <= S_max (range is convex: the corners bound the patch);
- the 3-D incidence, atan(d / |dz|) on a horizontal patch, is <= the surface's limit (``theta_max_floor_deg``); it grows
  with d, so the corners bound it; a ceiling at or below the instrument is not seen;
- no point of the patch lies in a blind cone about the nadir (floors) or zenith (ceilings): the patch's nearest point
  (not its corners) is at least |dz| tan(half angle) away horizontally;
- in plan, the segment to every point of the patch neither leaves the zone's outline nor enters a block that can be in
  the way (every block for a floor, those above the instrument for a ceiling): :mod:`planner.coverage.plan_sight` tests
  the patch's whole fan. This is conservative: a block lower than the instrument hides in plan what it does not hide in
  3-D.

Pairs come from an STRtree query within the horizontal reach that range and incidence allow, so the work grows with the
pairs in reach, never with stations x patches.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray
from scipy import sparse

from planner.core.checks import finite_number
from planner.coverage.plan_sight import EPS_PLAN_M, PlanBlockers, fans_clear, plan_blockers
from planner.coverage.surfaces import CEILING, FLOOR, REACH_TOL_M, SurfaceTargets, open_area
from planner.instrument.models import Scanner
from planner.site.model import ScanSide, Site

EPS_RANGE_M = 1e-6
EPS_ANGLE_DEG = 1e-7
#: station-patch pairs tested at once (bounds the memory of a wide reach over a large floor)
PAIR_BATCH = 1 << 20


@dataclass(frozen=True)
class SurfaceLimits:
    """The limits a station-patch pair must meet. ``theta_max_floor_deg``: the incidence limit of floors and ceilings
    (None: ``theta_max_deg``); ``instrument_height_m``: the instrument above the station's floor (> 0); the blind half
    angles are the scanner's (None: no cone)."""

    max_slant_range_m: float
    theta_max_deg: float
    instrument_height_m: float
    theta_max_floor_deg: float | None = None
    nadir_blind_half_angle_deg: float | None = None
    zenith_blind_half_angle_deg: float | None = None

    def __post_init__(self) -> None:
        checks = [
            ("max_slant_range_m", self.max_slant_range_m, 0.0, math.inf, True, True),
            ("theta_max_deg", self.theta_max_deg, 0.0, 90.0, True, False),
            ("instrument_height_m", self.instrument_height_m, 0.0, math.inf, True, True),
            ("theta_max_floor_deg", self.theta_max_floor_deg, 0.0, 90.0, True, False),
            ("nadir_blind_half_angle_deg", self.nadir_blind_half_angle_deg, 0.0, 90.0, False, True),
            ("zenith_blind_half_angle_deg", self.zenith_blind_half_angle_deg, 0.0, 90.0, False, True),
        ]
        for name, v, lo, hi, lo_open, hi_open in checks:
            inside = finite_number(v) and (lo < v if lo_open else lo <= v) and (v < hi if hi_open else v <= hi)
            if v is not None and not inside:
                raise ValueError(
                    f"{name} must be a finite number in {'(' if lo_open else '['}{lo:g}, {hi:g}"
                    f"{')' if hi_open else ']'}, got {v!r}"
                )

    def theta_for(self, kind: int) -> float:
        """The incidence limit of a surface kind (floors and ceilings: ``theta_max_floor_deg`` where set)."""
        if kind in (FLOOR, CEILING) and self.theta_max_floor_deg is not None:
            return self.theta_max_floor_deg
        return self.theta_max_deg


def surface_limits(
    scanner: Scanner,
    max_slant_range_m: float,
    theta_max_deg: float,
    instrument_height_m: float | None = None,
    theta_max_floor_deg: float | None = None,
) -> SurfaceLimits:
    """The limits for a scanner: its blind cones, and its ``instrument_height_3d_m`` unless a height is given (a
    ValueError when neither is)."""
    ih = instrument_height_m if instrument_height_m is not None else scanner.instrument_height_3d_m
    if ih is None:
        raise ValueError(f"no instrument height for 3-D work: give one, or instrument_height_3d_m in {scanner.name}")
    return SurfaceLimits(
        max_slant_range_m=max_slant_range_m,
        theta_max_deg=theta_max_deg,
        instrument_height_m=ih,
        theta_max_floor_deg=theta_max_floor_deg,
        nadir_blind_half_angle_deg=scanner.nadir_blind_half_angle_deg,
        zenith_blind_half_angle_deg=scanner.zenith_blind_half_angle_deg,
    )


@dataclass(frozen=True, eq=False)
class SurfacePairs:
    """Station-patch pairs seen, with the largest slant range and incidence over each patch."""

    station: NDArray[np.int64]
    patch: NDArray[np.int64]
    slant_m: NDArray[np.float64]
    incidence_deg: NDArray[np.float64]

    def matrix(self, n_stations: int, n_patches: int) -> sparse.csr_matrix:
        """The pairs as a boolean CSR matrix, stations x patches."""
        data = np.ones(len(self.station), dtype=bool)
        return sparse.csr_matrix((data, (self.station, self.patch)), shape=(n_stations, n_patches), dtype=bool)


def standing_zone(site: Site, xy: NDArray[np.float64], frames: NDArray[np.object_]) -> NDArray[np.int64]:
    """For each position (``xy`` in the zone frame ``frames``), the index of the first zone of its frame scanned from
    inside whose floor (outline less its blocks, the edge included) holds it; -1: none."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    frames = np.asarray(frames, dtype=object).reshape(-1)
    out = np.full(len(xy), -1, dtype=np.int64)
    for zi, zone in enumerate(site.zones):
        if ScanSide.INSIDE not in zone.scan_side.sides:
            continue
        todo = np.flatnonzero((out < 0) & (frames == zone.frame))
        if todo.size:
            out[todo[_standing(site, zi, xy[todo])]] = zi
    return out


def _standing(site: Site, zi: int, xy: NDArray) -> NDArray[np.bool_]:
    """For each point, True when it lies on zone ``zi``'s floor (its outline less every block; the edge counts)."""
    area = open_area(site, zi).buffer(EPS_PLAN_M, join_style="mitre")
    return np.asarray(shapely.covers(area, shapely.points(xy)))


@dataclass(frozen=True, eq=False)
class SurfaceLayer:
    """One zone's patches of one kind (``ts``: those no blocker meets), at one height offset ``dz`` from the
    instrument, the horizontal reach that range and incidence allow, and what can hide them."""

    patches: SurfaceTargets
    ts: NDArray[np.int64]
    tree: shapely.STRtree
    dz: float
    reach_m: float
    theta_deg: float
    blockers: PlanBlockers
    is_convex: NDArray[np.bool_]  # over all the patches
    blind_m: float  # the blind cone's radius in plan at the patches' height (0: no cone)


def surface_pairs(
    site: Site, patches: SurfaceTargets, xy: NDArray[np.float64], zone: NDArray[np.integer], limits: SurfaceLimits
) -> SurfacePairs:
    """Every (station, patch) pair in which the station sees the whole patch (the module's rules). ``xy`` (N, 2) are the
    stations in their zone's frame, ``zone`` (N,) the index in ``site.zones`` of the zone each stands in."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    zone = np.asarray(zone, dtype=np.int64).reshape(-1)
    if len(zone) != len(xy):
        raise ValueError(f"{len(xy)} stations but {len(zone)} zone indices")
    is_convex = patches.is_convex
    out: list[tuple[NDArray, ...]] = []
    for zi in np.unique(zone):
        here = np.flatnonzero(zone == zi)
        here = here[_standing(site, int(zi), xy[here])]
        for kind in (FLOOR, CEILING):
            layer = surface_layer(site, int(zi), kind, patches, limits, is_convex)
            if here.size == 0 or layer is None:
                continue
            step = max(1, PAIR_BATCH // len(layer.ts))  # stations per query: at most PAIR_BATCH pairs at once
            out += [_test_pairs(xy, here[k : k + step], layer, limits) for k in range(0, len(here), step)]
    if not out:
        e = np.zeros(0, np.int64)
        return SurfacePairs(e, e, np.zeros(0), np.zeros(0))
    st, pt, sl, inc = (np.concatenate(parts) for parts in zip(*out))
    order = np.lexsort((pt, st))
    return SurfacePairs(st[order], pt[order], sl[order], inc[order])


def surface_layer(
    site: Site, zi: int, kind: int, patches: SurfaceTargets, limits: SurfaceLimits, is_convex: NDArray[np.bool_]
) -> SurfaceLayer | None:
    """Zone ``zi``'s patches of ``kind`` that a station can see at all, with the horizontal reach that range and
    incidence allow; None when there are none (no such patches, a ceiling at or below the instrument, out of range)."""
    ts = np.flatnonzero((patches.zone == zi) & (patches.kind == kind))
    if ts.size == 0:
        return None
    ih = limits.instrument_height_m
    dz = float(patches.height_m[ts[0]] - (site.zones[zi].floor_level_m + ih))  # above (+) or below the instrument
    longest = limits.max_slant_range_m + EPS_RANGE_M
    if not (dz < 0 if kind == FLOOR else dz > 0) or abs(dz) >= longest:  # the instrument on the room side
        return None
    theta = limits.theta_for(kind)
    reach = math.sqrt(longest**2 - dz**2)
    if theta < 90.0:
        reach = min(reach, abs(dz) * math.tan(math.radians(theta + EPS_ANGLE_DEG)))
    # a floor is hidden by every block, a ceiling by the blocks that stand above the instrument; a ceiling patch over
    # such a block is hidden from every station
    blockers = plan_blockers(site, zi, 0.0 if kind == FLOOR else ih + REACH_TOL_M)
    ts = ts[~blockers.hits(patches.polygon[ts])]
    if ts.size == 0:
        return None
    half = limits.nadir_blind_half_angle_deg if dz < 0 else limits.zenith_blind_half_angle_deg
    blind = abs(dz) * math.tan(math.radians(max(half - EPS_ANGLE_DEG, 0.0))) if half is not None and half > 0 else 0.0
    tree = shapely.STRtree(patches.polygon[ts])
    return SurfaceLayer(patches, ts, tree, dz, reach, theta, blockers, is_convex, blind)


def _test_pairs(xy: NDArray, here: NDArray, layer: SurfaceLayer, limits: SurfaceLimits) -> tuple[NDArray, ...]:
    """The pairs of stations ``here`` and the layer's patches within its reach that meet every rule."""
    p, dz = layer.patches, layer.dz
    longest = limits.max_slant_range_m + EPS_RANGE_M
    cos_max = math.cos(math.radians(min(layer.theta_deg + EPS_ANGLE_DEG, 90.0)))
    si, pi = layer.tree.query(shapely.points(xy[here]), predicate="dwithin", distance=layer.reach_m + EPS_RANGE_M)
    s, t = here[si], layer.ts[pi]
    d = np.hypot(*(p.corners[t] - xy[s][:, None, :]).transpose(2, 0, 1))  # (pairs, K) horizontal distances
    slant = np.hypot(d, dz).max(axis=1)
    ok = (slant <= longest) & (abs(dz) / slant >= cos_max)  # the farthest corner has the largest incidence
    if layer.blind_m > 0:
        blind_r = layer.blind_m
        box = shapely.bounds(p.polygon[t[ok]])
        gap = np.maximum(np.maximum(box[:, :2] - xy[s[ok]], xy[s[ok]] - box[:, 2:]), 0.0)
        near = np.flatnonzero(ok)[np.hypot(gap[:, 0], gap[:, 1]) < blind_r]  # the box is never farther than the patch
        ok[near] &= shapely.distance(shapely.points(xy[s[near]]), p.polygon[t[near]]) >= blind_r
    idx = np.flatnonzero(ok)
    ok[idx] = fans_clear(layer.blockers, xy[s[idx]], p.corners[t[idx]], p.n_corners[t[idx]], layer.is_convex[t[idx]])
    s, t, slant = s[ok], t[ok], slant[ok]
    inc = np.degrees(np.arccos(np.clip(abs(dz) / slant, -1.0, 1.0)))
    return s.astype(np.int64), t.astype(np.int64), slant, inc


def surface_sight(
    site: Site, patches: SurfaceTargets, xy: NDArray[np.float64], zone: NDArray[np.integer], limits: SurfaceLimits
) -> sparse.csr_matrix:
    """Boolean CSR matrix, stations x patches: True where the station sees the whole patch."""
    return surface_pairs(site, patches, xy, zone, limits).matrix(len(np.asarray(xy).reshape(-1, 2)), len(patches))
