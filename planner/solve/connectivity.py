"""Connectivity of the chosen stations under the overlap relation: checks, cuts, repair, connected greedy.

The registration constraint says: within each group (zone, side) the chosen stations form a connected graph under the
overlap relation. It is enforced lazily: solve without it, find the components of each group's choice, and for a
component S add the cut

    sum_{v in N(S)} x_v >= x_i + x_j - 1        (i in S, j chosen outside S)

where N(S) are the candidates adjacent to S but not in it: if i and j are both chosen, some station must stand next to
S to lead out of it. The cut is valid for every connected choice, so the relaxation's optimum is a lower bound.
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components, dijkstra

from planner.coverage.overlap import group_ids
from planner.solve.bundles import bundle_cover, induced

Cut = tuple[np.ndarray, np.ndarray, float]  # (indices, coefficients, lower bound)


def group_members(groups: Sequence[Hashable], selected: Sequence[int]) -> dict[Hashable, list[int]]:
    out: dict[Hashable, list[int]] = {}
    for i in selected:
        out.setdefault(groups[i], []).append(int(i))
    return out


def components(adj: sp.csr_matrix, nodes: Sequence[int]) -> list[list[int]]:
    """Connected components of the subgraph induced by ``nodes``, each sorted, largest first."""
    nodes = sorted(nodes)
    if len(nodes) <= 1:
        return [nodes] if nodes else []
    sub = induced(adj, nodes)
    n, label = connected_components(sub, directed=False)
    comps = [[nodes[k] for k in np.flatnonzero(label == c)] for c in range(n)]
    return sorted(comps, key=lambda c: (-len(c), c[0]))


def disconnected_groups(
    adj: sp.csr_matrix, groups: Sequence[Hashable], selected: Sequence[int]
) -> dict[Hashable, list[list[int]]]:
    """Groups whose chosen stations fall apart, with their components."""
    comps = {g: components(adj, members) for g, members in group_members(groups, selected).items()}
    return {g: c for g, c in comps.items() if len(c) > 1}


def connectivity_cuts(
    adj: sp.csr_matrix, comps: list[list[int]], a: sp.csr_matrix | None = None, essential: np.ndarray | None = None
) -> list[Cut]:
    """Cuts that the current components violate (module docstring). For each component S, its region R(S) holds the
    candidates strictly closer (in overlap steps) to S than to any other component; R(S)'s boundary N(R) then holds no
    chosen station. When R(S) cannot cover every *essential* target of the group (a target only that group's candidates
    see), a connected plan that uses any station i of R(S) must leave R(S), so sum_{v in N(R)} x_v >= x_i for every i in
    R(S): one cut per candidate of the region, which rules out every disconnected plan with a part inside it; and, S
    being inside R, sum_{v in N(S)} x_v >= sum_{s in S} x_s - |S| + 1 (S whole needs a chosen neighbour), which also
    cuts S off wherever the other parts stand. Otherwise the pairwise cut (with a station j of another component) is
    used.
    """
    n = adj.shape[0]
    dist = np.vstack([dijkstra(adj, directed=False, indices=c, unweighted=True, min_only=True) for c in comps])
    cuts: list[Cut] = []
    for k, comp in enumerate(comps):
        others = np.delete(dist, k, axis=0).min(axis=0) if len(comps) > 1 else np.full(n, np.inf)
        region = np.isfinite(dist[k]) & (dist[k] < others)
        boundary = (np.asarray(adj[np.flatnonzero(region)].sum(axis=0)).ravel() > 0) & ~region
        nb = np.flatnonzero(boundary)
        strong = False
        if a is not None and essential is not None:
            seen = np.asarray(a[np.flatnonzero(region)].sum(axis=0)).ravel() > 0
            strong = bool(np.any(essential & ~seen))
        near = np.asarray(adj[comp].sum(axis=0)).ravel() > 0
        near[comp] = False
        ns = np.flatnonzero(near)  # N(S)
        if strong:
            ones = np.ones(len(nb))
            for i in np.flatnonzero(region):
                cuts.append((np.append(nb, i).astype(np.int64), np.append(ones, -1.0), 0.0))
            if len(comp) > 1:  # S itself needs a chosen neighbour: sum_{N(S)} x >= sum_{s in S} x_s - |S| + 1
                idx = np.concatenate([ns, comp]).astype(np.int64)
                cuts.append((idx, np.concatenate([np.ones(len(ns)), -np.ones(len(comp))]), 1.0 - len(comp)))
            continue
        for j, other in enumerate(comps):
            if j != k:
                idx = np.concatenate([ns, [comp[0], other[0]]]).astype(np.int64)
                cuts.append((idx, np.concatenate([np.ones(len(ns)), [-1.0, -1.0]]), -1.0))
    return cuts


def neighbour_cuts(
    adj: sp.csr_matrix, a: sp.csr_matrix, groups: Sequence[Hashable], essential: dict[Hashable, np.ndarray]
) -> list[Cut]:
    """x_i <= sum of its overlap neighbours, for every candidate that alone misses an essential target of its group: a
    station that cannot do the group's work alone needs a registration partner."""
    cuts: list[Cut] = []
    for i in range(a.shape[0]):
        ess = essential.get(groups[i])
        if ess is None or not ess.any():
            continue
        seen = np.zeros(a.shape[1], dtype=bool)
        seen[a.indices[a.indptr[i] : a.indptr[i + 1]]] = True
        if np.any(ess & ~seen):
            nb = adj.indices[adj.indptr[i] : adj.indptr[i + 1]]
            cuts.append((np.append(nb, i).astype(np.int64), np.append(np.ones(len(nb)), -1.0), 0.0))
    return cuts


def essential_targets(a: sp.csr_matrix, groups: Sequence[Hashable]) -> dict[Hashable, np.ndarray]:
    """Per group, the targets that only that group's candidates see."""
    gid = group_ids(groups)
    g = sp.csr_matrix((np.ones(len(gid)), (gid, np.arange(len(gid)))), shape=(int(gid.max(initial=-1)) + 1, len(gid)))
    per_group = (g @ a.astype(np.float64)).tocsc()  # groups x targets: how many candidates of each group see t
    seen_by = np.diff((per_group > 0).astype(np.int64).tocsc().indptr)
    out = {}
    for grp, k in dict(zip(groups, gid.tolist())).items():
        row = np.asarray(per_group[k].todense()).ravel() > 0
        out[grp] = row & (seen_by == 1)
    return out


def path_to_nearest(weights: sp.csr_matrix, sources: Sequence[int], wanted: np.ndarray) -> list[int] | None:
    """Nodes (excluding the sources) of the cheapest path from ``sources`` to any node where ``wanted``."""
    dist, pred, _ = dijkstra(weights, directed=True, indices=list(sources), min_only=True, return_predecessors=True)
    hits = np.flatnonzero(wanted & np.isfinite(dist))
    if hits.size == 0:
        return None
    target = int(hits[np.argmin(dist[hits])])
    path, v = [], target
    src = {int(x) for x in sources}
    while v >= 0 and v not in src:
        path.append(int(v))
        v = pred[v]
    return path


def repair(
    adj: sp.csr_matrix, cost: np.ndarray, groups: Sequence[Hashable], selected: Sequence[int]
) -> list[int] | None:
    """Each group's choice made connected by the cheapest chains of stations between its components (None if some
    cannot be joined)."""
    chosen = {int(i) for i in selected}
    # edge u->v weighs cost[v]: a path's length is the cost of the stations it adds
    weights = adj.astype(np.float64).multiply(np.asarray(cost, dtype=float)[None, :]).tocsr()
    for g, members in group_members(groups, sorted(chosen)).items():
        comps = components(adj, members)
        while len(comps) > 1:
            wanted = np.zeros(adj.shape[0], dtype=bool)
            wanted[[v for c in comps[1:] for v in c]] = True
            path = path_to_nearest(weights, comps[0], wanted)
            if path is None:
                return None
            chosen.update(path)
            comps = components(adj, [v for v in chosen if groups[v] == g])
    return sorted(chosen)


#: a cover of ``need`` whose every group's stations are connected under ``adj``, sorted, or None
#: (:func:`planner.solve.bundles.bundle_cover`: phases, invariants, complexity, references)
connected_greedy = bundle_cover
