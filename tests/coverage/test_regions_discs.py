"""Range discs kept per frame (:attr:`planner.coverage.regions.FrameSpace.discs`) for later chunks and calls: the
regions drawn with discs taken from the cache are the regions drawn with every disc drawn afresh, bit for bit, with
the cache full (:data:`~planner.coverage.regions.DISC_CACHE`) as well."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import shapely

import planner.coverage.regions as regions_mod
from planner.coverage.regions import coverage_regions, frame_space
from planner.coverage.targets import make_targets
from planner.coverage.visibility import SightLimits
from planner.site.model import ScanSide, Site, Zone

SITE = Site(
    "a room scanned inside and out, beside another",
    (
        Zone("L", ScanSide.BOTH, ((0, 0), (12, 0), (12, 5), (7, 5), (7, 10), (0, 10)), (3,) * 6),
        Zone("R", ScanSide.INSIDE, ((15, 0), (24, 0), (24, 9), (15, 9)), (4,) * 4),
    ),
)


@pytest.mark.parametrize("cap", [4096, 5])
def test_regions_with_cached_discs_are_the_regions_drawn_afresh(cap: int, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(regions_mod, "CHUNK", 9)
    monkeypatch.setattr(regions_mod, "DISC_CACHE", cap)
    lim = SightLimits(20.0, 70.0, 1.5)
    targets = make_targets(SITE, 1.0)
    frame = targets.frames[0]
    spaces = {frame: frame_space(SITE, frame, lim)}
    order = np.random.default_rng(4).permutation(len(targets))
    warm: dict[int, shapely.Geometry] = {}
    for part in np.array_split(order, 6):  # calls one after another: later ones take discs the earlier drew
        warm.update(coverage_regions(SITE, targets, lim, part, spaces))
    assert 0 < len(spaces[frame].discs) <= cap
    monkeypatch.setattr(regions_mod, "DISC_CACHE", 0)  # every disc drawn afresh, in one call
    fresh = coverage_regions(SITE, targets, lim, None, {frame: replace(spaces[frame], discs={})})
    for t in range(len(targets)):
        assert shapely.to_wkb(warm[t]) == shapely.to_wkb(fresh[t]), targets.label(t)
    assert any(not g.is_empty for g in warm.values())
