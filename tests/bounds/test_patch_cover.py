"""The quick cover's narrower tests give the answers of the tests they replace (planner.bounds.patch_family,
planner.bounds.patch_cover), on random patch families with runs of a ring and holes in them:

- implied targets (only the narrowest seer's targets tested) = planner.solve.presolve.implied_targets;
- the undominated patches (only the seers of the rarest piece tested) = planner.solve.presolve.dominated with low as the
  cost;
- the relaxed links as a dense matrix = planner.bounds.plane_refine.relaxed_links;
- the dominance under the links (only the kept seers of the rarest target tested) = the walk in the order written out
  plainly: Q goes when one of the first 64 kept patches before it that cover all it covers is linked to each of its
  neighbours not gone before it, itself aside.
- The whole quick cover (family_bound) never passes the connected optimum of the patches under the relaxed links,
  found by brute force.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.bounds.patch_cover import _PROBE, family_bound, implied, linked_dominated
from planner.bounds.patch_family import link_matrix, undominated
from planner.bounds.plane_refine import relaxed_links
from planner.solve.presolve import dominated, implied_targets
from tests.bounds.test_plane_patches_cover import brute_optimum
from tests.bounds.test_plane_ring import QUICK


@st.composite
def families(draw, most: int = 40):
    """(u: patches x pieces, bool; low; lengths; share; cells): each patch sees a run of the ring with holes."""
    n, m = draw(st.integers(3, 24)), draw(st.integers(1, most))
    u = np.zeros((m, n), dtype=bool)
    for j in range(m):
        start, length = draw(st.integers(0, n - 1)), draw(st.integers(1, n))
        keep = draw(st.lists(st.booleans(), min_size=length, max_size=length))
        keep[0] = True
        u[j, [(start + i) % n for i, k in enumerate(keep) if k]] = True
    if draw(st.booleans()):  # repeated rows: ties in every order
        u = np.concatenate([u, u[: m // 2]])
    lengths = np.array(draw(st.lists(st.sampled_from([0.5, 1.0, 1.5]), min_size=n, max_size=n)))
    low = (u * lengths).sum(axis=1) * np.array(
        draw(st.lists(st.sampled_from([0.0, 0.5, 1.0]), min_size=len(u), max_size=len(u)))
    )
    cells = np.stack([np.arange(len(u)) % 5, np.arange(len(u)) // 5], axis=1)
    return u, low, lengths, draw(st.sampled_from([0.1, 0.3, 0.6])), cells


def _walked(a: np.ndarray, adj: np.ndarray) -> np.ndarray:
    """The dominance under the links, written out as the walk in the order (module docstring)."""
    n = a.shape[0]
    size = a.sum(axis=1)
    gone, kept = np.zeros(n, dtype=bool), []
    for q in np.lexsort((np.arange(n), -size)).tolist():
        ps = [p for p in kept if not (a[q] & ~a[p]).any()][:_PROBE]
        need = [r for r in np.flatnonzero(adj[q]) if not gone[r]]
        if any(all(adj[p, r] for r in need if r != p) for p in ps):
            gone[q] = True
        else:
            kept.append(q)
    return gone


@settings(QUICK, max_examples=60)
@given(fam=families())
def test_the_narrow_tests_give_the_answers_of_the_full_ones(fam):
    u, low, lengths, share, _ = fam
    us = sp.csr_matrix(u)
    assert np.array_equal(implied(us), implied_targets(us.T.tocsr()))
    assert np.array_equal(undominated(us, low), np.flatnonzero(~dominated(us, low)))
    assert np.array_equal(link_matrix(us, low, lengths, share), relaxed_links(us, low, lengths, share).toarray())
    adj = link_matrix(us, low, lengths, share)
    assert np.array_equal(linked_dominated(us, adj), _walked(u, adj))
    assert np.array_equal(linked_dominated(us, sp.csr_matrix(adj)), _walked(u, adj))
    some = u[:, ::3]  # fewer targets: rows that cover none of them too
    assert np.array_equal(linked_dominated(sp.csr_matrix(some), adj), _walked(some, adj))


@settings(QUICK, max_examples=25)
@given(fam=families(most=8))
def test_the_quick_cover_stays_below_the_connected_optimum(fam):
    u, low, lengths, share, cells = fam
    us = sp.csr_matrix(u)
    adj = relaxed_links(us, low, lengths, share).toarray()
    best = brute_optimum(u, adj)
    got = family_bound(us, low, cells, lengths, np.ones(u.shape[1], dtype=bool), share, 99, 10_000)
    assert got is not None
    assert got[0] <= best
