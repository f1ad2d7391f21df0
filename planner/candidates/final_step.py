"""The final step of the closed form (3.1.3, fig. 3.1): move misplaced candidates, drop redundant ones."""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from dataclasses import replace

import networkx as nx
import numpy as np
import scipy.sparse as sp

from planner.coverage.matrix import station_places
from planner.coverage.overlap import OverlapRule, overlap_graph
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Site

#: Fractions of the original stand-off tried, nearest to the original first.
SHRINK_STEPS = tuple(np.round(np.arange(0.95, 0.0, -0.05), 2))


def _anchor(site: Site, c: Candidate) -> np.ndarray | None:
    """The point a candidate moves toward when its stand-off is reduced: its vertex or its wall foot."""
    zone = site.zone(c.zone)
    xy = np.asarray(zone.xy)
    if c.kind is CandidateKind.VERTEX and c.vertex is not None:
        return xy[c.vertex - 1]
    if c.kind is CandidateKind.WALL and c.wall is not None and c.local_x_m is not None:
        start, end = xy[c.wall - 1], xy[c.wall % len(xy)]
        return start + c.local_x_m * (end - start) / np.hypot(*(end - start))
    return None


def misplacement(site: Site, c: Candidate, x: float, y: float) -> str:
    """Why a station of zone c.zone on side c.side cannot stand at (x, y); '' if it can."""
    places = station_places(site, np.array([[x, y]]), [c.frame])
    if places.reason[0]:
        return places.reason[0]
    zi = next(i for i, z in enumerate(site.zones) if z.id == c.zone)
    inside = bool(places.inside[0, zi])
    if inside != (c.side is ScanSide.INSIDE):
        return f"not {c.side.value} zone {c.zone}"
    return ""


def relocate(site: Site, candidates: list[Candidate]) -> tuple[list[Candidate], list[str]]:
    """Move each misplaced closed-form candidate toward its vertex or wall (HD or HD_0 reduced in 5 % steps) until it
    stands on its scan side, in the boundary, outside obstacles and no-go areas; drop it if no step works. Returns the
    candidates and a log line per change."""
    out, log = [], []
    for c in candidates:
        why = misplacement(site, c, c.x, c.y)
        if not why:
            out.append(c)
            continue
        anchor = _anchor(site, c)
        moved = None
        if anchor is not None:
            for f in SHRINK_STEPS:
                p = anchor + f * (np.array(c.xy) - anchor)
                if not misplacement(site, c, float(p[0]), float(p[1])):
                    moved = replace(
                        c,
                        x=float(p[0]),
                        y=float(p[1]),
                        hd_m=None if c.hd_m is None else c.hd_m * f,
                        local_y_m=None if c.local_y_m is None else c.local_y_m * f,
                    )
                    log.append(f"{c.id}: {why}; stand-off reduced to {f:.0%}")
                    break
        if moved is None:
            log.append(
                f"{c.id}: {why}; no position on the way to its {'vertex' if c.vertex else 'wall'} works, dropped"
            )
        else:
            out.append(moved)
    return out, log


def drop_redundant(
    by_candidate: sp.csr_matrix,
    groups: Sequence[Hashable],
    lengths: np.ndarray,
    rule: OverlapRule,
) -> list[int]:
    """Indices kept after removing candidates the plan does not need. A candidate is redundant when every target it sees
    stays seen without it AND its group (zone-side) keeps as few registration components as before (the closed form
    builds the required overlap into its spacing; dropping a station that bridges two others would break it). Candidates
    are tried from the one seeing the fewest targets (ties: the later one first), so the result is deterministic; the
    covered set never shrinks."""
    a = by_candidate.astype(np.int64).tocsr()
    count = np.asarray(a.sum(axis=0)).ravel()
    sizes = np.diff(a.indptr)
    keep = np.ones(a.shape[0], dtype=bool)
    for i in sorted(range(a.shape[0]), key=lambda i: (sizes[i], -i)):
        cols = a.indices[a.indptr[i] : a.indptr[i + 1]]
        if not np.all(count[cols] >= 2):
            continue
        members = [j for j in range(a.shape[0]) if keep[j] and groups[j] == groups[i]]
        before = nx.number_connected_components(overlap_graph(a, lengths, members, rule))
        after = nx.number_connected_components(overlap_graph(a, lengths, [j for j in members if j != i], rule))
        if members == [i] or after > before:
            continue
        keep[i] = False
        count[cols] -= 1
    return [i for i in range(a.shape[0]) if keep[i]]
