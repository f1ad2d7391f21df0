"""The outer coverage regions O_t of a run, drawn once: pricing's heaviest-weight check and the connected plane bound
both weigh them, and drawing them is most of what either costs on a large zone-side. They may be drawn ahead, on another
thread while the run solves its LPs (:meth:`OuterRegions.draw_ahead`), until the run asks for them: each region is drawn
from its own piece alone, so it is the same region whenever and beside whatever it is drawn."""

from __future__ import annotations

import threading
from collections.abc import Iterable
from concurrent.futures import Future
from dataclasses import dataclass, field
from typing import Any

import shapely

from planner.coverage.regions import FrameSpace, coverage_regions, frame_space
from planner.coverage.threads import Background, thread_count
from planner.coverage.visibility import SightLimits
from planner.site.model import Site

#: pieces per batch drawn ahead: the drawing ahead stops after the batch under way when the run asks for its regions
AHEAD_BATCH = 256


@dataclass(frozen=True, eq=False)
class OuterRegions:
    """O_t per piece (:func:`planner.coverage.regions.coverage_regions` with ``outer=True``) and the outer frame spaces
    they are drawn in, kept for one site, one set of targets and one set of limits (one planning run)."""

    drawn: dict[int, shapely.Geometry] = field(default_factory=dict)
    spaces: dict[str, FrameSpace] = field(default_factory=dict)
    #: the regions being drawn ahead on another thread (at most one run, its stop flag), taken into ``drawn`` before
    #: anything reads them
    _ahead: list[tuple[Background, threading.Event, Future[dict[int, shapely.Geometry]]]] = field(default_factory=list)

    def draw_ahead(self, site: Site, targets: Any, limits: SightLimits, pieces: Iterable[int]) -> None:
        """Start drawing O_t for those of ``pieces`` not drawn yet on another thread, :data:`AHEAD_BATCH` at a time,
        where this process may use more than one core (else nothing: :meth:`of` draws them when asked). The next call of
        :meth:`of` or :meth:`space` stops it after the batch under way and keeps what it drew; :meth:`of` draws the
        rest it needs itself."""
        self._settle()
        missing = [p for p in dict.fromkeys(int(p) for p in pieces) if p not in self.drawn]
        if not missing or thread_count() < 2:
            return
        stop = threading.Event()

        def batches() -> dict[int, shapely.Geometry]:
            out: dict[int, shapely.Geometry] = {}
            for k in range(0, len(missing), AHEAD_BATCH):
                if stop.is_set():
                    break
                out.update(coverage_regions(site, targets, limits, missing[k : k + AHEAD_BATCH], self.spaces, True))
            return out

        later = Background()
        self._ahead.append((later, stop, later.start(batches)))

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
        """Stop the drawing ahead, if any, after its batch under way and keep its regions (its error is raised here)."""
        while self._ahead:
            later, stop, drawn = self._ahead.pop()
            stop.set()
            try:
                self.drawn.update(drawn.result())
            finally:
                later.close()
