"""The (station, setting) columns of a pool and the point spacing's coverage: which views meet a
spacing at a setting (:func:`spacing_coverage`, :func:`spacing_refusal`), and every useful pair of a candidate
and a setting with its cost (:func:`setting_columns`). Planning with them: :mod:`planner.plan.hours.field_time`."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.core.errors import InfeasibleError
from planner.coverage.matrix import CoverageProblem
from planner.coverage.spacing import spacing_factors
from planner.instrument.field_table import FieldProperties

#: a view meets the spacing within this relative tolerance (rounding of the settings' names, not a margin)
REL_TOL = 1e-9


def masked(problem: CoverageProblem, keep: NDArray[np.bool_]) -> CoverageProblem:
    """``problem`` with only the views ``keep`` (aligned with ``by_candidate``'s stored pairs) left."""
    m = problem.by_candidate.tocsr()
    rows = np.repeat(np.arange(m.shape[0]), np.diff(m.indptr))[keep]
    cols = m.indices[keep]

    def pick(values: sp.csr_matrix) -> NDArray[np.float64]:
        v = values.tocsr()
        if np.array_equal(v.indptr, m.indptr) and np.array_equal(v.indices, m.indices):  # the same pattern
            return np.asarray(v.data[keep], dtype=float)
        return np.asarray(v[rows, cols], dtype=float).ravel()

    def build(values: NDArray) -> sp.csr_matrix:
        return sp.csr_matrix((values, (rows, cols)), shape=m.shape)

    by = build(np.ones(len(rows), dtype=bool))
    return replace(
        problem,
        by_candidate=by,
        by_target=by.T.tocsr(),
        slant_m=build(pick(problem.slant_m)),
        incidence_deg=build(pick(problem.incidence_deg)),
    )


def spacing_coverage(problem: CoverageProblem, step_rad: float, max_spacing_m: float) -> CoverageProblem:
    """The views of ``problem`` whose point spacing at angular step ``step_rad`` is at most ``max_spacing_m``."""
    f = spacing_factors(problem)
    return masked(problem, f.data * step_rad <= max_spacing_m * (1 + REL_TOL))


def spacing_refusal(
    problem: CoverageProblem, unseen: NDArray[np.int64], setting: str, step_rad: float, m: float
) -> InfeasibleError:
    """The refusal of pieces no view meets the spacing on: up to five, each with the finest spacing reached."""
    f = spacing_factors(problem).tocsc()
    t = problem.targets
    shown = []
    for i in unseen[:5]:
        col = f.data[f.indptr[i] : f.indptr[i + 1]]
        best = f" (finest {1e3 * col.min() * step_rad:.1f} mm)" if col.size else " (seen by no candidate)"
        shown.append(f"{t.label(int(i))} at ({t.midpoint(int(i))[0]:.2f}, {t.midpoint(int(i))[1]:.2f}){best}")
    more = f" and {len(unseen) - 5} more" if len(unseen) > 5 else ""
    return InfeasibleError(
        f"{len(unseen)} piece(s) no candidate scans at a point spacing of at most {1e3 * m:g} mm, even at the finest "
        f"setting {setting!r}: {'; '.join(shown)}{more}"
    )


@dataclass(frozen=True)
class SettingColumns:
    """The (station, setting) pairs of a pool: ``candidate[j]`` and ``setting[j]`` (an index of ``names``) of
    column j, the pieces it covers (``matrix``, columns x pieces) and its cost, set-up + scan (s)."""

    candidate: NDArray[np.int64]
    setting: NDArray[np.int64]
    names: tuple[str, ...]
    matrix: sp.csr_matrix
    cost_s: NDArray[np.float64]

    def expand(self) -> sp.csr_matrix:
        """Columns x candidates: column j's candidate (to carry per-candidate data onto the columns)."""
        n = len(self.candidate)
        n_cand = int(self.candidate.max()) + 1 if n else 0
        return sp.csr_matrix((np.ones(n, dtype=bool), (np.arange(n), self.candidate)), shape=(n, n_cand))


def setting_columns(
    problem: CoverageProblem,
    props: FieldProperties,
    max_spacing_m: float | None,
    rows: NDArray[np.int64] | None = None,
    *,
    all_relays: bool = True,
) -> SettingColumns:
    """Every useful (candidate, setting) pair of ``problem`` (the candidates ``rows`` only, where given): a pair is kept
    where it covers a piece, and more pieces than every coarser pair of its candidate kept before it (without a spacing
    every setting covers the same: the cheapest is kept). That drops only dominated pairs because a setting is first
    dropped where another is no coarser and no dearer (:func:`useful_settings`): of the settings left, a finer one
    always costs more. A candidate with no pair at the cheapest setting gets one there covering nothing: it may still
    stand for registration, which is judged on what stations see, not on the spacing (a relay between two stations), and
    it should not pay for a finer setting to do so. So the pairs kept hold an optimum of every (station, setting) pair:
    a bound over them is a bound over all. ``all_relays=False``: relays only for the candidates with no other pair
    (fewer columns, the same station counts; a field-time optimum over them may cost more)."""
    if max_spacing_m is not None:
        settings = useful_settings(props.by_step())
    else:  # cheapest first: the only pair kept per candidate
        settings = tuple(sorted(((n, 0.0, props.scan_time_s(n)) for n in props.settings), key=lambda r: r[2]))
    a = problem.by_candidate.tocsr()
    if rows is not None:
        a = a[rows]
    f = None
    if max_spacing_m is not None:
        f = spacing_factors(problem).tocsr()
        f = f[rows] if rows is not None else f
    base = np.arange(a.shape[0]) if rows is None else np.asarray(rows, dtype=np.int64)
    best = np.zeros(a.shape[0], dtype=np.int64)
    cand, sets, mats, costs = [], [], [], []
    for s, (_name, step, scan) in enumerate(settings):
        ok = (
            np.ones(a.nnz, dtype=bool)
            if f is None or max_spacing_m is None
            else f.data * step <= max_spacing_m * (1 + REL_TOL)
        )
        m = sp.csr_matrix((ok, a.indices.copy(), a.indptr.copy()), shape=a.shape)  # eliminate_zeros works in place
        m.eliminate_zeros()
        n = np.diff(m.indptr)
        take = np.flatnonzero(n > best)
        best[take] = n[take]
        cand.append(base[take])
        sets.append(np.full(len(take), s, dtype=np.int64))
        mats.append(m[take])
        costs.append(np.full(len(take), props.setup_time_s + scan))
    cheap = min(range(len(settings)), key=lambda k: (settings[k][2], k))
    relay = _without_cheap_pair(base, cand, sets, cheap) if all_relays else np.flatnonzero(best == 0)
    if relay.size:
        cand.append(base[relay])
        sets.append(np.full(len(relay), cheap, dtype=np.int64))
        mats.append(sp.csr_matrix((len(relay), a.shape[1]), dtype=bool))
        costs.append(np.full(len(relay), props.setup_time_s + settings[cheap][2]))
    matrix = sp.vstack(mats, format="csr") if mats else sp.csr_matrix((0, a.shape[1]), dtype=bool)
    return SettingColumns(
        candidate=np.concatenate(cand).astype(np.int64),
        setting=np.concatenate(sets).astype(np.int64),
        names=tuple(name for name, _, _ in settings),
        matrix=matrix.astype(bool),
        cost_s=np.concatenate(costs).astype(float),
    )


def useful_settings(settings: tuple[tuple[str, float, float], ...]) -> tuple[tuple[str, float, float], ...]:
    """``settings`` (name, step, scan time; coarsest step first) less each one that another setting makes
    useless: no coarser and no dearer (on an exact tie the one listed first stays). Of those left, a finer
    setting always costs more, which :func:`setting_columns` relies on."""
    kept = []
    for k, (_name, step, scan) in enumerate(settings):
        beaten = any(
            (s2 <= step and t2 <= scan) and (s2 < step or t2 < scan or j < k)
            for j, (_n2, s2, t2) in enumerate(settings)
            if j != k
        )
        if not beaten:
            kept.append(settings[k])
    return tuple(kept)


def _without_cheap_pair(
    base: NDArray[np.int64], cand: list[NDArray[np.int64]], sets: list[NDArray[np.int64]], cheap: int
) -> NDArray[np.int64]:
    """Positions (in ``base``) of the candidates with no pair at setting ``cheap`` among the pairs so far."""
    chosen = np.concatenate(cand) if cand else np.zeros(0, dtype=np.int64)
    at = np.concatenate(sets) if sets else np.zeros(0, dtype=np.int64)
    has = np.isin(base, chosen[at == cheap])
    return np.flatnonzero(~has)
