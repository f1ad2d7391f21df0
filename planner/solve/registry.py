"""The MILP backends by name: :func:`make_backend` (one home of the choice; SCIP through PySCIPOpt loads only when
asked for)."""

from __future__ import annotations

from typing import Any

import numpy as np

from planner.core.errors import UsageError
from planner.solve.backends import BACKENDS, CpSatBackend, MipBackend, PulpBackend


def make_backend(name: str, n: int, cost: np.ndarray) -> Any:
    """The backend ``name`` (one of :data:`planner.solve.backends.BACKENDS`) for ``n`` binary columns of ``cost``."""
    if name == "cpsat":
        return CpSatBackend(n, cost)
    if name in MipBackend.SOLVERS:
        return MipBackend(name, n, cost)
    if name == "pulp-cbc":
        return PulpBackend(n, cost)
    if name == "pyscipopt":
        from planner.solve.scip_bc import PyScipBackend  # lazy: SCIP loads only when asked for

        return PyScipBackend(n, cost)
    raise UsageError(f"unknown backend (known: {', '.join(BACKENDS)})", field="backend", value=name)
