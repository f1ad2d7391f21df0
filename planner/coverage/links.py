"""Registration links through openings: two stations that see each other through a door, gate or window.

Across two zones (a room and the next room, a room and the ground outside) scans share almost no surface: each station's
targets are the faces of its own zone, and only the reveal of the opening is common. Cloud-to-cloud registration (ICP)
needs a common surface (seed 003: at least 30 % of the smaller scan), which such a pair does not have; target-based
registration needs common targets (at least 3, not in a line, seen from both stations). Through an opening both
conditions of the latter are met when the two stations see each other through it: targets set up in the opening and on
either side of it (spheres on the floor, the jambs, a checkerboard on the lintel) lie in both fields of view. So a
cross-zone link is measured as: the segment between the two stations crosses an opening, nothing else blocks it, and it
is no longer than the link limit.
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.core.errors import UsageError
from planner.coverage.matrix import blockers_for
from planner.coverage.openings import accessible_areas, opening_segments, space_of
from planner.coverage.stair_links import NO_WALL, link_matrix, stair_links
from planner.coverage.visibility import segments_touch, sight_clear
from planner.site.candidate import Candidate
from planner.site.model import SITE_FRAME, Site


def opening_links(
    site: Site, xy: NDArray[np.float64], frames: Sequence[str], spaces: Sequence[object], reach_m: float
) -> sp.csr_matrix:
    """Symmetric C x C boolean matrix: stations of different spaces that see each other through an opening (both within
    ``reach_m`` of it and of each other)."""
    frames_arr = np.asarray(frames, dtype=object)
    space_id = {s: k for k, s in enumerate(dict.fromkeys(spaces))}
    sid = np.array([space_id[s] for s in spaces], dtype=np.int64)
    rows: list[NDArray[np.int64]] = []
    cols: list[NDArray[np.int64]] = []
    for frame in dict.fromkeys(frames):
        segs = opening_segments(site, frame)
        if not segs:
            continue
        blockers = blockers_for(site, frame)
        here = np.flatnonzero(frames_arr == frame)
        for _zi, _w, _kind, ends in segs:
            mid = ends.mean(axis=0)
            near = here[np.hypot(*(xy[here] - mid).T) <= reach_m]
            if near.size < 2:
                continue
            m = np.repeat(mid[None], len(near), axis=0)
            near = near[sight_clear(xy[near], m, m, np.full(len(near), NO_WALL), blockers)]
            d = ends[1] - ends[0]
            side = np.sign(d[0] * (xy[near, 1] - ends[0][1]) - d[1] * (xy[near, 0] - ends[0][0]))
            left, right = near[side > 0], near[side < 0]
            if not left.size or not right.size:
                continue
            i, j = (g.ravel() for g in np.meshgrid(left, right, indexing="ij"))
            ok = (sid[i] != sid[j]) & (np.hypot(*(xy[i] - xy[j]).T) <= reach_m)
            i, j = i[ok], j[ok]
            e0, e1 = np.repeat(ends[:1], len(i), axis=0), np.repeat(ends[1:], len(i), axis=0)
            ok = segments_touch(xy[i], xy[j], e0, e1)
            i, j = i[ok], j[ok]
            ok = sight_clear(xy[i], xy[j], xy[j], np.full(len(i), NO_WALL), blockers)
            rows.append(i[ok])
            cols.append(j[ok])
    return link_matrix(rows, cols, len(xy))


REGISTRATION_MODES = ("zone", "site")


@dataclass(frozen=True)
class RegistrationDefault:
    """The registration scope a site gets when none is asked for: ``mode`` (``zone`` or ``site``) and ``reason``, the
    words the summary's registration line prints."""

    mode: str
    reason: str


def default_registration(site: Site) -> RegistrationDefault:
    """The scope of a site's registration when none is asked for, and why: ``site`` (one bundle per accessible area)
    where openings are given or the zones share one frame (placed, given in site coordinates, or read from one model;
    outdoors too), ``zone`` (one bundle per zone-side) for one zone or table zones each in its own frame; mixed frames:
    ``site`` where table zones were placed in the site frame, else ``zone``."""
    zones = site.zones
    n = len(zones)
    if any(z.openings for z in zones):
        return RegistrationDefault("site", "openings given: one bundle per accessible area, linked through them")
    if n == 1:
        return RegistrationDefault("zone", "one zone")
    frames = list(dict.fromkeys(z.frame for z in zones))
    if len(frames) == 1:
        where = "site coordinates" if frames[0] == SITE_FRAME else f"frame {frames[0]!r}"
        return RegistrationDefault("site", f"the {n} zones share one frame ({where}): one bundle per accessible area")
    placed = sum(z.frame == SITE_FRAME and z.closure is not None for z in zones)
    if placed:
        return RegistrationDefault(
            "site", f"{placed} of the {n} zones placed in the site frame: one bundle per accessible area"
        )
    if len(frames) == n:
        return RegistrationDefault(
            "zone", f"each of the {n} zones in its own frame: one bundle per zone-side, as the dissertation plans"
        )
    return RegistrationDefault("zone", f"the {n} zones in {len(frames)} frames, none placed: one bundle per zone-side")


def zone_side_groups(candidates: Sequence[Candidate], labels: Sequence[Hashable], links: sp.csr_matrix | None) -> bool:
    """True when registration groups ``labels`` (with ``links``) are the zone-sides: no link through an opening, and
    each group holds the candidates of exactly one zone-side (``site`` registration of rooms without doors and a single
    outside zone, or ``zone`` registration)."""
    if links is not None and links.nnz:
        return False
    pairs = {(label, (c.zone, c.side)) for label, c in zip(labels, candidates, strict=True)}
    return len(pairs) == len({p[0] for p in pairs}) == len({p[1] for p in pairs})


def registration_groups(
    site: Site, candidates: Sequence[Candidate], mode: str, reach_m: float
) -> tuple[tuple[Hashable, ...], sp.csr_matrix | None]:
    """Group label of each candidate and the links through openings (None in ``zone`` mode). ``zone``: one bundle per
    zone-side, as the dissertation plans; ``site``: one bundle per accessible area
    (:func:`planner.coverage.openings.accessible_areas`, storeys joined by the site's stairs), linked through openings
    and, across storeys, through the stairs (:func:`planner.coverage.stair_links.stair_links`)."""
    if mode not in REGISTRATION_MODES:
        raise UsageError(
            f"unknown registration mode (known: {', '.join(REGISTRATION_MODES)})", field="registration", value=mode
        )
    if mode == "zone":
        return tuple((c.zone, c.side.value) for c in candidates), None
    by_id = {z.id: z for z in site.zones}
    spaces = [space_of(by_id[c.zone], c.side) for c in candidates]
    areas = accessible_areas(site)
    xy = np.array([c.xy for c in candidates], dtype=float).reshape(-1, 2)
    links = opening_links(site, xy, [c.frame for c in candidates], spaces, reach_m)
    if site.stairs:
        links = (links + stair_links(site, xy, spaces, reach_m)).astype(bool).tocsr()
    return tuple(("area", areas[s]) for s in spaces), links
