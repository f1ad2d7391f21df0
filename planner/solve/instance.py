"""A set-cover instance as the solvers see it: a site's coverage problem (with the registration data and the combined
precision weights) or a plain OR-Library instance (costs only)."""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.core.checks import argument
from planner.core.errors import InputError
from planner.coverage.matrix import CoverageProblem
from planner.coverage.visibility import PrecisionRule
from planner.instrument.accuracy import ErrorBudget
from planner.instrument.models import Scanner
from planner.solve.combined import information


@dataclass(frozen=True, eq=False)
class CoverInstance:
    """Candidates (rows of ``by_candidate``) covering targets (columns). ``groups[c]``: the registration group of
    candidate c (zone, side); the chosen candidates of one group must form a connected overlap graph.
    ``target_length_m``: wall length of each target (overlap is measured in metres of wall). ``xy``: candidate positions
    (for ``max_link_m``). ``info``: C x T weights (sigma_req / sigma_tj)^2 of the combined precision mode. ``links``: C
    x C symmetric pairs related besides shared wall (seen through an opening); ``groups`` are then accessible areas of
    the site (``--registration site``). ``relation``: C x C symmetric, the registration relation given whole, in place
    of the overlap rule's (:mod:`planner.bounds.plane_refine`: relaxed links between patches of the plane); None: the
    rule's.
    """

    by_candidate: sp.csr_matrix
    cost: NDArray[np.float64]
    name: str = ""
    groups: tuple[Hashable, ...] | None = None
    target_length_m: NDArray[np.float64] | None = None
    xy: NDArray[np.float64] | None = None
    info: sp.csr_matrix | None = None
    candidate_ids: tuple[str, ...] | None = None
    links: sp.csr_matrix | None = None
    relation: sp.csr_matrix | None = None

    @property
    def lengths_m(self) -> NDArray[np.float64]:
        """Wall length of each target (1 each where the instance gives none)."""
        return self.target_length_m if self.target_length_m is not None else np.ones(self.by_candidate.shape[1])

    def __post_init__(self) -> None:
        c, t = self.by_candidate.shape
        if len(self.cost) != c:
            raise InputError(f"{len(self.cost)} costs for {c} candidates", field="cost", value=len(self.cost))
        cost = np.asarray(self.cost, dtype=float)
        if not (ok := np.isfinite(cost) & (cost > 0)).all():  # 0 or -1 would make "0 stations" optimal
            bad = int(np.flatnonzero(~ok)[0])
            raise InputError(
                "costs must be finite and > 0", row=f"candidate {bad}", field="cost", value=float(cost[bad])
            )
        if self.groups is not None and len(self.groups) != c:
            raise InputError(f"{len(self.groups)} groups for {c} candidates", field="groups", value=len(self.groups))
        if self.relation is not None and self.relation.shape != (c, c):
            raise InputError(f"a relation of shape {self.relation.shape} for {c} candidates", field="relation", value=c)
        if self.target_length_m is not None and len(self.target_length_m) != t:
            n = len(self.target_length_m)
            raise InputError(f"{n} target lengths for {t} targets", field="target_length_m", value=n)

    @property
    def shape(self) -> tuple[int, int]:
        return self.by_candidate.shape

    @cached_property
    def by_target(self) -> sp.csr_matrix:
        return self.by_candidate.T.tocsr()

    def coverage_count(self, selected: Sequence[int]) -> NDArray[np.int64]:
        if len(selected) == 0:
            return np.zeros(self.shape[1], dtype=np.int64)
        return np.asarray(self.by_candidate[list(selected)].astype(np.int64).sum(axis=0)).ravel()


def cover_instance(
    problem: CoverageProblem,
    *,
    scanner: Scanner | None = None,
    budget: ErrorBudget | None = None,
    sigma_req_m: float | None = None,
    cost: Sequence[float] | None = None,
    name: str = "",
    groups: Sequence[Hashable] | None = None,
    links: sp.csr_matrix | None = None,
    incidence_model: str = "none",
) -> CoverInstance:
    """The solver's view of a site's coverage problem; with ``scanner``, ``budget`` and ``sigma_req_m`` the combined
    precision weights are filled in (:func:`planner.solve.combined.information`). ``groups`` (default: zone and side of
    each candidate) and ``links``: see :func:`planner.coverage.links.registration_groups`."""
    argument(problem, CoverageProblem, "problem")
    info = None
    if scanner is not None and budget is not None and sigma_req_m is not None:
        info = information(problem, PrecisionRule(scanner, budget, sigma_req_m, incidence_model))
    cands = problem.candidates
    t = problem.targets
    return CoverInstance(
        by_candidate=problem.by_candidate.astype(bool).tocsr(),
        cost=np.ones(len(cands)) if cost is None else np.asarray(cost, dtype=float),
        name=name,
        groups=tuple(groups) if groups is not None else tuple((c.zone, c.side.value) for c in cands),
        target_length_m=np.asarray(t.s1_m - t.s0_m, dtype=float),
        xy=np.array([c.xy for c in cands], dtype=float).reshape(-1, 2),
        info=info,
        candidate_ids=tuple(c.id for c in cands),
        links=links,
    )
