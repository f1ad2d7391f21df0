"""Export a site's coverage problem for third-party solvers: OR-Library, MPS or JSON.

OR-Library and MPS carry the plain cover (min cost, every target covered once); the registration constraint is lazy
here and has no compact linear form, so the JSON export carries the overlap graph's edges for solvers that want to add
it themselves.
"""

from __future__ import annotations

from typing import Any

from planner.core.errors import UsageError
from planner.core.text import dumps
from planner.coverage.matrix import CoverageProblem
from planner.coverage.overlap import OverlapRule, overlap_adjacency, piece_lengths

FORMATS = ("orlib", "mps", "json")


def to_orlib(problem: CoverageProblem) -> str:
    """Beasley's format: 'm n', the n costs (all 1), then per row its count and 1-based columns (targets seen by no
    candidate are left out)."""
    bt = problem.by_target
    rows = [
        bt.indices[bt.indptr[t] : bt.indptr[t + 1]] + 1 for t in range(bt.shape[0]) if bt.indptr[t + 1] > bt.indptr[t]
    ]
    out = [f"{len(rows)} {problem.shape[0]}", " ".join(["1"] * problem.shape[0])]
    for r in rows:
        out.append(f"{len(r)} " + " ".join(str(int(v)) for v in r))
    return "\n".join(out) + "\n"


def to_mps(problem: CoverageProblem) -> str:
    """Free MPS of the plain cover (every target covered once), written by OR-Tools' model exporter."""
    from ortools.linear_solver import pywraplp

    s = pywraplp.Solver.CreateSolver("CBC")
    x = [s.BoolVar(c.id) for c in problem.candidates]
    bt = problem.by_target
    for t in range(bt.shape[0]):
        idx = bt.indices[bt.indptr[t] : bt.indptr[t + 1]]
        if idx.size:
            ct = s.RowConstraint(1, s.infinity(), f"t{t}")
            for i in idx:
                ct.SetCoefficient(x[i], 1.0)
    obj = s.Objective()
    for v in x:
        obj.SetCoefficient(v, 1.0)
    obj.SetMinimization()
    return s.ExportModelAsMpsFormat(False, False)


def to_json(problem: CoverageProblem, rule: OverlapRule) -> dict[str, Any]:
    t = problem.targets
    adj, share = overlap_adjacency(
        problem.by_candidate, piece_lengths(t.s0_m, t.s1_m), rule, [(c.zone, c.side.value) for c in problem.candidates]
    )
    bt = problem.by_target
    coo = share.tocoo()
    return {
        "candidates": [
            {"id": c.id, "zone": c.zone, "side": c.side.value, "x": c.x, "y": c.y, "kind": c.kind.value}
            for c in problem.candidates
        ],
        "targets": [
            {
                "id": t.label(i),
                "zone": t.zone_ids[t.zone[i]],
                "side": ["inside", "outside"][int(t.side[i])],
                "wall": int(t.wall[i]),
                "from_m": float(t.s0_m[i]),
                "to_m": float(t.s1_m[i]),
                "seen_by": bt.indices[bt.indptr[i] : bt.indptr[i + 1]].tolist(),
            }
            for i in range(len(t))
        ],
        "overlap": {
            "rule": {"overlap": rule.overlap, "min_shared_m": rule.min_shared_m, "max_link_m": rule.max_link_m},
            "edges": [[int(i), int(j), float(v)] for i, j, v in zip(coo.row, coo.col, coo.data) if i < j],
        },
    }


def export_problem(problem: CoverageProblem, fmt: str, rule: OverlapRule) -> str:
    if fmt == "orlib":
        return to_orlib(problem)
    if fmt == "mps":
        return to_mps(problem)
    if fmt == "json":
        return dumps(to_json(problem, rule), indent=None)
    raise UsageError(f"unknown format (known: {', '.join(FORMATS)})", field="format", value=fmt)
