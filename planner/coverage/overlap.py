"""The registration-overlap relation between stations (METHOD.md section 2, seed 003).

Two stations can be registered to each other when the wall length both of them
cover is at least ``overlap`` of the smaller of their two covered lengths,
optionally also at least ``min_shared_m`` metres and at most ``max_link_m``
apart (cloud-to-cloud registration degrades beyond 30-70 m, seed 003).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import networkx as nx
import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray


@dataclass(frozen=True)
class OverlapRule:
    overlap: float = 0.30
    min_shared_m: float = 0.0
    max_link_m: float | None = None


def piece_lengths(s0_m: NDArray[np.float64], s1_m: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.asarray(s1_m) - np.asarray(s0_m)


def overlap_graph(
    by_candidate: sp.csr_matrix, lengths: NDArray[np.float64], nodes: Sequence[int], rule: OverlapRule,
    xy: NDArray[np.float64] | None = None,
) -> nx.Graph:
    """Graph on ``nodes`` (candidate indices) with an edge wherever two can be registered.

    Edge attributes: ``shared_m`` (common covered wall length) and ``length_m``
    (distance between the stations, when ``xy`` is given).
    """
    nodes = list(nodes)
    g = nx.Graph()
    g.add_nodes_from(nodes)
    if len(nodes) < 2:
        return g
    sub = by_candidate[nodes].astype(np.float64)
    covered = np.asarray(sub @ lengths).ravel()
    shared = (sub @ sp.diags(lengths) @ sub.T).tocoo()
    for i, j, s in zip(shared.row, shared.col, shared.data):
        if i >= j:
            continue
        if s + 1e-9 < rule.overlap * min(covered[i], covered[j]) or s < rule.min_shared_m or s <= 0:
            continue
        attrs = {"shared_m": float(s)}
        if xy is not None:
            d = float(np.hypot(*(xy[nodes[i]] - xy[nodes[j]])))
            if rule.max_link_m is not None and d > rule.max_link_m:
                continue
            attrs["length_m"] = d
        g.add_edge(nodes[i], nodes[j], **attrs)
    return g
