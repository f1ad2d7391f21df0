"""The sparse adjustment against the dense one kept beside it (``method="dense"``), on random networks;
with the reduced normal matrix factored dense (LAPACK) and sparse (SuperLU)."""

from __future__ import annotations

import contextlib
import math
from unittest import mock

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from planner.core.errors import InputError
from planner.network import lsq_dense, normal
from planner.network.adjustment import Adjustment, Obs, adjust

TOL = 1e-9


def random_network(
    seed: int, n_points: int, n_obs: int, n_fixed: int, kinds: tuple[str, ...]
) -> tuple[dict[str, tuple[float, float]], list[str], list[Obs]]:
    """Points on a 100 m square (at least 1 m apart), the first ``n_fixed`` fixed, and ``n_obs`` random
    observations of ``kinds`` between random pairs (sigmas: 5", 2 mm, 8 mm)."""
    rng = np.random.default_rng(seed)
    xy: list[tuple[float, float]] = []
    while len(xy) < n_points:
        p = (float(rng.uniform(0, 100)), float(rng.uniform(0, 100)))
        if all(math.dist(p, q) > 1.0 for q in xy):
            xy.append(p)
    names = [f"P{k}" for k in range(n_points)]
    coords = dict(zip(names, xy))
    obs = []
    for _ in range(n_obs):
        kind = kinds[int(rng.integers(len(kinds)))]
        i, j = (int(v) for v in rng.choice(n_points, 2, replace=False))
        (xi, yi), (xj, yj) = xy[i], xy[j]
        if kind == "direction":
            obs.append(Obs(kind, names[i], names[j], math.degrees(math.atan2(yj - yi, xj - xi)), 5 / 3600))
        elif kind == "distance":
            obs.append(Obs(kind, names[i], names[j], math.dist(xy[i], xy[j]), 0.002))
        elif kind in ("dx", "dy"):
            obs.append(Obs(kind, names[i], names[j], (xj - xi) if kind == "dx" else (yj - yi), 0.008))
        else:
            obs.append(Obs(kind, names[i], None, xi if kind == "x" else yi, 0.003))
    return coords, names[:n_fixed], obs


def condition(coords, fixed, obs) -> float:
    """The condition number of N = A^T P A on the unit diagonal (``obs`` in degrees and metres)."""
    rad = [Obs(o.kind, o.at, o.to, o.value, math.radians(o.sigma) if o.kind == "direction" else o.sigma) for o in obs]
    a, _, _ = lsq_dense.design(coords, [n for n in coords if n not in fixed], rad)
    n = a.T @ (a / np.array([o.sigma for o in rad])[:, None] ** 2)
    s = 1.0 / np.sqrt(np.diag(n))
    return float(np.linalg.cond(n * s[:, None] * s[None, :])) if len(n) else 1.0


def assert_same(a: Adjustment, b: Adjustment, loose: float = 1.0) -> None:
    """Points, redundancy numbers, residuals and the global test agree to TOL (times ``loose``: two solvers, each
    backward stable, agree to about the condition of N times the rounding, 1e-9 only where that is 1e5 at most)."""
    tol = TOL * loose
    assert [p.name for p in a.points] == [p.name for p in b.points]
    for p, q in zip(a.points, b.points):
        assert abs(p.x - q.x) <= tol and abs(p.y - q.y) <= tol
        assert max(
            abs(u - v)
            for u, v in zip(
                (p.sigma_x, p.sigma_y, p.ellipse_a, p.ellipse_b), (q.sigma_x, q.sigma_y, q.ellipse_a, q.ellipse_b)
            )
        ) <= tol * max(1.0, p.sigma_x, p.sigma_y, p.ellipse_a)
    assert a.dof == b.dof
    np.testing.assert_allclose(a.redundancy, b.redundancy, rtol=0, atol=tol)
    np.testing.assert_allclose(a.residuals, b.residuals, rtol=0, atol=tol)
    np.testing.assert_allclose(a.standardized, b.standardized, rtol=0, atol=1e-6 * loose)
    assert (a.m0 is None) == (b.m0 is None)
    if a.m0 is not None and b.m0 is not None and a.chi2_p is not None and b.chi2_p is not None:
        assert abs(a.m0 - b.m0) <= tol and abs(a.chi2_p - b.chi2_p) <= tol
    # entries near 0 (two points barely correlated) to the matrix's own scale, not to an absolute 1e-15
    np.testing.assert_allclose(
        a.qxx, b.qxx, rtol=1e-9 * loose, atol=1e-12 * loose * float(np.abs(b.qxx).max(initial=0))
    )


def factor(kind: str) -> contextlib.AbstractContextManager:
    """Have the sparse solver factor N* with SuperLU (``sparse``) or LAPACK (``dense``) whatever its size."""
    if kind == "dense":
        return mock.patch.multiple(normal, DENSE_SMALL=10**9, DENSE_MAX=10**9)
    return mock.patch.multiple(normal, DENSE_SMALL=0, DENSE_MAX=0)


def both(coords, fixed, obs, kind: str = "sparse", **kw):
    """The dense and the sparse adjustment (N* factored as ``kind`` says), or the error both raise."""
    out = []
    for method in ("dense", "sparse"):
        try:
            with factor(kind):
                out.append(adjust(coords, fixed, obs, method=method, **kw))
        except InputError as exc:
            out.append(exc.message)
    return out


ALL = ("direction", "distance", "dx", "dy", "x", "y")


@settings(max_examples=60, deadline=None, derandomize=True)
@given(
    seed=st.integers(0, 2**31),
    n_points=st.integers(3, 14),
    extra=st.integers(0, 40),
    n_fixed=st.integers(0, 3),
    kinds=st.sampled_from(
        [
            ("direction", "distance"),
            ("dx", "dy"),
            ("direction", "distance", "dx", "dy", "x", "y"),
            ("distance",),
            ("direction",),
        ]
    ),
    observed=st.booleans(),
    kind=st.sampled_from(["sparse", "dense"]),
)
# a station whose only directions go to fixed points: its orientation touches no point (Q_oo took a size-0 reshape)
@example(seed=734324022, n_points=5, extra=5, n_fixed=3, kinds=ALL, observed=False, kind="sparse")
# P3's x tied by one direction from P2 only: eliminating P2's orientation left its diagonal as rounding noise, scaled to 1
@example(seed=1364122997, n_points=11, extra=30, n_fixed=3, kinds=ALL, observed=False, kind="dense")
# distances about one fixed point (a free rotation): SuperLU's order made a pivot 2.6e-7, the last (0) came out 5.8e-9
@example(seed=1241392596, n_points=11, extra=21, n_fixed=1, kinds=("distance",), observed=False, kind="sparse")
# a station with one direction (redundancy 0): N* and a Q a^T as differences of large numbers were 4e-9 out
@example(seed=748396460, n_points=10, extra=14, n_fixed=2, kinds=("direction",), observed=True, kind="sparse")
# a weak network (sigmas of 2.7 m; N's condition 1.6e8): the two solvers agree to that condition, not to 1e-9
@example(seed=1782785349, n_points=10, extra=5, n_fixed=1, kinds=ALL, observed=False, kind="sparse")
def test_sparse_and_dense_agree_on_random_networks(seed, n_points, extra, n_fixed, kinds, observed, kind):
    coords, fixed, obs = random_network(seed, n_points, 2 * n_points + extra, n_fixed, kinds)
    if observed:
        rng = np.random.default_rng(seed + 1)
        obs = [Obs(o.kind, o.at, o.to, o.value + o.sigma * float(rng.standard_normal()), o.sigma) for o in obs]
    dense, sparse = both(coords, fixed, obs, kind, observed=observed, angle_unit="deg")
    if isinstance(dense, str) or isinstance(sparse, str):
        assert dense == sparse  # the same datum defect, counted the same
    else:
        assert_same(dense, sparse, max(1.0, condition(coords, fixed, obs) / 1e5))


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["sparse", "dense"])
def test_a_large_sparse_network_agrees_with_the_dense_one(kind):
    # 90 points, 900 observations of every kind: a network where the pattern of N is far from full
    coords, fixed, obs = random_network(7, 90, 900, 3, ("direction", "distance", "dx", "dy", "x", "y"))
    dense, sparse = both(coords, fixed, obs, kind, angle_unit="deg")
    assert_same(dense, sparse)
    rng = np.random.default_rng(8)
    noisy = [Obs(o.kind, o.at, o.to, o.value + o.sigma * float(rng.standard_normal()), o.sigma) for o in obs]
    dense, sparse = both(coords, fixed, noisy, kind, observed=True, angle_unit="deg")
    assert_same(dense, sparse)


@pytest.mark.parametrize("kind", ["sparse", "dense"])
def test_datum_defects_are_counted_as_the_dense_solver_counts_them(kind):
    # a free network of distances (2 shifts and a rotation), and one point seen by one distance only
    coords, _, obs = random_network(3, 6, 30, 0, ("distance",))
    dense, sparse = both(coords, [], obs, kind)
    assert dense == sparse and "leaves 3 unknown(s)" in sparse
    coords["Q"] = (500.0, 500.0)
    dense, sparse = both(
        coords, ["P0", "P1"], obs + [Obs("distance", "P0", "Q", math.dist(coords["P0"], (500, 500)), 0.002)], kind
    )
    assert dense == sparse and "leaves 1 unknown(s)" in sparse


def test_unknown_method_is_refused():
    coords, fixed, obs = random_network(1, 4, 10, 2, ("distance",))
    with pytest.raises(InputError, match="unknown adjustment method"):
        adjust(coords, fixed, obs, method="cholmod")


def test_coincident_points_are_named_by_both():
    coords = {"A": (0.0, 0.0), "B": (10.0, 0.0), "C": (10.0, 0.0)}
    obs = [Obs("distance", "A", "B", 10.0, 0.002), Obs("distance", "B", "C", 0.0, 0.002)]
    dense, sparse = both(coords, ["A"], obs)
    assert dense == sparse == "observation between coincident points"


@pytest.mark.parametrize("kind", ["sparse", "dense"])
def test_heights_agree_with_the_dense_inverse(kind):
    # a random levelling network: 40 points, 3 of known height, 120 height differences
    from planner.network.heights import HeightObs, adjust_heights

    rng = np.random.default_rng(5)
    names = [f"H{k}" for k in range(40)]
    fixed = {n: float(rng.uniform(0, 10)) for n in names[:3]}
    approx = {n: float(rng.uniform(0, 10)) for n in names[3:]}
    pairs = [tuple(int(v) for v in rng.choice(40, 2, replace=False)) for _ in range(120)]
    obs = [HeightObs(names[i], names[j], float(rng.normal(0, 0.5)), float(rng.uniform(0.001, 0.005))) for i, j in pairs]
    with factor(kind):
        got = adjust_heights(approx, fixed, obs, observed=True)
    # the dense solution: A, N = A^T P A, Q = N^-1
    unknown = list(approx)
    a = np.zeros((len(obs), len(unknown)))
    h0 = {**approx, **fixed}
    for k, o in enumerate(obs):
        for name, sign in ((o.at, -1.0), (o.to, 1.0)):
            if name in approx:
                a[k, unknown.index(name)] = sign
    w = np.array([1 / o.sigma_m**2 for o in obs])
    l = np.array([o.dh_m - (h0[o.to] - h0[o.at]) for o in obs])
    q = np.linalg.inv(a.T @ (a * w[:, None]))
    x = q @ (a.T @ (w * l))
    v = a @ x - l
    m0 = math.sqrt(float(v @ (w * v)) / (len(obs) - len(unknown)))
    assert got.m0 == pytest.approx(m0, abs=TOL)
    for k, n in enumerate(unknown):
        assert abs(got.heights_m[n] - (h0[n] + x[k])) <= TOL
        assert abs(got.sigma_m[n] - math.sqrt(q[k, k]) * m0) <= TOL
    with pytest.raises(InputError, match="height datum defect"), factor(kind):
        adjust_heights({**approx, "alone": 1.0}, fixed, obs)


@pytest.mark.parametrize("kind", ["sparse", "dense"])
def test_datum_defects_are_counted_by_the_pivots_where_the_rank_would_cost_too_much(kind):
    # as on a network above normal.DENSE_RANK_MAX unknowns: the count comes from the factor's small pivots
    coords, _, obs = random_network(3, 6, 30, 0, ("distance",))
    with mock.patch.object(normal, "DENSE_RANK_MAX", 0), factor(kind):
        with pytest.raises(InputError, match="leaves 3 unknown"):
            adjust(coords, [], obs)
        with pytest.raises(InputError, match="leaves 2 unknown"):
            adjust({**coords, "Q": (500.0, 500.0)}, ["P0", "P1"], obs)


def test_an_adjustment_that_does_not_converge_is_refused_by_both_solvers():
    # five points, all kinds of observation with noise: Gauss-Newton wanders (P4 moves 0.1-1 m an iteration whatever
    # the number of iterations); the plain return of the last iterate would read as an adjusted network
    coords, fixed, obs = random_network(1966957930, 5, 2 * 5 + 16, 3, ALL)
    rng = np.random.default_rng(1966957930 + 1)
    obs = [Obs(o.kind, o.at, o.to, o.value + o.sigma * float(rng.standard_normal()), o.sigma) for o in obs]
    for kind in ("sparse", "dense"):
        dense, sparse = both(coords, fixed, obs, kind, observed=True, angle_unit="deg")
        for message in (dense, sparse):
            assert isinstance(message, str) and message.startswith("the adjustment did not converge in 10 iterations")
            assert "point P4 still moved" in message and "\n" not in message
