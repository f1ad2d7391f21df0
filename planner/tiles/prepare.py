"""What a tiled plan needs of the whole site before any tile runs: the pool, the pieces, where a station may stand,
the registration groups and the overlap rule, made once here for :func:`planner.tiles.run.plan_by_tiles` and for the
scripts that study its matrix (``scripts/studies/study_gap.py``, ``scripts/bench/bench_lagrange.py``), so that they
always study the planner's own problem.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any, cast

import numpy as np
import scipy.sparse as sp

from planner.coverage.matrix import station_places
from planner.coverage.overlap import overlap_adjacency, piece_lengths
from planner.coverage.relation import Registration
from planner.coverage.targets import Targets
from planner.coverage.visibility import SightLimits
from planner.plan import PlanOptions, site_candidates
from planner.plan.problem import Problem, resolve
from planner.plan.run import as_problem
from planner.site.candidate import Candidate
from planner.site.model import Site
from planner.tiles.layout import TileJob, make_tiles, tile_job, zone_anchors
from planner.tiles.options import TileOptions, tile_milp


@dataclass(frozen=True)
class Prepared:
    """The whole site's problem before coverage: ``pool`` (candidates) and ``targets`` (pieces) as
    :func:`planner.plan.build_problem` makes them, ``xy`` (candidates' positions), ``usable`` (where a station may
    stand: ``station_places`` gives no reason against it), and each candidate's registration group name in
    ``groups`` with the ``links`` between groups (the problem's registration)."""

    problem: Problem
    pool: tuple[Candidate, ...]
    targets: Targets
    xy: np.ndarray
    usable: np.ndarray
    groups: tuple[str, ...]
    links: Any

    @property
    def limits(self) -> SightLimits:
        return self.problem.limits

    @property
    def registration(self) -> Registration:
        return self.problem.registration

    def overlap(self, by_candidate: sp.csr_matrix) -> sp.csr_matrix:
        """The overlap relation (candidate x candidate, symmetric) of a coverage matrix over this pool."""
        lengths = piece_lengths(self.targets.s0_m, self.targets.s1_m)
        rule = self.registration.checked_rule
        adj, _ = overlap_adjacency(by_candidate, lengths, rule, self.groups, self.xy, self.links)
        return cast(sp.csr_matrix, adj)

    def coverage(self) -> sp.csr_matrix:
        """The whole site's coverage (candidates x pieces, bool CSR) built in one piece, with the rows of candidates
        that stand nowhere emptied: the matrix the tiles assemble (``test_tiles_columns_are_the_site_matrix``). For
        studies of it; the planner builds it by tiles."""
        a = self.problem.sight.coverage(list(self.pool), self.targets).by_candidate.astype(bool).tocsr()
        a.data &= np.repeat(self.usable, np.diff(a.indptr))  # a row per candidate: empty where it stands nowhere
        a.eliminate_zeros()
        return a


def tiles_problem(
    site: Site | Problem, options: PlanOptions | None = None, tiling: TileOptions | None = None
) -> Problem:
    """``site`` itself when it is a resolved problem, else ``site`` resolved for tiles under ``options`` (default:
    the MILP), registration ``options.registration`` or else the site's default
    (:func:`planner.coverage.links.default_registration`). ``tiling`` given (and no strategy in ``options``): the
    strategy is those tiles, as ``planner plan --tiles M`` resolves it (so the same pool: the automatic strategy's
    finer grid is its own); None: the automatic strategy, the plain command's pool."""
    if isinstance(site, Problem):
        return as_problem(site, options)
    options = options or PlanOptions(method="milp")
    if tiling is not None and options.strategy.tiling is None and not options.strategy.single:
        options = replace(options, strategy=replace(options.strategy, tiling=tiling))  # as `--tiles M` resolves
    return resolve(site, options)


def prepare(problem: Problem | Site, options: PlanOptions | None = None, extra: Sequence[Candidate] = ()) -> Prepared:
    """The :class:`Prepared` problem of a resolved run (or of a site, :func:`tiles_problem`): its registration
    scope, links within the overlap rule's ``max_link_m`` or else the sight range. ``extra``: candidates added to
    the pool (those that the completion of unseen pieces found, :func:`planner.tiles.run.plan_by_tiles`)."""
    problem = tiles_problem(problem, options)
    site = problem.site
    targets = problem.targets  # the pool as :func:`planner.plan.build_problem` makes it, before the completion
    # the frame spaces and coverage regions drawn once, for the whole-side and the axis candidates both (each
    # drew its own when given none)
    pool = site_candidates(problem, targets, {}, {}) + list(extra)
    xy = np.array([c.xy for c in pool], dtype=float).reshape(-1, 2)
    usable = np.array([r == "" for r in station_places(site, xy, [c.frame for c in pool]).reason], dtype=bool)
    labels, links = problem.registration.groups(pool)
    groups = tuple("/".join(str(x) for x in cast(tuple, g)) for g in labels)
    return Prepared(problem, tuple(pool), targets, xy, usable, groups, links)


def tile_work(tiling: TileOptions, prep: Prepared) -> tuple[list[TileJob], dict[str, Any]]:
    """The tiles' jobs (one per tile of ``tiling.tile_m``, with a margin of ``tiling.margin_m`` or the slant range)
    and the values every tile task shares: what :func:`planner.tiles.run.plan_by_tiles` hands to its engine, and
    ``scripts/bench/bench_workers.py`` to each worker count."""
    site, options = prep.problem.site, prep.problem.options
    margin = tiling.margin_for(prep.limits.max_slant_range_m)
    anchor = zone_anchors(site, prep.targets)
    jobs = [tile_job(t, anchor, prep.targets, prep.xy, prep.usable) for t in make_tiles(anchor, tiling.tile_m, margin)]
    shared = {
        "sight": prep.problem.sight,
        "candidates": prep.pool,
        "targets": prep.targets,
        "groups": prep.groups,
        # a tile MILP where its plans are asked for, or where a plain cover has no CFT cover to start from
        "milp": tile_milp(options, tiling)
        if tiling.tile_plans or (not tiling.cft and prep.problem.rule is None)
        else None,
    }
    return jobs, shared
