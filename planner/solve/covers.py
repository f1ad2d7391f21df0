"""Interchangeable cover methods: each takes a :class:`CoverInstance` and a registration rule and gives a typed
:class:`SolveResult` (the :class:`Cover` protocol). The plain covers (Chvatal's greedy, CFT) take no rule: given one
for an instance with registration groups, they refuse it rather than give a plan that ignores it."""

from __future__ import annotations

import time
from typing import Protocol

import numpy as np

from planner.core.errors import UsageError
from planner.coverage.overlap import OverlapRule
from planner.solve.cft import cft_cover
from planner.solve.greedy import connected_greedy_plan, greedy_cover
from planner.solve.instance import CoverInstance
from planner.solve.milp import solve
from planner.solve.result import SolveResult, Status


class Cover(Protocol):
    """A cover method: the instance and its registration rule (None: a plain cover) -> the method's result."""

    def __call__(self, instance: CoverInstance, rule: OverlapRule | None = None) -> SolveResult: ...


def _plain(instance: CoverInstance, rule: OverlapRule | None, method: str) -> None:
    if rule is not None and instance.groups is not None:
        raise UsageError("a plain cover takes no registration rule", field="method", value=method)


def greedy(instance: CoverInstance, rule: OverlapRule | None = None) -> SolveResult:
    """Chvatal's greedy over the instance's costs (:func:`planner.solve.greedy.greedy_cover`)."""
    _plain(instance, rule, "greedy")
    return greedy_cover(instance.by_candidate, weights=instance.cost)


def cft(instance: CoverInstance, rule: OverlapRule | None = None) -> SolveResult:
    """CFT's cover (:func:`planner.solve.cft.cft_cover`), its Lagrangian bound as the result's bound."""
    _plain(instance, rule, "cft")
    start = time.perf_counter()
    found = cft_cover(instance.by_candidate.astype(bool).tocsr(), np.asarray(instance.cost, dtype=float))
    objective = float(instance.cost[list(found.selected)].sum())
    # CFT reports -FLT_MAX where it proved nothing
    return SolveResult.timed(
        "cft", Status.FEASIBLE, found.selected, objective, start, bound=max(0.0, found.lower_bound)
    )


def connected_greedy(instance: CoverInstance, rule: OverlapRule | None = None) -> SolveResult:
    """The greedy under the registration rule (:func:`planner.solve.greedy.connected_greedy_plan`); with no rule or
    no groups, the plain greedy."""
    return greedy(instance) if rule is None else connected_greedy_plan(instance, rule)


def milp(instance: CoverInstance, rule: OverlapRule | None = None) -> SolveResult:
    """The MILP (:func:`planner.solve.milp.solve`) with its default options and this registration rule."""
    return solve(instance, overlap=rule)


#: the cover methods by name, interchangeable wherever a :class:`Cover` is taken
COVERS: dict[str, Cover] = {"greedy": greedy, "cft": cft, "connected-greedy": connected_greedy, "milp": milp}
