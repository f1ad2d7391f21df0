"""The outer coverage regions O_t of a run, drawn once: pricing's heaviest-weight check and the connected plane bound
both weigh them, and drawing them is most of what either costs on a large zone-side. They may be drawn ahead, on another
thread while the run solves its LPs (:meth:`OuterRegions.draw_ahead`): each region is drawn from its own piece alone, so
it is the same region whenever and beside whatever it is drawn."""

from __future__ import annotations

from collections.abc import Iterable
from concurrent.futures import Future
from dataclasses import dataclass, field
from typing import Any

import shapely

from planner.coverage.regions import FrameSpace, coverage_regions, frame_space
from planner.coverage.threads import Background, thread_count
from planner.coverage.visibility import SightLimits
from planner.site.model import Site


@dataclass(frozen=True, eq=False)
class OuterRegions:
    """O_t per piece (:func:`planner.coverage.regions.coverage_regions` with ``outer=True``) and the outer frame spaces
    they are drawn in, kept for one site, one set of targets and one set of limits (one planning run)."""

    drawn: dict[int, shapely.Geometry] = field(default_factory=dict)
    spaces: dict[str, FrameSpace] = field(default_factory=dict)
    #: a batch being drawn ahead on another thread (at most one), taken into ``drawn`` before anything reads them
    _ahead: list[tuple[Background, Future[dict[int, shapely.Geometry]]]] = field(default_factory=list)

    def draw_ahead(self, site: Site, targets: Any, limits: SightLimits, pieces: Iterable[int]) -> None:
        """Start drawing O_t for those of ``pieces`` not drawn yet on another thread, where this process may use more
        than one core (else nothing: :meth:`of` draws them when asked); :meth:`of` and :meth:`space` wait for them."""
        self._settle()
        missing = [p for p in dict.fromkeys(int(p) for p in pieces) if p not in self.drawn]
        if not missing or thread_count() < 2:
            return
        later = Background()
        self._ahead.append((later, later.start(coverage_regions, site, targets, limits, missing, self.spaces, True)))

    def of(self, site: Site, targets: Any, limits: SightLimits, pieces: Iterable[int]) -> dict[int, shapely.Geometry]:
        """O_t for ``pieces``: those not drawn yet are drawn now (all in one call, frame by frame)."""
        self._settle()
        want = [int(p) for p in pieces]
        missing = [p for p in dict.fromkeys(want) if p not in self.drawn]
        if missing:
            self.drawn.update(coverage_regions(site, targets, limits, missing, self.spaces, outer=True))
        return {p: self.drawn[p] for p in want}

    def space(self, site: Site, frame: str, limits: SightLimits) -> FrameSpace:
        """The outer frame space of ``frame`` the regions are drawn in (made now where no region of it is drawn yet):
        every O_t of a zone-side lies in that side's stand area there."""
        self._settle()
        if frame not in self.spaces:
            self.spaces[frame] = frame_space(site, frame, limits, outer=True)
        return self.spaces[frame]

    def _settle(self) -> None:
        """Wait for the batch drawn ahead, if any, and keep its regions (its error, if any, is raised here)."""
        while self._ahead:
            later, batch = self._ahead.pop()
            try:
                self.drawn.update(batch.result())
            finally:
                later.close()
