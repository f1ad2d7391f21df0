"""The zone-sides test of the connected plane bound (:func:`planner.bounds.plane_ring._sides_meet`): zone-sides found
apart by their stand areas (:func:`planner.bounds.plane_ring._apart`, no outer region drawn) are apart by their grown
regions too, and the regions of a zone-side at its count are drawn only where the test needs them."""

from __future__ import annotations

import numpy as np
import pytest

import planner
import planner.bounds.plane_ring as ring
from planner.bounds.outer import OuterRegions
from planner.bounds.plane_ring import connected_plane_bound
from planner.plan import PlanOptions, coverage_problem, plan_limits, resolve
from planner.site.model import ScanSide, Site, Zone
from planner.site.params import Parameters
from planner.site.validate import validate_site
from planner.solve.milp import MilpOptions


def _site(zones: list[tuple[str, ScanSide, list[tuple[float, float]]]], standoff: float = 0.4) -> Site:
    made = tuple(Zone(z, side, tuple(xy), (3.0,) * len(xy)) for z, side, xy in zones)
    params = Parameters(theta_max_deg=70.0, max_slant_range_m=25.0, overlap=0.3, min_standoff_m=standoff)
    return Site("sides", made, parameters=params)


def _box(x0: float, y0: float, x1: float, y1: float) -> list[tuple[float, float]]:
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def _bound(site: Site, apart: bool, monkeypatch: pytest.MonkeyPatch, count: int = 0) -> tuple[str, tuple, OuterRegions]:
    """The connected plane bound's note and sides, with the stand-area test on or off, and the outer regions drawn;
    ``count``: the plan's stations on each zone-side (0: every zone-side at its count with no duals, no ring walked)."""
    if not apart:
        monkeypatch.setattr(ring, "_apart", lambda *a: False)
    options = PlanOptions(method="milp", precision=False, milp=MilpOptions(overlap=planner.OverlapRule(0.3)))
    problem, _unseen, _ = coverage_problem(resolve(site, options))
    limits = plan_limits(validate_site(site), options)
    t = problem.targets
    keys = np.unique(t.zone.astype(np.int64) * 2 + t.side)
    counts = {int(k): count for k in keys}
    outer = OuterRegions()
    cb = connected_plane_bound(site, problem, limits, 0.3, np.zeros(len(t)), counts, outer_regions=outer)
    monkeypatch.undo()
    return cb.note, cb.sides, outer


SITES = {
    "two rooms side by side": [("A", ScanSide.INSIDE, _box(0, 0, 8, 6)), ("B", ScanSide.INSIDE, _box(8, 0, 14, 6))],
    "a room and its outside": [("A", ScanSide.INSIDE, _box(0, 0, 8, 6)), ("O", ScanSide.OUTSIDE, _box(-2, -2, 20, 9))],
    "two buildings seen from outside": [
        ("A", ScanSide.OUTSIDE, _box(0, 0, 6, 6)),
        ("B", ScanSide.OUTSIDE, _box(12, 0, 18, 6)),
    ],
}


@pytest.mark.parametrize("name", list(SITES))
def test_stand_areas_decide_as_the_regions_do(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    site = _site(SITES[name])
    fast = _bound(site, True, monkeypatch)
    plain = _bound(site, False, monkeypatch)
    assert fast[:2] == plain[:2]
    if name == "two buildings seen from outside":  # a position between them sees both: not summed
        assert fast[0].startswith("not formed: A/outside and B/outside")
    else:
        assert fast[0] == "" and len(fast[1]) == 2
        # every zone-side at its count and apart by its stand area: only the weighed regions (none here) are drawn
        assert fast[2].drawn == {} and len(plain[2].drawn) > 0


def test_no_stand_off_falls_back_to_the_regions(monkeypatch: pytest.MonkeyPatch) -> None:
    # with no stand-off the outer stand areas reach the walls: the stand-area test cannot decide, the regions do
    site = _site(SITES["two rooms side by side"], standoff=0.0)
    fast = _bound(site, True, monkeypatch)
    assert fast[:2] == _bound(site, False, monkeypatch)[:2]
    assert len(fast[2].drawn) > 0


@pytest.mark.slow
def test_rings_walked_alike(monkeypatch: pytest.MonkeyPatch) -> None:
    # zone-sides below their count walk their rings over the same regions either way
    site = _site(SITES["a room and its outside"])
    fast = _bound(site, True, monkeypatch, count=5)
    assert fast[:2] == _bound(site, False, monkeypatch, count=5)[:2]
    assert any(s.ring is not None for s in fast[1])
