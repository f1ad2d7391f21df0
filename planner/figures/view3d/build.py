"""Fill a :class:`~planner.figures.view3d.model.Scene3D` from a site, its stations and their coverage matrix
(:func:`scene_3d`); coverage as runs (:func:`planner.figures.webmap.build.run_ends`), each a
:class:`~planner.figures.view3d.model.Covered` the renderer draws as one quad on its wall.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from planner.coverage.matrix import CoverageProblem
from planner.coverage.targets import Targets
from planner.figures.view3d.model import Covered, Scene3D, Station3D, Surface, View, WallQuad, Zone3D
from planner.figures.webmap.build import run_ends
from planner.plan.plan_dict import StationNumbering
from planner.site.candidate import Candidate
from planner.site.model import ScanSide, Site


def wall_quads(site: Site) -> tuple[WallQuad, ...]:
    """Every wall of every zone (outline, then holes) as a quad from its zone's floor to its top edge."""
    out = []
    for k, z in enumerate(site.zones):
        f = z.floor_level_m
        for w in z.walls:
            a, b = (float(w.start[0]), float(w.start[1])), (float(w.end[0]), float(w.end[1]))
            out.append(WallQuad(k, w.index, a, b, f, f + w.h_start_m, f + w.h_end_m))
    return tuple(out)


def surfaces(site: Site) -> tuple[Surface, ...]:
    """The floor of every zone scanned inside (its outline and holes at its floor level) and its ceiling where it has
    one (at the floor level plus the ceiling height). A zone scanned from outside only has neither."""
    out = []
    for k, z in enumerate(site.zones):
        if z.scan_side is ScanSide.OUTSIDE:
            continue
        rings = tuple(tuple((float(x), float(y)) for x, y in r) for r in z.rings)
        out.append(Surface(k, "floor", z.floor_level_m, rings))
        if z.ceiling_height_m is not None:
            out.append(Surface(k, "ceiling", z.floor_level_m + z.ceiling_height_m, rings))
    return tuple(out)


def covered_runs(
    targets: Targets, cols: NDArray[np.integer], wall_at: Mapping[tuple[int, int], int]
) -> tuple[Covered, ...]:
    """The runs of the pieces ``cols`` (target indices, :func:`planner.figures.webmap.build.run_ends`); ``wall_at``:
    (zone index, 1-based wall) to the scene's wall index."""
    t = targets
    firsts, lasts = run_ends(t, cols)
    return tuple(
        Covered(wall_at[(int(t.zone[a]), int(t.wall[a]))], float(t.s0_m[a]), float(t.s1_m[b]), int(b - a + 1))
        for a, b in zip(firsts.tolist(), lasts.tolist())
    )


def views(site: Site, stations: Sequence[Candidate]) -> tuple[View, ...]:
    """The storey filter's choices.

    One frame: everything, then each floor level where there are several. Several frames that are the storeys of one
    building (each frame's zones on one floor level, a different level per frame: an IFC model read with ``--storey
    all``): all storeys, then each frame from the lowest. Other frames (table zones, each in its own local frame, which
    do not share coordinates): each frame on its own, the one with most stations first.
    """
    zones = site.zones
    frames = list(dict.fromkeys(z.frame for z in zones))
    by_frame = {f: tuple(k for k, z in enumerate(zones) if z.frame == f) for f in frames}
    levels = {f: {zones[k].floor_level_m for k in ks} for f, ks in by_frame.items()}
    if len(frames) == 1:
        lv = sorted(levels[frames[0]])
        out = [View("all", tuple(range(len(zones))))]
        if len(lv) > 1:
            out += [View(f"level {v:g} m", tuple(k for k, z in enumerate(zones) if z.floor_level_m == v)) for v in lv]
        return tuple(out)
    single = [next(iter(v)) for v in levels.values() if len(v) == 1]
    if len(single) == len(frames) and len(set(single)) == len(frames):
        ordered = sorted(frames, key=lambda f: next(iter(levels[f])))
        first = View("all storeys", tuple(range(len(zones))))
        return (first, *(View(f"{f} ({next(iter(levels[f])):g} m)", by_frame[f]) for f in ordered))
    per = Counter(s.frame for s in stations)
    ordered = sorted(frames, key=lambda f: -per.get(f, 0))  # stable: ties keep the site's order
    return tuple(View(f, by_frame[f]) for f in ordered)


def scene_3d(
    site: Site,
    stations: Sequence[Candidate],
    problem: CoverageProblem | None = None,
    instrument_height_m: float | None = None,
    numbering: StationNumbering | None = None,
) -> Scene3D:
    """The 3-D scene of a site and its stations.

    ``problem``: the stations' coverage problem (its rows in the order of ``stations``: each station's covered runs;
    None: no coverage shown); ``instrument_height_m``: the height above its floor each station is drawn at (None: the
    site's ``instrument_height_m``). Stations are labelled with their numbers in ``numbering`` (None: their 1-based
    place in ``stations``, plan order).
    """
    ih = site.parameters.instrument_height_m if instrument_height_m is None else float(instrument_height_m)
    numbering = numbering or StationNumbering.plan_order(stations)
    walls = wall_quads(site)
    wall_at = {(w.zone, w.wall): i for i, w in enumerate(walls)}
    zone_at = {z.id: k for k, z in enumerate(site.zones)}
    per: list[tuple[Covered, ...]] = [()] * len(stations)
    union: tuple[Covered, ...] = ()
    if problem is not None:
        m = problem.by_candidate
        for i in range(len(stations)):
            per[i] = covered_runs(problem.targets, m.indices[m.indptr[i] : m.indptr[i + 1]], wall_at)
        union = covered_runs(problem.targets, np.unique(m.indices[: m.indptr[len(stations)]]), wall_at)
    st = []
    for k, s in enumerate(stations):
        zi = zone_at.get(s.zone, 0)
        floor = site.zones[zi].floor_level_m
        st.append(Station3D(s.id, str(numbering.number(s.id)), zi, float(s.x), float(s.y), floor, floor + ih, per[k]))
    zones = tuple(Zone3D(z.id, z.frame, z.scan_side.value, z.floor_level_m) for z in site.zones)
    return Scene3D(
        title=site.name,
        zones=zones,
        walls=walls,
        surfaces=surfaces(site),
        stations=tuple(st),
        views=views(site, stations),
        covered=union,
        instrument_height_m=ih,
    )
