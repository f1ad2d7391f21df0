"""The engine: :func:`plan_site`, what ``planner plan`` runs, for a site file, a site, or a resolved problem.

reader (:func:`planner.site.load_site`) -> resolved problem (:func:`planner.plan.problem.resolve`) -> the strategy
it names (one model, :func:`planner.plan.run.plan_single`; or tiles, on Dask where it says,
:func:`planner.tiles.plan_by_tiles`) -> a verified :class:`~planner.plan.result.Plan`, with the strategy and the gap
to the best plan known for the site in its log and its result's info. The command line parses, calls this and
prints: the library and the command give the same plan.
"""

from __future__ import annotations

import os
from dataclasses import replace

from planner.core.checks import argument
from planner.io import load_site
from planner.plan.best_known import best_known, problem_kind
from planner.plan.options import PlanOptions
from planner.plan.problem import Problem
from planner.plan.result import Plan
from planner.plan.run import as_problem, plan_single
from planner.site.model import Site


def problem_of(site: Site | str | os.PathLike[str] | Problem, options: PlanOptions | None = None) -> Problem:
    """``site`` resolved under ``options``: read first when it is a path; a resolved problem as it is (then
    ``options`` must be None: the problem carries its own)."""
    argument(site, (Site, str, os.PathLike, Problem), "site")
    if isinstance(site, (str, os.PathLike)):
        site = load_site(os.fspath(site))
    return as_problem(site, options)


def plan_site(site: Site | str | os.PathLike[str] | Problem, options: PlanOptions | None = None) -> Plan:
    """Plan a site as ``planner plan`` does: the problem resolved once (:func:`problem_of`), planned by the
    strategy it names, verified, with the strategy and the best-known gap added. The plan's problem holds the
    run's one registration (:attr:`Problem.registration`), which its field sheet, network check and report take.

    Examples
    --------
    >>> import planner
    >>> plan = planner.plan_site("instances/polygon_b.json")            # doctest: +SKIP
    >>> problem = planner.resolve(planner.load_site("instances/plant_16ha.json"))  # doctest: +SKIP
    >>> problem.strategy.tiles                                          # doctest: +SKIP
    True

    Raises InfeasibleError where some wall piece is seen from no position, UsageError where the options contradict
    each other or the site (e.g. Dask workers for one model).
    """
    problem = problem_of(site, options)
    strategy = problem.strategy
    if strategy.tiling is None:
        plan = plan_single(problem)
        if problem.options.objective == "field-time":  # beside the plans at one setting and the fewest stations
            from planner.field.tradeoff import with_tradeoff

            plan = with_tradeoff(plan)
    else:
        from planner.tiles import dask_client, plan_by_tiles

        o = problem.options.strategy
        if not strategy.workers and not o.scheduler:
            plan = plan_by_tiles(problem, tiling=strategy.tiling)
        else:
            with dask_client(strategy.workers, o.scheduler, o.worker_memory) as client:
                plan = plan_by_tiles(problem, tiling=strategy.tiling, client=client)
    return with_strategy(plan)


def with_strategy(plan: Plan) -> Plan:
    """The plan with its problem's strategy in its log (summary) and in its result's info (plan.json), and the
    best plan known for the same problem (:mod:`planner.plan.best_known`: the gap on the same pool, else a line
    saying the pools differ)."""
    problem = plan.problem
    info = {**plan.result.info, "strategy": problem.strategy.to_dict()}
    log = [*plan.log, problem.strategy.line()]
    kind = problem_kind(problem.rule is not None)
    share = problem.checked_rule.overlap if problem.rule else 0.0
    registration = problem.registration.mode if problem.rule else None
    fingerprint = plan.pool.fingerprint if plan.pool is not None else None
    known = best_known(plan.site.name, kind, registration, share, fingerprint)
    if known is not None:
        n = len(plan.stations)
        info["best_known"] = known.to_dict(n)
        log.append(known.line(n))
    return replace(plan, result=replace(plan.result, info=info), log=tuple(log))
