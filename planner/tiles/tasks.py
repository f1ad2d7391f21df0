"""One tile's work, a pure function of picklable inputs: its coverage columns and its own plan.

The same function runs in the serial loop and as a Dask task, so both give the same plan.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.coverage.sight import Sight
from planner.coverage.targets import Targets
from planner.plan.tripod import take_targets
from planner.site.candidate import Candidate
from planner.solve.instance import cover_instance
from planner.solve.local_search import Shrunk, shrink
from planner.solve.milp import MilpOptions, solve
from planner.solve.result import Status
from planner.tiles.layout import Tile, TileJob


@dataclass(frozen=True, eq=False, kw_only=True)
class TileResult:
    """A tile's coverage pairs (global indices, with worst slant range and incidence) and its plan. ``selected``:
    global candidate indices of the tile's plan; ``covers_core``: that plan, re-checked on the tile's coverage
    columns (not the solver's word), sees every core target."""

    tile: Tile
    rows: NDArray[np.int64]
    cols: NDArray[np.int64]
    slant_m: NDArray[np.float64]
    incidence_deg: NDArray[np.float64]
    status: Status
    selected: tuple[int, ...]
    objective: float | None
    bound: float | None
    unseen: NDArray[np.int64]
    covers_core: bool
    coverage_s: float
    solve_s: float
    wall_cap_hit: bool = False

    @property
    def n_targets(self) -> int:
        return int(len(np.unique(self.cols)))


def tile_task(
    sight: Sight,
    candidates: Sequence[Candidate],
    targets: Targets,
    groups: Sequence[str],
    job: TileJob,
    milp: MilpOptions | None,
) -> TileResult:
    """Coverage of the tile's core pieces by the candidates in its margin, then the tile's MILP (with the
    registration rule inside the tile: overlap measured on the tile's pieces); with ``milp`` None the coverage
    only (status NO_SOLUTION, no plan: the whole site's plain cover is made once, :mod:`planner.tiles.run`). The
    result also where some core piece is seen by no candidate (``unseen``, status INFEASIBLE)."""
    t0 = time.perf_counter()
    cands = [candidates[i] for i in job.candidates]
    problem = sight.coverage(cands, take_targets(targets, job.targets))
    coo = problem.by_candidate.tocoo()
    t1 = time.perf_counter()
    unseen = job.targets[problem.uncoverable()]
    pairs: dict[str, Any] = {
        "tile": job.tile,
        "rows": job.candidates[coo.row],
        "cols": job.targets[coo.col],
        "slant_m": problem.slant_m.tocoo().data,
        "incidence_deg": problem.incidence_deg.tocoo().data,
        "unseen": unseen,
        "coverage_s": t1 - t0,
    }
    if unseen.size or milp is None:
        status = Status.INFEASIBLE if unseen.size else Status.NO_SOLUTION
        return TileResult(
            **pairs, status=status, selected=(), objective=None, bound=None, covers_core=False, solve_s=0.0
        )
    inst = cover_instance(problem, groups=[groups[i] for i in job.candidates], name=job.tile.name)
    res = solve(inst, milp)
    picked = list(res.selected)
    covers = bool(picked) and bool(np.all(problem.covered_by(picked) >= 1))
    selected = tuple(sorted(int(job.candidates[i]) for i in picked))
    return TileResult(
        **pairs,
        status=res.status,
        selected=selected,
        objective=res.objective,
        bound=res.bound,
        covers_core=covers,
        solve_s=time.perf_counter() - t1,
        wall_cap_hit=res.wall_cap_hit,
    )


def shrink_task(
    a: sp.csr_matrix, adj: sp.csr_matrix, groups: Sequence[str], plan: Sequence[int], moves: int, floor: int, job: int
) -> Shrunk:
    """The local search on the kept plan with seed ``job`` (one of the seeds of ``TileOptions.search_seeds``)."""
    return shrink(a, adj, groups, plan, moves=moves, floor=floor, seed=job)
