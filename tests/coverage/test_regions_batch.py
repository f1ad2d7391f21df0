"""Coverage regions drawn in chunks (vectorised over a frame's pieces) are the regions one piece at a time draws, bit for
bit: horizontal and 3-D incidence, the per-view precision test, the outer approximation, a stand-off, chunks smaller
than the site (so that discs shared across a chunk's edge and pieces split between chunks are exercised), and the
reason an empty region gives."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import shapely

import planner.coverage.regions as regions_mod
from planner.coverage.regions import (
    STAGE_REASON,
    coverage_regions,
    frame_space,
    piece_region,
    region_stages,
    why_empty,
)
from planner.coverage.targets import make_targets
from planner.coverage.visibility import PrecisionRule, SightLimits
from planner.instrument.accuracy import ErrorBudget, RangeAngleSigma, max_slant_range_m, sigma_instr_m
from planner.site.model import Obstacle, ScanSide, Site, Zone

P30 = RangeAngleSigma(range_sigma_const_m=0.0012, range_sigma_ppm=10.0, angle_sigma_arcsec=8.0)
BUDGET = ErrorBudget(0.0005, 0.0005, 0.0005)
SITE = Site(
    "two rooms and a yard",
    (
        Zone("H", ScanSide.INSIDE, ((0, 0), (20, 0), (20, 12), (0, 12)), (4,) * 4,
             holes=(((8, 5), (8, 7), (11, 7), (11, 5)),), hole_heights_m=((3,) * 4,)),
        Zone("L", ScanSide.BOTH, ((20, 0), (32, 0), (32, 5), (25, 5), (25, 10), (20, 10)), (3,) * 6),
        Zone("T", ScanSide.INSIDE, ((0, 20), (3, 20), (3, 23), (0, 23)), (60,) * 4),  # beyond range: empty regions
    ),
    obstacles=(Obstacle("column", ((36, 2), (37, 2), (37, 3), (36, 3)), 2.0),),
)  # fmt: skip


def limits(kind: str) -> SightLimits:
    if kind == "precision":
        s_prec = max_slant_range_m(P30, sigma_instr_m(0.003, BUDGET))
        return SightLimits(
            40.0, 79.0, 1.5, precision_range_m=s_prec, precision=PrecisionRule(P30, BUDGET, 0.003, "table")
        )
    return SightLimits(25.0, 68.0, 1.5, incidence_3d=kind == "3d")


@pytest.mark.parametrize(
    "kind,outer,standoff",
    [
        ("plain", False, 0.0),
        pytest.param("plain", True, 0.5, marks=pytest.mark.slow),
        pytest.param("3d", False, 0.3, marks=pytest.mark.slow),
        pytest.param("precision", False, 0.0, marks=pytest.mark.slow),
    ],
)
def test_chunked_regions_are_the_single_piece_regions(
    kind: str, outer: bool, standoff: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    site = replace(SITE, parameters=replace(SITE.parameters, min_standoff_m=standoff))
    lim = limits(kind)
    targets = make_targets(site, 1.0)
    monkeypatch.setattr(regions_mod, "CHUNK", 7)
    which = np.random.default_rng(3).permutation(len(targets))  # any order; duplicates of a frame split over chunks
    spaces: dict = {}
    drawn = coverage_regions(site, targets, lim, which, spaces, outer=outer)
    assert list(drawn) == [int(t) for t in which]
    empty = 0
    for t in range(len(targets)):
        space = spaces[targets.frames[int(targets.frame[t])]]
        one = piece_region(targets, t, lim, space, outer)
        assert shapely.to_wkb(drawn[t]) == shapely.to_wkb(one), targets.label(t)
        stages = list(region_stages(targets, t, lim, space, outer))
        assert shapely.to_wkb(stages[-1][1]) == shapely.to_wkb(one)
        if one.is_empty:
            empty += 1
            assert stages[-1][0] in STAGE_REASON
            if not outer:
                assert why_empty(targets, t, lim, space) == STAGE_REASON[stages[-1][0]]
    assert 0 < empty < len(targets)  # both kinds of piece were drawn


def test_one_piece_of_a_frame_alone() -> None:
    lim = limits("plain")
    targets = make_targets(SITE, 1.0)
    space = frame_space(SITE, targets.frames[0], lim)
    t = int(np.flatnonzero(targets.zone == 0)[3])
    assert shapely.to_wkb(coverage_regions(SITE, targets, lim, [t])[t]) == shapely.to_wkb(
        piece_region(targets, t, lim, space)
    )
    assert coverage_regions(SITE, targets, lim, []) == {}
