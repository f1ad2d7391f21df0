"""Registration networks across storeys: which accessible areas the site's stairs join over several storeys, and whether
a plan's stations in each form one connected network (the summary's line, plan.json's ``registration.networks``).

A site read from a building model has one frame per storey; its stairs (:class:`planner.site.stairs.Stair`) join
the storeys' accessible areas (:func:`planner.coverage.openings.accessible_areas`), and the stair links
(:mod:`planner.coverage.stair_links`) are the only links between stations of two frames. So an area spanning
several frames whose chosen stations form one component under the overlap relation is one registration network
across those storeys. A site without stairs has none of this (no line, no key).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from planner.coverage.openings import accessible_areas, space_of
from planner.site.model import Site


@dataclass(frozen=True, kw_only=True)
class StoreyNetwork:
    """One accessible area (``area``, :func:`planner.coverage.openings.accessible_areas`) that the ``stairs`` join
    across storeys (``frames``, in the site's order); ``parts``: the components of the plan's stations in it under the
    overlap relation (1: one network), None where the plan was registered per zone-side or has no station there."""

    area: int
    frames: tuple[str, ...]
    stairs: tuple[str, ...]
    parts: int | None

    def line(self) -> str:
        """The summary's line."""
        span = f"{len(self.frames)} storeys ({', '.join(self.frames)})"
        by = f"stair{'s' if len(self.stairs) > 1 else ''} {', '.join(self.stairs)}"
        if self.parts is None:
            return f"registration network: {span} joined by {by}, not checked as one group (zone scope)"
        state = "one connected network" if self.parts == 1 else f"NOT connected: {self.parts} parts"
        return f"registration network: {span} linked by {by}: {state}"

    def to_dict(self) -> dict[str, Any]:
        return {
            "area": self.area,
            "storeys": list(self.frames),
            "stairs": list(self.stairs),
            "parts": self.parts,
            "connected": self.parts == 1,
        }


def storey_networks(site: Site, registration: dict[str, int]) -> tuple[StoreyNetwork, ...]:
    """One network per area the site's stairs join across frames, by area number (none without stairs), with
    the parts the plan's check found in it (``registration``: its components by group key,
    :meth:`planner.coverage.relation.Registration.check`: ``area K (...)`` in ``site`` scope)."""
    if not site.stairs:
        return ()
    areas = accessible_areas(site)
    frames: dict[int, list[str]] = {}
    for z in site.zones:
        for side in z.scan_side.sides:
            here = frames.setdefault(areas[space_of(z, side)], [])
            if z.frame not in here:
                here.append(z.frame)
    out = []
    for k, fs in sorted(frames.items()):
        if len(fs) < 2:
            continue
        stairs = tuple(s.name for s in site.stairs if areas.get(("in", s.lower_zone)) == k)
        parts = next((n for g, n in registration.items() if g.startswith(f"area {k} (")), None)
        out.append(StoreyNetwork(area=k, frames=tuple(fs), stairs=stairs, parts=parts))
    return tuple(out)
