"""relied_targets (each station's own targets, the nearest station answering for each, plus those shared with its
registration partners) equals the plain per-station, per-partner loop on random coverage."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.plan.tripod import relied_targets


def _plain(problem, selected, partners):
    """The reference: the nearest (slant, then station) of the chosen seers owns a target; a partner adds the targets
    both see."""
    sel = list(selected)
    slant = problem.slant_m[sel].tocoo()
    best: dict[int, tuple[float, int]] = {}
    for r, t, v in zip(slant.row, slant.col, slant.data):
        if t not in best or (v, r) < best[t]:
            best[int(t)] = (float(v), int(r))
    out = {}
    for k, j in enumerate(sel):
        keep = {t for t, (_, r) in best.items() if r == k}
        for p in (partners or {}).get(j, []):
            keep |= set(np.intersect1d(problem.by_candidate[j].indices, problem.by_candidate[p].indices).tolist())
        out[j] = np.array(sorted(keep), dtype=np.int64)
    return out


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n_c=st.integers(1, 30), n_t=st.integers(1, 40), ties=st.booleans())
def test_relied_targets_equal_the_plain_loop(seed, n_c, n_t, ties):
    rng = np.random.default_rng(seed)
    seen = rng.random((n_c, n_t)) < 0.3
    slant = np.where(seen, rng.integers(1, 4, (n_c, n_t)) if ties else rng.random((n_c, n_t)) * 50, 0.0)
    problem = SimpleNamespace(by_candidate=sp.csr_matrix(seen), slant_m=sp.csr_matrix(slant))
    sel = [int(j) for j in rng.permutation(n_c)[: rng.integers(1, n_c + 1)]]
    partners = {j: [int(p) for p in rng.integers(0, n_c, rng.integers(0, 4))] for j in sel}
    for given_partners in (None, partners):
        got, want = relied_targets(problem, sel, given_partners), _plain(problem, sel, given_partners)
        assert got.keys() == want.keys()
        assert all(np.array_equal(got[j], want[j]) for j in sel)
