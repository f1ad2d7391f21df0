"""The registration-overlap relation between stations (docs/method.md section 5, seed 003).

Two stations can be registered to each other when the wall length both of them cover is at least ``overlap`` of the
smaller of their two covered lengths, optionally also at least ``min_shared_m`` metres and at most ``max_link_m`` apart
(cloud-to-cloud registration degrades beyond 30-70 m, seed 003). Stations are related only within one group: a zone-side
(``--registration zone``) or an accessible area of the site (``--registration site``). Within a site's area, stations of
different zones are also related by ``links``: they see each other through an opening (see :mod:`planner.coverage.links`
for why that, and not shared wall, is the measure across zones).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Hashable, Sequence
from dataclasses import dataclass

import networkx as nx
import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.core.checks import real
from planner.core.errors import UsageError
from planner.coverage.gram import filtered_gram

#: the overlap share when none is given (the dissertation's O = 30 %)
DEFAULT_OVERLAP = 0.30


@dataclass(frozen=True)
class OverlapRule:
    overlap: float = DEFAULT_OVERLAP
    min_shared_m: float = 0.0
    max_link_m: float | None = None

    def __post_init__(self) -> None:
        real(self.overlap, "overlap", at_least=0.0)
        if not self.overlap < 1.0:
            raise UsageError("must be in [0, 1)", field="overlap", value=self.overlap)
        real(self.min_shared_m, "min_shared_m", at_least=0.0, infinite_ok=True)  # inf: links given explicitly only
        if self.max_link_m is not None:
            real(self.max_link_m, "max_link_m", above=0.0, infinite_ok=True)


def rule_of(share: float, min_shared_m: float = 0.0, max_link_m: float | None = None) -> OverlapRule:
    """The overlap rule of a share of wall (with the optional shared-length and distance limits): the one place a rule
    is built from a share. Share 0 still links any two stations that share wall (checking, surveys)."""
    return OverlapRule(share, min_shared_m, max_link_m)


def planning_rule(share: float, min_shared_m: float = 0.0, max_link_m: float | None = None) -> OverlapRule | None:
    """The rule a plan must satisfy for a share: ``None`` for share 0 (no registration required), the one place that
    decides "overlap 0 means off"."""
    return None if share == 0 else rule_of(share, min_shared_m, max_link_m)


@dataclass(frozen=True, kw_only=True)
class SiteShare:
    """The registration rule at the site's own overlap share, with these extra limits: what a plan's options ask for
    until the run is resolved against its site (:func:`planner.plan.problem.resolve`), where :meth:`rule` gives the rule
    in force (``None`` for share 0)."""

    min_shared_m: float = 0.0
    max_link_m: float | None = None

    def __post_init__(self) -> None:
        real(self.min_shared_m, "min_shared_m", at_least=0.0, infinite_ok=True)
        if self.max_link_m is not None:
            real(self.max_link_m, "max_link_m", above=0.0, infinite_ok=True)

    def rule(self, share: float) -> OverlapRule | None:
        """The rule at ``share`` (the site's, or :data:`DEFAULT_OVERLAP` where no site is at hand)."""
        return planning_rule(share, self.min_shared_m, self.max_link_m)


#: the default registration requirement of a plan: the site's overlap share, no extra limits
SITE_SHARE = SiteShare()
#: a rule no shared wall meets: stations relate only by links given explicitly
LINKS_ONLY = rule_of(0.0, min_shared_m=math.inf)


def group_ids(groups: Sequence[Hashable]) -> NDArray[np.int64]:
    """The index of each item's group, groups numbered in order of first appearance."""
    index: dict[Hashable, int] = {}
    return np.array([index.setdefault(g, len(index)) for g in groups], dtype=np.int64)


def piece_lengths(s0_m: NDArray[np.float64], s1_m: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.asarray(s1_m) - np.asarray(s0_m)


Pairs = Callable[[NDArray[np.int64], NDArray[np.int64]], NDArray[np.bool_]]


def link_filter(
    rule: OverlapRule,
    covered: NDArray[np.float64],
    gid: NDArray[np.int64] | None = None,
    xy: NDArray[np.float64] | None = None,
) -> tuple[Pairs, Callable[[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]], NDArray[np.bool_]]]:
    """The rule as two tests on index pairs: ``allowed(r, c)`` (not the same, one group, within ``max_link_m``) and
    ``keep(r, c, shared)`` (allowed, and sharing > 0, >= ``overlap`` of the smaller of the two ``covered`` lengths and
    >= ``min_shared_m``): the one home of "registered" for a coverage matrix."""

    def allowed(r: NDArray[np.int64], c: NDArray[np.int64]) -> NDArray[np.bool_]:
        ok = r != c
        if gid is not None:
            ok &= gid[r] == gid[c]
        if rule.max_link_m is not None and xy is not None:
            ok &= np.hypot(*(xy[r] - xy[c]).T) <= rule.max_link_m
        return ok

    def keep(r: NDArray[np.int64], c: NDArray[np.int64], v: NDArray[np.float64]) -> NDArray[np.bool_]:
        rule_ok = (v > 0) & (v + 1e-9 >= rule.overlap * np.minimum(covered[r], covered[c])) & (v >= rule.min_shared_m)
        return rule_ok & allowed(r, c)

    return allowed, keep


def overlap_adjacency(
    by_candidate: sp.csr_matrix,
    lengths: NDArray[np.float64],
    rule: OverlapRule,
    groups: Sequence[Hashable] | None = None,
    xy: NDArray[np.float64] | None = None,
    links: sp.spmatrix | None = None,
) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Symmetric C x C adjacency of the overlap relation, and the shared length (m) on the same pattern. One sparse
    product (in row blocks, :func:`planner.coverage.gram.filtered_gram`) gives every pair's shared wall length; the
    rule, groups and distance filter each block. ``links`` (C x C, symmetric): further related pairs (seen through an
    opening), kept under the same group and distance rules."""
    a = by_candidate.astype(np.float64).tocsr()
    n = a.shape[0]
    gid = group_ids(groups) if groups is not None else None
    allowed, keep = link_filter(rule, np.asarray(a @ lengths).ravel(), gid, xy)

    share = filtered_gram(a, lengths, keep)
    if links is not None and links.nnz:
        # pairs related through an opening join with shared length 0 (explicit entries)
        lk, sh = sp.coo_matrix(links), share.tocoo()
        ok = allowed(lk.row.astype(np.int64), lk.col.astype(np.int64))
        rows, cols = np.concatenate([sh.row, lk.row[ok]]), np.concatenate([sh.col, lk.col[ok]])
        share = sp.csr_matrix((np.concatenate([sh.data, np.zeros(int(ok.sum()))]), (rows, cols)), shape=(n, n))
    share.sum_duplicates()
    adj = sp.csr_matrix((np.ones(share.nnz, dtype=bool), share.indices.copy(), share.indptr.copy()), shape=(n, n))
    return adj, share


def overlap_graph(
    by_candidate: sp.csr_matrix,
    lengths: NDArray[np.float64],
    nodes: Sequence[int],
    rule: OverlapRule,
    xy: NDArray[np.float64] | None = None,
    links: sp.spmatrix | None = None,
) -> nx.Graph:
    """Graph on ``nodes`` (candidate indices) with an edge wherever two can be registered. Edge attributes: ``shared_m``
    (common covered wall length; 0 for a link through an opening, ``links`` being C x C over all candidates) and, with
    ``xy``, ``length_m``."""
    nodes = list(nodes)
    g = nx.Graph()
    g.add_nodes_from(nodes)
    if len(nodes) < 2:
        return g
    sub_xy = None if xy is None else xy[nodes]
    sub_links = None if links is None else sp.csr_matrix(links)[nodes][:, nodes]
    adj, share = overlap_adjacency(by_candidate[nodes], lengths, rule, xy=sub_xy, links=sub_links)
    coo = sp.triu(adj, k=1).tocoo()
    shared = np.asarray(share.tocsr()[coo.row, coo.col]).ravel()  # one look-up for every edge, not one per edge
    ids = np.asarray(nodes)
    if sub_xy is None:
        g.add_edges_from(
            (int(ids[i]), int(ids[j]), {"shared_m": float(m)}) for i, j, m in zip(coo.row, coo.col, shared)
        )
        return g
    length = np.hypot(*(sub_xy[coo.row] - sub_xy[coo.col]).T)
    g.add_edges_from(
        (int(ids[i]), int(ids[j]), {"shared_m": float(m), "length_m": float(d)})
        for i, j, m, d in zip(coo.row, coo.col, shared, length)
    )
    return g
