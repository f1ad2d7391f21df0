"""Stitching tile plans into one site plan.

The union of the tiles' plans covers every piece (each tile's plan covers its core). On the site's whole coverage
matrix and overlap relation (shared wall over every piece a station sees, not only a tile's), stations are then

1. pruned: in order of fewest pieces seen (ties by index), a station is dropped when every piece stays covered
   and its registration group does not fall into more parts;
2. joined: :func:`planner.solve.connectivity.repair` adds the cheapest chains of stations between the parts of
   each group (shortest paths in the overlap graph);
3. pruned again.

The other starts and the choice among them: :func:`planner.tiles.search.best_plan`.
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from planner.solve.connectivity import components, group_members, repair


def _group_parts(adj: sp.csr_matrix, groups: Sequence[str], chosen: Sequence[int], g: str) -> int:
    return len(components(adj, [i for i in chosen if groups[i] == g]))


def group_parts(adj: sp.csr_matrix, groups: Sequence[str], chosen: Sequence[int]) -> dict[Hashable, int]:
    """The registration parts of each group among the stations ``chosen`` (1: connected)."""
    return {g: len(components(adj, m)) for g, m in group_members(groups, chosen).items()}


def prune(a: sp.csr_matrix, adj: sp.csr_matrix, groups: Sequence[str], chosen: Sequence[int]) -> list[int]:
    """Drop stations that no piece needs and whose removal splits no registration group further."""
    keep = sorted(int(i) for i in chosen)
    count = np.asarray(a[keep].astype(np.int64).sum(axis=0)).ravel()
    seen = {i: a.indices[a.indptr[i] : a.indptr[i + 1]] for i in keep}
    for i in sorted(keep, key=lambda i: (len(seen[i]), i)):
        if np.any(count[seen[i]] <= 1):
            continue
        before = _group_parts(adj, groups, keep, groups[i])
        rest = [j for j in keep if j != i]
        if _group_parts(adj, groups, rest, groups[i]) > before:
            continue
        keep = rest
        count[seen[i]] -= 1
    return keep


@dataclass(frozen=True, kw_only=True)
class Stitched:
    """The site plan made from the tiles': ``selected`` (global indices), how many stations the union, the pruning
    and the joining chains held, and the parts of each group at the end."""

    selected: tuple[int, ...]
    union: int
    pruned: int
    added: int
    parts: dict[Hashable, int]
    source: str = "tile plans"
    tried: dict[str, int] | None = None


def stitch(
    a: sp.csr_matrix, adj: sp.csr_matrix, groups: Sequence[str], tile_plans: Sequence[Sequence[int]]
) -> Stitched:
    """Union, prune, join, prune (module docstring)."""
    union = sorted({int(i) for plan in tile_plans for i in plan})
    first = prune(a, adj, groups, union)
    joined = repair(adj, np.ones(a.shape[0]), groups, first)
    joined = first if joined is None else joined
    final = prune(a, adj, groups, joined)
    return Stitched(
        selected=tuple(final),
        union=len(union),
        pruned=len(union) - len(first),
        added=len(joined) - len(first),
        parts=group_parts(adj, groups, final),
    )
