"""Fewer stations for a connected plan: a swap local search under the registration rule.

Given a connected cover P of n stations (every target seen, every group's stations one component
of the overlap graph), :func:`shrink` looks for one of n - 1 stations, then n - 2, and so on: it drops
a station and then swaps one chosen station for one unchosen station at a time, minimising

    f(S) = sum of the weights of the targets S leaves unseen + w_link * sum_g (parts of g in S - 1)

until f = 0 (a connected cover one station smaller) or the move budget is spent. The weights of the
targets left unseen, and w_link while S is in pieces, grow by one after every move (the weighting
scheme of set-cover local search: Gao et al., "An efficient local search heuristic with row weighting
for the unicost set covering problem", EJOR 246(3), 2015), and the two stations of a swap may not be
swapped back for a few moves (tabu). Ties go to the lowest (station, candidate) index, so the result
depends only on the input and the move budget: no clock, no random numbers.

Every move is scored for all pairs at once: with cnt[t] the number of chosen seers of t,

    f(S - s + c) - f(S) = loss(s) - gain(c) - both(s, c) + w_link * change in parts,

loss(s) the weight of the targets only s sees, gain(c) that of the unseen targets c sees, both(s, c)
that of the targets only s sees that c also sees (one sparse-dense product A @ Only). A candidate c
joining S - s merges the parts it is linked to: parts(S - s + c) = parts(S - s) + 1 - (parts c is
linked to) within c's group. One move costs O(nnz(A) * n) arithmetic; unit costs only (the objective
is the number of stations).
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence

import numpy as np
import scipy.sparse as sp

#: moves a swapped-out station may not come back, and a swapped-in one may not leave
TABU_MOVES = 3


def shrink(a: sp.csr_matrix, adj: sp.csr_matrix, groups: Sequence[Hashable], plan: Sequence[int],
           moves: int = 2000, floor: int = 1) -> list[int]:
    """The smallest connected cover found from ``plan`` by dropping a station and repairing by swaps.

    Parameters
    ----------
    a
        C x T boolean CSR coverage matrix (the targets to cover are those ``plan`` covers).
    adj
        C x C symmetric overlap adjacency; links join candidates of one group only.
    groups
        Registration group of each candidate.
    plan
        A connected cover (returned unchanged when no smaller one is found).
    moves
        Swap budget for each size tried.
    floor
        Stop at this many stations (a proven lower bound).

    Returns
    -------
    list[int]
        A connected cover, sorted, no larger than ``plan``.
    """
    best = sorted(int(i) for i in plan)
    a = a.astype(np.float64).tocsr()
    need = np.asarray(a[best].sum(axis=0)).ravel() > 0
    adj = adj.astype(bool).tocsr()
    gid = _group_ids(groups)
    while len(best) > max(floor, 1):
        found = _search(a, adj, gid, need, best, moves)
        if found is None:
            break
        best = found
    return best


def _group_ids(groups: Sequence[Hashable]) -> np.ndarray:
    index: dict[Hashable, int] = {}
    return np.array([index.setdefault(g, len(index)) for g in groups], dtype=np.int64)


def _search(a: sp.csr_matrix, adj: sp.csr_matrix, gid: np.ndarray, need: np.ndarray, plan: list[int],
            moves: int) -> list[int] | None:
    """A connected cover of len(plan) - 1 stations, or None within ``moves`` swaps."""
    weight = need.astype(np.float64)
    # drop the station whose loss is smallest (ties: lowest index): the search starts near a cover
    cnt = np.asarray(a[plan].sum(axis=0)).ravel()
    only = [(float(weight[(a[s].toarray().ravel() > 0) & (cnt == 1)].sum()), s) for s in plan]
    chosen = [s for s in plan if s != min(only)[1]]
    w_link = 1.0
    tabu = np.zeros(a.shape[0], dtype=np.int64)  # move number until which a candidate may not move
    in_s = np.zeros(a.shape[0], dtype=bool)
    in_s[chosen] = True
    for step in range(moves):
        cnt = np.asarray(a[chosen].sum(axis=0)).ravel()
        unseen = need & (cnt == 0)
        parts = _parts(adj, gid, chosen)
        if not unseen.any() and parts == 0:
            return sorted(chosen)
        s_k, c = _best_swap(a, adj, gid, chosen, in_s, cnt, weight, w_link, tabu, step)
        if c < 0:
            return None
        out = chosen[s_k]
        chosen[s_k] = c
        in_s[out], in_s[c] = False, True
        tabu[out] = tabu[c] = step + TABU_MOVES
        cnt = np.asarray(a[chosen].sum(axis=0)).ravel()
        weight[need & (cnt == 0)] += 1.0
        if _parts(adj, gid, chosen) > 0:
            w_link += 1.0
    return None


def _labels(sub: np.ndarray) -> np.ndarray:
    """Component label (lowest member index) of each node of a small dense adjacency matrix."""
    if len(sub) == 0:
        return np.zeros(0, dtype=np.int64)
    reach = sub | np.eye(len(sub), dtype=bool)
    while True:  # transitive closure by squaring: O(n^3 log n), n = stations in the plan
        nxt = (reach.astype(np.int64) @ reach.astype(np.int64)) > 0
        if (nxt == reach).all():
            return np.argmax(reach, axis=1)
        reach = nxt


def _parts(adj: sp.csr_matrix, gid: np.ndarray, chosen: Sequence[int]) -> int:
    """sum over groups of (components - 1) of the chosen stations."""
    idx = np.asarray(chosen, dtype=np.int64)
    return _parts_of(adj[idx][:, idx].toarray().astype(bool), gid[idx])


def _parts_of(sub: np.ndarray, gid: np.ndarray) -> int:
    """sum over groups of (components - 1) of the stations of the dense adjacency ``sub``."""
    return int(np.unique(_labels(sub)).size - np.unique(gid).size)


def _best_swap(a: sp.csr_matrix, adj: sp.csr_matrix, gid: np.ndarray, chosen: list[int], in_s: np.ndarray,
               cnt: np.ndarray, weight: np.ndarray, w_link: float, tabu: np.ndarray, step: int) -> tuple[int, int]:
    """(position in ``chosen``, candidate) of the best non-tabu swap, or (-1, -1) when none is allowed."""
    n_cand = a.shape[0]
    idx = np.asarray(chosen, dtype=np.int64)
    only = a[idx].toarray() * ((cnt == 1) * weight)[None, :]  # n x T: weights of the targets only s sees
    loss = only.sum(axis=1)
    gain = a @ ((cnt == 0) * weight)
    both = np.asarray(a @ only.T)  # C x n: weight of s's own targets that c also sees
    link = adj[:, idx].toarray().astype(np.int64)  # C x n
    sub = link[idx] > 0
    delta = np.empty((n_cand, len(idx)))
    for k in range(len(idx)):
        rest = np.delete(np.arange(len(idx)), k)
        label = _labels(sub[np.ix_(rest, rest)])
        roots, label = np.unique(label, return_inverse=True)
        groups_rest = np.unique(gid[idx[rest]])
        base = roots.size - groups_rest.size
        member = np.zeros((len(rest), roots.size), dtype=np.int64)
        member[np.arange(len(rest)), label] = 1
        touched = ((link[:, rest] @ member) > 0).sum(axis=1)
        parts = np.where(np.isin(gid, groups_rest), base + 1 - touched, base)
        delta[:, k] = loss[k] - gain - both[:, k] + w_link * parts
    delta[in_s, :] = np.inf
    free = delta.copy()
    free[tabu > step, :] = np.inf
    free[:, tabu[idx] > step] = np.inf
    # a tabu move is taken when it reaches a connected cover (aspiration) or when every move is tabu
    now = float(weight[cnt == 0].sum()) + w_link * _parts_of(sub, gid[idx])
    if np.isfinite(free).any() and not (now + delta.min() <= 1e-9 < now + free.min()):
        delta = free
    if not np.isfinite(delta).any():
        return -1, -1
    flat = int(np.argmin(delta.T))  # row-major over (position, candidate): ties to the lowest indices
    k, c = divmod(flat, n_cand)
    return k, c
