"""The MILP backends by name: :func:`make_backend`."""

from __future__ import annotations

from typing import Any

import numpy as np

from planner.core.errors import UsageError
from planner.solve.backends import BACKENDS, Backend, CpSatBackend, MipBackend, PulpBackend


def make_backend(name: str, n: int, cost: np.ndarray, node_limit: int | None = None) -> Backend:
    """The backend ``name`` (one of :data:`planner.solve.backends.BACKENDS`) for ``n`` binary columns of ``cost``,
    stopped on ``node_limit`` branch-and-bound nodes per solve where it takes one (None: no limit)."""
    backend: Any
    if name == "cpsat":
        backend = CpSatBackend(n, cost)
    elif name in MipBackend.SOLVERS:
        backend = MipBackend(name, n, cost)
    elif name == "pulp-cbc":
        backend = PulpBackend(n, cost)
    elif name == "pyscipopt":
        from planner.solve.scip_bc import PyScipBackend  # lazy: SCIP loads only when asked for

        backend = PyScipBackend(n, cost)
    else:
        raise UsageError(f"unknown backend (known: {', '.join(BACKENDS)})", field="backend", value=name)
    if backend.capabilities.node_limit:
        backend.node_limit = node_limit
    return backend
