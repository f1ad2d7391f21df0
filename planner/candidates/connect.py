"""Connectivity candidates: positions that link the two sides of a corner or an opening the pool cannot link across.

Under an overlap rule every registration group's stations must form one network, and two registered stations share
wall. So all the pieces a connected plan covers lie in one component of the graph that joins a candidate to the pieces
it sees (and to the candidates it is linked to through an opening): where the pool splits a group's pieces into several
components, no connected plan over the pool exists, whatever the solver does. That happens at outside corners, where
only a thin region sees a piece of both walls within theta_max, and no grid or ring of the pool need land in it.

:func:`connect_candidates` finds those splits (:func:`split_groups`, one sparse component count, so a pool that is
connected costs nothing more) and, for each junction of two components (two pieces that meet at a wall end, then the
nearest pairs across), adds the pole of the intersection of the two pieces' coverage regions, and the pole of that
intersection grown by the nearest pieces of both sides while it stays non-empty (a station that shares more with each
side). The coverage test decides what the new candidates see; a split left afterwards is for the plane proof
(:mod:`planner.bounds.corners`) or the solver to judge.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import shapely
from scipy.sparse.csgraph import connected_components

from planner.candidates.closed_form import side_candidate
from planner.candidates.from_regions import largest_part_pole
from planner.coverage.matrix import CoverageProblem, merge_problems
from planner.coverage.regions import FrameSpace, coverage_regions
from planner.coverage.sight import Sight
from planner.coverage.targets import SIDE_NAME
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide

#: the groups of candidates (a label per candidate) and their links through openings (None: none)
Groups = Callable[[Sequence[Candidate]], tuple[tuple[Hashable, ...], sp.csr_matrix | None]]
#: pairs of pieces tried per pair of components besides those that meet at a wall end (nearest first)
NEAREST_PAIRS = 4
#: pieces of either side tried when a junction's common region is grown (nearest first)
GROW_PIECES = 16
#: rounds of bridging (each round bridges every junction left, then the components are counted again)
ROUNDS = 3
#: a junction's common region smaller than this (m^2) gives no candidate
MIN_AREA_M2 = 1e-10
#: two piece ends closer than this meet (a corner of the wall chain)
MEET_M = 1e-6


@dataclass(frozen=True, kw_only=True)
class Split:
    """A registration group whose pieces the pool splits: the pieces (indices of the targets) and the component of
    each (0, 1, ...), over the graph of candidates, the pieces they see and their links."""

    label: Hashable
    pieces: np.ndarray
    component: np.ndarray

    @property
    def parts(self) -> int:
        return int(self.component.max()) + 1 if self.component.size else 0


def piece_groups(candidates: Sequence[Candidate], labels: Sequence[Hashable], problem: CoverageProblem) -> np.ndarray:
    """The registration group of each piece (an index into the distinct ``labels``; -1: no candidate of its zone-side),
    from the group of the candidates proposed for its zone-side."""
    t = problem.targets
    index: dict[Hashable, int] = {}
    by_side: dict[tuple[str, str], int] = {}
    for c, label in zip(candidates, labels, strict=True):
        by_side.setdefault((c.zone, c.side.value), index.setdefault(label, len(index)))
    table = np.array(
        [[by_side.get((z, SIDE_NAME[s]), -1) for s in (0, 1)] for z in t.zone_ids], dtype=np.int64
    ).reshape(-1, 2)
    return table[np.asarray(t.zone, dtype=np.int64), np.asarray(t.side, dtype=np.int64)]


def split_groups(problem: CoverageProblem, groups: Groups) -> list[Split]:
    """The registration groups whose pieces (those a candidate of the group sees) lie in more than one component of
    the graph of the group's candidates, the pieces they see and their links: groups with no connected plan over the
    pool. Asked first per zone-side, without links (no group is formed: the links through openings cost seconds on a
    site with doors); only where a zone-side's own candidates split its pieces are the groups formed and asked."""
    cands = problem.candidates
    if not splits_of(problem, tuple((c.zone, c.side.value) for c in cands), None):
        return []
    labels, links = groups(cands)
    return splits_of(problem, labels, links)


def splits_of(problem: CoverageProblem, labels: Sequence[Hashable], links: sp.csr_matrix | None) -> list[Split]:
    """:func:`split_groups` for the groups ``labels`` (one per candidate) and their ``links``."""
    cands = problem.candidates
    distinct = list(dict.fromkeys(labels))
    index = {label: k for k, label in enumerate(distinct)}
    gid = np.array([index[label] for label in labels], dtype=np.int64)
    pg = piece_groups(cands, labels, problem)
    a = problem.by_candidate.tocoo()
    keep = gid[a.row] == pg[a.col]  # a candidate links only the pieces of its own group
    c, t = len(cands), a.shape[1]
    rows, cols = [a.row[keep]], [c + a.col[keep]]
    if links is not None and links.nnz:
        lk = sp.coo_matrix(links)
        same = gid[lk.row] == gid[lk.col]
        rows, cols = [*rows, lk.row[same]], [*cols, lk.col[same]]
    r, k = np.concatenate(rows), np.concatenate(cols)
    graph = sp.csr_matrix((np.ones(r.size, dtype=bool), (r, k)), shape=(c + t, c + t))
    _, comp = connected_components(graph, directed=False)
    seen = np.zeros(t, dtype=bool)
    seen[a.col[keep]] = True
    out = []
    for g, label in enumerate(distinct):
        pieces = np.flatnonzero((pg == g) & seen)
        labels_here = comp[c + pieces]
        if np.unique(labels_here).size > 1:
            _, dense = np.unique(labels_here, return_inverse=True)
            out.append(Split(label=label, pieces=pieces, component=dense))
    return out


def junctions(problem: CoverageProblem, split: Split) -> list[tuple[int, int]]:
    """Pairs of pieces of different components to bridge: those that meet at a wall end (a corner, the two sides of
    a joint), then for each pair of components its :data:`NEAREST_PAIRS` nearest pairs by midpoint."""
    t = problem.targets
    p, comp = split.pieces, split.component
    a, b = np.asarray(t.a)[p], np.asarray(t.b)[p]
    mid = (a + b) / 2.0
    out: dict[tuple[int, int], None] = {}
    for i in range(p.size):  # ends that meet
        meet = np.flatnonzero(
            (comp != comp[i])
            & (
                (np.hypot(*(a - b[i]).T) < MEET_M)
                | (np.hypot(*(b - a[i]).T) < MEET_M)
                | (np.hypot(*(a - a[i]).T) < MEET_M)
                | (np.hypot(*(b - b[i]).T) < MEET_M)
            )
        )
        for j in meet:
            out[(int(min(p[i], p[j])), int(max(p[i], p[j])))] = None
    for u in range(split.parts):
        for v in range(u + 1, split.parts):
            iu, iv = np.flatnonzero(comp == u), np.flatnonzero(comp == v)
            d = np.hypot(*(mid[iu][:, None, :] - mid[iv][None, :, :]).transpose(2, 0, 1))
            for flat in np.argsort(d, axis=None, kind="stable")[:NEAREST_PAIRS]:
                x, y = np.unravel_index(int(flat), d.shape)
                out[(int(min(p[iu[x]], p[iv[y]])), int(max(p[iu[x]], p[iv[y]])))] = None
    return list(out)


def _grown(
    problem: CoverageProblem,
    split: Split,
    pair: tuple[int, int],
    regions: dict[int, shapely.Geometry],
    draw: Callable[[list[int]], None],
) -> list[shapely.Geometry]:
    """The common region of the pair, and that region grown by the nearest pieces of both sides while it stays
    non-empty (empty list: the pair's regions do not meet)."""
    t = problem.targets
    common = regions[pair[0]].intersection(regions[pair[1]])
    if common.is_empty or common.area <= MIN_AREA_M2:
        return []
    centre = (np.asarray(t.a)[list(pair)] + np.asarray(t.b)[list(pair)]).mean(axis=0) / 2.0
    mid = (np.asarray(t.a)[split.pieces] + np.asarray(t.b)[split.pieces]) / 2.0
    near = [int(split.pieces[i]) for i in np.argsort(np.hypot(*(mid - centre).T), kind="stable")]
    near = [k for k in near if k not in pair][:GROW_PIECES]
    draw(near)
    grown = common
    for k in near:
        both = grown.intersection(regions[k])
        if not both.is_empty and both.area > MIN_AREA_M2:
            grown = both
    return [common] if grown.equals(common) else [common, grown]


def connect_candidates(
    sight: Sight,
    problem: CoverageProblem,
    groups: Groups,
    spaces: dict[str, FrameSpace] | None = None,
    cache: dict[int, shapely.Geometry] | None = None,
) -> tuple[CoverageProblem, list[str]]:
    """``problem`` with connectivity candidates wherever the pool splits a registration group's pieces (module
    docstring), and log lines (none where the pool was connected: then nothing is drawn or added)."""
    spaces = {} if spaces is None else spaces
    cache = {} if cache is None else cache
    t = problem.targets
    log: list[str] = []

    def draw(pieces: list[int]) -> None:
        missing = [k for k in dict.fromkeys(pieces) if k not in cache]
        if missing:
            cache.update(coverage_regions(sight.site, t, sight.limits, missing, spaces))

    added, tried = 0, set[tuple[str, str, float, float]]()  # positions tried in any round (else retried)
    for n in range(ROUNDS):
        splits = split_groups(problem, groups)
        if not splits:
            break
        new: list[Candidate] = []
        for split in splits:
            pairs = junctions(problem, split)
            draw([k for pair in pairs for k in pair])
            for pair in pairs:
                for region in _grown(problem, split, pair, cache, draw):
                    pole = largest_part_pole(region, min_tolerance_m=1e-7)
                    for k in dict.fromkeys(pair):  # a station of either side (both sides of an opening)
                        zone, side = t.zone_ids[int(t.zone[k])], ScanSide(SIDE_NAME[int(t.side[k])])
                        name = f"L{n + 1}.{len(new) + 1}"
                        new.append(side_candidate(zone, side, t.frames[int(t.frame[k])], name, pole.x, pole.y, KIND))
        new = [c for c in _distinct(new) if _key(c) not in tried]
        tried.update(_key(c) for c in new)
        if not new:
            break
        problem = merge_problems(problem, sight.coverage(new, t))
        added += len(new)
        log.append(
            f"connectivity candidates: {len(splits)} registration group(s) split by the pool "
            f"({', '.join(f'{_name(s.label)} in {s.parts} parts' for s in splits[:4])}); {len(new)} added"
        )
    if added:
        left = split_groups(problem, groups)
        log.append(
            "connectivity candidates: every group's pieces joined"
            if not left
            else "connectivity candidates: still split: "
            + ", ".join(f"{_name(s.label)} in {s.parts} parts" for s in left)
        )
    return problem, log


#: the kind of a connectivity candidate (a point of the arrangement of coverage regions)
KIND = CandidateKind.REGION


def is_link(c: Candidate) -> bool:
    """A connectivity candidate (its name ``L<round>.<n>``)."""
    return c.kind is KIND and c.id.rsplit("-", 1)[-1].startswith("L")


def _key(c: Candidate) -> tuple[str, str, float, float]:
    return (c.zone, c.side.value, round(c.x, 7), round(c.y, 7))


def _distinct(cands: list[Candidate]) -> list[Candidate]:
    """One candidate per (zone, side, position)."""
    seen: set[tuple[str, str, float, float]] = set()
    out = []
    for c in cands:
        key = _key(c)
        if key not in seen:
            seen.add(key)
            out.append(c)
    return out


def _name(label: Hashable) -> str:
    """A group label in words (``zone/side`` or ``area k``)."""
    if isinstance(label, tuple) and len(label) == 2 and label[0] == "area":
        return f"area {label[1]}"
    return "/".join(str(x) for x in label) if isinstance(label, tuple) else str(label)
