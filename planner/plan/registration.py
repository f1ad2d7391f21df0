"""Where a plan's stations stand (:func:`placed_stations`: the tripod discs, and stations recentred on them);
their registration is checked by :meth:`planner.coverage.relation.Registration.check`."""

from __future__ import annotations

from dataclasses import replace

from planner.coverage.matrix import CoverageProblem
from planner.plan.options import PlanOptions
from planner.plan.tripod import TripodDisc, tripod_discs
from planner.site.candidate import Candidate
from planner.site.model import Site


def placed_stations(
    site: Site,
    problem: CoverageProblem,
    selected: tuple[int, ...],
    options: PlanOptions,
    partners: dict[int, list[int]],
) -> tuple[list[Candidate], tuple[TripodDisc, ...]]:
    """The chosen stations and, with ``options.tripod`` or ``options.recentre``, their tripod discs (relied
    pieces only, checked on centre and rim); ``recentre`` moves each station to its disc's centre."""
    stations = [problem.candidates[i] for i in selected]
    if not (options.tripod or options.recentre):
        return stations, ()
    tripods = tuple(tripod_discs(site, problem, selected, problem.limits, partners, options.recentre))
    if options.recentre:
        stations = [replace(s, x=d.centre[0], y=d.centre[1]) for s, d in zip(stations, tripods)]
    return stations, tripods
