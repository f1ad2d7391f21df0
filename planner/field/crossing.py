"""Legs that cross a wall: where the site model has no opening between two parts of the walkable area.

A site drawn without its doors (rooms entered in reality) splits the walkable area into parts no walk joins. The sheet
is still made: a leg between two parts is the **straight line** from one setup to the other, through whatever walls it
meets (:func:`bridge`: its length is the straight-line distance, so the order and the bound are those of walks where
they exist and of straight lines where they do not). Each such leg is listed (:class:`Crossing`: the zones whose walls
it crosses, the parts it joins), drawn dashed, and the summary says once which rooms have no opening in the model
(:func:`advice`). ``--strict-walls`` refuses such a plan instead (exit 4).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.core.errors import InfeasibleError
from planner.field.storeys import StoreyWalk
from planner.field.walking import WalkGraph
from planner.site.candidate import Candidate
from planner.site.model import ScanSide, Site

#: where openings are documented (the advice points there)
OPENINGS_DOC = "docs/site.md#2-openings-and-registration-across-the-site"
#: the name of the part of the walkable area outside every zone
OPEN_GROUND = "the open ground"


@dataclass(frozen=True)
class Crossing:
    """Leg ``leg`` of the route (an index into the sheet's legs), from ``start`` to ``end`` (station ids, or the
    start's label), a straight line of ``length_m`` through the walls of ``zones``, joining the walkable parts
    ``parts`` (see :func:`part_names`)."""

    leg: int
    setup: int | None  # the setup number the leg walks to (None: back to a start point)
    start: str
    end: str
    length_m: float
    zones: tuple[str, ...]
    parts: tuple[str, str]


def bridge(g: WalkGraph | StoreyWalk) -> NDArray[np.float64]:
    """The walking distances of ``g``, with the straight-line distance where no walk joins two points."""
    straight = np.hypot(*(g.points[:, None] - g.points[None]).transpose(2, 0, 1))
    return np.where(np.isfinite(g.dist), g.dist, straight)


def part_names(
    site: Site, g: WalkGraph | StoreyWalk, node_station: Sequence[int], stations: Sequence[Candidate]
) -> list[str]:
    """A name for the walkable part each point of ``g`` stands in: its rooms (the zones of the inside stations
    in it, in the site's order) and :data:`OPEN_GROUND` where an outside station stands in it, joined by "+";
    a part that holds only the start point is "the start"."""
    rank = {z.id: k for k, z in enumerate(site.zones)}
    members: dict[int, list[Candidate]] = {int(c): [] for c in g.component}
    for n, k in enumerate(node_station):
        if k >= 0:
            members[int(g.component[n])].append(stations[k])
    names = {}
    for comp, here in members.items():
        rooms = sorted({s.zone for s in here if s.side is ScanSide.INSIDE}, key=lambda z: rank.get(z, 0))
        ground = [OPEN_GROUND] if any(s.side is ScanSide.OUTSIDE for s in here) else []
        names[comp] = "+".join(rooms + ground) or "the start"
    return [names[int(c)] for c in g.component]


def crossings(
    site: Site,
    g: WalkGraph | StoreyWalk,
    path_nodes: Sequence[int],
    labels: Sequence[str],
    numbers: Sequence[int | None],
    parts: Sequence[str],
    first_leg: int,
) -> tuple[Crossing, ...]:
    """The legs of the route ``path_nodes`` (nodes of ``g``) that no walk joins: node n is ``labels[n]``,
    setup ``numbers[n]``, in the part ``parts[n]``; the leg from ``path_nodes[t]`` is the sheet's leg
    ``first_leg + t``, through the walls of the zones of its frame whose outline (or a block's) it crosses."""
    out = []
    for t, (a, b) in enumerate(itertools.pairwise(path_nodes)):
        if math.isfinite(g.dist[a, b]):
            continue
        pa, pb = (float(g.points[a][0]), float(g.points[a][1])), (float(g.points[b][0]), float(g.points[b][1]))
        frame, line = g.frames[a] if isinstance(g, StoreyWalk) else g.space.frame, shapely.LineString([pa, pb])
        zones = tuple(z.id for z in site.zones if z.frame == frame and line.intersects(z.polygon.boundary))
        leg = (first_leg + t, numbers[b], labels[a], labels[b], math.dist(pa, pb), zones, (parts[a], parts[b]))
        out.append(Crossing(*leg))
    return tuple(out)


def closed_parts(found: Sequence[Crossing]) -> tuple[str, ...]:
    """The walkable parts the legs through walls join, each once, in the order the route first meets them."""
    return tuple(dict.fromkeys(p for c in found for p in c.parts))


def advice(found: Sequence[Crossing]) -> str:
    """One line for the summary and the sheet: the rooms with no opening in the model between them, how many
    legs cross a wall, and what to do ("" where no leg does)."""
    if not found:
        return ""
    parts = closed_parts(found)
    rooms = [p for p in parts if OPEN_GROUND not in p.split("+")]
    ground = [p for p in parts if OPEN_GROUND in p.split("+")]
    names = ", ".join(rooms)
    if ground:
        rest = ground[0].split("+")
        with_rooms = [r for r in rest if r != OPEN_GROUND]
        names += (" and " if names else "") + OPEN_GROUND + (f" (with {', '.join(with_rooms)})" if with_rooms else "")
    return (
        f"no opening in the model between rooms {names}: {len(found)} leg(s) of the route cross a wall (a straight "
        f"line, dashed on the plan); add openings ({OPENINGS_DOC}) or check on site"
    )


def check_reach(
    site: Site,
    st: Sequence[Candidate],
    g: WalkGraph | StoreyWalk,
    node_station: list[int],
    label: str,
    plan_file: str | None,
) -> None:
    """``--strict-walls``: a station no walk joins to the start (node 0 of ``g``) is an infeasible route
    (exit 4), named with its zone and accessible area."""
    from planner.coverage.openings import accessible_areas, space_of

    for n, k in enumerate(node_station):
        if k >= 0 and not math.isfinite(g.dist[0, n]):
            s = st[k]
            area = accessible_areas(site).get(space_of(site.zone(s.zone), s.side))
            raise InfeasibleError(
                f"cannot be reached on foot from the start ({label}): it stands in zone {s.zone} "
                f"({s.side.value}), accessible area {area}, which no door or gate joins to the start's",
                file=plan_file,
                field="station",
                value=s.id,
            )
