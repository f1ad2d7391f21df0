"""The outer coverage regions O_t of a run, drawn once: pricing's heaviest-weight check and the connected plane bound
both weigh them, and drawing them is most of what either costs on a large zone-side."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import shapely

from planner.coverage.regions import FrameSpace, coverage_regions, frame_space
from planner.coverage.visibility import SightLimits
from planner.site.model import Site


@dataclass(frozen=True, eq=False)
class OuterRegions:
    """O_t per piece (:func:`planner.coverage.regions.coverage_regions` with ``outer=True``) and the outer frame spaces
    they are drawn in, kept for one site, one set of targets and one set of limits (one planning run)."""

    drawn: dict[int, shapely.Geometry] = field(default_factory=dict)
    spaces: dict[str, FrameSpace] = field(default_factory=dict)

    def of(self, site: Site, targets: Any, limits: SightLimits, pieces: Iterable[int]) -> dict[int, shapely.Geometry]:
        """O_t for ``pieces``: those not drawn yet are drawn now (all in one call, frame by frame)."""
        want = [int(p) for p in pieces]
        missing = [p for p in dict.fromkeys(want) if p not in self.drawn]
        if missing:
            self.drawn.update(coverage_regions(site, targets, limits, missing, self.spaces, outer=True))
        return {p: self.drawn[p] for p in want}

    def space(self, site: Site, frame: str, limits: SightLimits) -> FrameSpace:
        """The outer frame space of ``frame`` the regions are drawn in (made now where no region of it is drawn yet):
        every O_t of a zone-side lies in that side's stand area there."""
        if frame not in self.spaces:
            self.spaces[frame] = frame_space(site, frame, limits, outer=True)
        return self.spaces[frame]
