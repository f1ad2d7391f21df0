"""The tiles' pool is built with each piece's coverage region drawn once: the whole-side and the axis candidates
share the frame spaces and the regions (each drew its own when given none), and the pool is the same."""

from __future__ import annotations

from collections import Counter

import planner.candidates.axis as axis_mod
import planner.candidates.from_regions as regions_mod
from planner.plan import PlanOptions, site_candidates
from planner.site.model import ScanSide, Site, Zone
from planner.site.params import Parameters
from planner.tiles.prepare import prepare, tiles_problem

OPTIONS = PlanOptions(method="milp", pricing=False)


def _room() -> Site:
    zone = Zone("K", ScanSide.INSIDE, ((0.0, 0.0), (60.0, 0.0), (60.0, 8.0), (0.0, 8.0)), (3.0,) * 4)
    return Site("room", (zone,), parameters=Parameters(theta_max_deg=68.0, overlap=0.0))


def test_prepare_draws_each_region_once_and_keeps_the_pool(monkeypatch) -> None:
    problem = tiles_problem(_room(), OPTIONS)
    alone = site_candidates(problem, problem.targets)  # each kind of candidate with its own regions
    drawn: Counter[int] = Counter()

    def counted(module):
        whole = module.coverage_regions

        def draw(site, targets, limits, which=None, spaces=None, outer=False):
            drawn.update(int(t) for t in which)
            return whole(site, targets, limits, which, spaces, outer)

        monkeypatch.setattr(module, "coverage_regions", draw)

    counted(axis_mod)
    counted(regions_mod)
    prep = prepare(problem)
    assert drawn and max(drawn.values()) == 1
    assert [c.xy for c in prep.pool] == [c.xy for c in alone]
