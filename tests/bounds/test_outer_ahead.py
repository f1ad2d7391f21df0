"""The outer regions drawn ahead on another thread (:meth:`planner.bounds.outer.OuterRegions.draw_ahead`) are the
regions drawn when asked: each is drawn from its own piece alone."""

from __future__ import annotations

import pytest
import shapely

import planner.coverage.threads as threads
from planner.bounds.outer import OuterRegions
from planner.coverage.targets import make_targets
from planner.coverage.visibility import SightLimits
from planner.site import ScanSide, Site, Zone
from planner.site.model import Obstacle


def _site() -> Site:
    zone = Zone("R", ScanSide.BOTH, ((0, 0), (16, 0), (16, 10), (7, 10), (7, 16), (0, 16)), (3.0,) * 6)
    return Site("ahead", (zone,), obstacles=(Obstacle("column", ((20, 3), (21, 3), (21, 4), (20, 4)), 4.0),))


@pytest.mark.parametrize("cores", [1, 2])
def test_drawn_ahead_is_drawn_when_asked(cores: int, monkeypatch: pytest.MonkeyPatch) -> None:
    site = _site()
    t = make_targets(site, 1.0)
    limits = SightLimits(25.0, 70.0)
    monkeypatch.setattr(threads, "thread_count", lambda: cores)
    monkeypatch.setattr("planner.bounds.outer.thread_count", lambda: cores)
    ahead = OuterRegions()
    ahead.draw_ahead(site, t, limits, range(0, len(t), 2))  # every other piece ahead, the rest when asked
    assert bool(ahead._ahead) == (cores > 1)  # one core: nothing ahead, all drawn when asked
    got = ahead.of(site, t, limits, range(len(t)))
    plain = OuterRegions().of(site, t, limits, range(len(t)))
    assert list(got) == list(plain)
    assert all(shapely.to_wkb(got[k]) == shapely.to_wkb(plain[k]) for k in plain)
    assert ahead.space(site, "site", limits) is ahead.spaces["site"]


def test_an_error_drawn_ahead_is_raised_when_asked(monkeypatch: pytest.MonkeyPatch) -> None:
    site = _site()
    t = make_targets(site, 1.0)
    limits = SightLimits(25.0, 70.0)
    monkeypatch.setattr(threads, "thread_count", lambda: 2)
    monkeypatch.setattr("planner.bounds.outer.thread_count", lambda: 2)

    def broken(*args: object, **kwargs: object) -> None:
        raise ValueError("drawn ahead")

    monkeypatch.setattr("planner.bounds.outer.coverage_regions", broken)
    regions = OuterRegions()
    regions.draw_ahead(site, t, limits, [0, 1])
    with pytest.raises(ValueError, match="drawn ahead"):
        regions.of(site, t, limits, [0])
