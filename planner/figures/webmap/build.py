"""Fill a :class:`~planner.figures.webmap.model.SiteMap` from a site, its stations, their coverage and a field sheet:
:func:`site_map_data`, with :func:`wall_lines`, :func:`coverage_runs` and :func:`field_layers`.

Coverage is drawn as runs, not pieces: consecutive pieces one station covers on one wall face (no opening between them)
become one segment, so a 100-station plan over thousands of pieces draws a few runs per station and wall, never one
element per piece per station. The field sheet comes as its ``field.json`` dictionary
(:func:`planner.field.record.to_dict`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from planner.coverage.matrix import CoverageProblem
from planner.coverage.overlap import piece_lengths
from planner.coverage.targets import SIDE_NAME, Targets
from planner.figures.webmap.model import MapArea, MapLine, MapLink, MapPoint, MapStation, Point, Run, SiteMap
from planner.plan.plan_dict import StationNumbering
from planner.site.candidate import Candidate
from planner.site.model import SITE_FRAME, Site

#: two pieces join into one run where the first ends within this of where the second starts (m)
JOIN_M = 1e-6
#: the tooltip of a route leg through a wall adds this
THROUGH_NOTE = ": a straight line through a wall (no opening in the model)"


def _pt(p: Any) -> Point:
    return float(p[0]), float(p[1])


def wall_lines(site: Site) -> tuple[MapLine, ...]:
    """Every zone ring (outline and holes) and opening in its zone's frame; obstacles, no-go areas and the boundary in
    the site frame (where the figures draw them too)."""
    out: list[MapLine] = []
    for z in site.zones:
        for k, ring in enumerate(z.rings):
            name = z.id if k == 0 else f"{z.id} hole {k}"
            label = f"{name} ({z.scan_side.value})"
            out.append(MapLine(f"{z.id}#{k}", z.frame, "wall", tuple(map(_pt, ring)), True, label))
        walls = z.walls
        for op in z.openings:
            w = walls[op.wall - 1]
            (x0, y0), (x1, y1) = w.start, w.end
            f0, f1 = op.s0_m / w.length_m, min(op.s1_m / w.length_m, 1.0)
            pts = ((x0 + f0 * (x1 - x0), y0 + f0 * (y1 - y0)), (x0 + f1 * (x1 - x0), y0 + f1 * (y1 - y0)))
            name = op.name or f"{op.kind} on wall {op.wall}"
            out.append(MapLine(f"{z.id}/{name}", z.frame, "opening", pts, False, f"{z.id}: {name}"))
    for ob in site.obstacles:
        out.append(MapLine(ob.name, SITE_FRAME, "obstacle", tuple(map(_pt, ob.vertices)), True, f"obstacle {ob.name}"))
    for a in site.no_go_areas:
        out.append(MapLine(a.name, SITE_FRAME, "nogo", tuple(map(_pt, a.vertices)), True, f"no-go area {a.name}"))
    if site.boundary is not None:
        out.append(MapLine("boundary", SITE_FRAME, "boundary", tuple(map(_pt, site.boundary)), True, "site boundary"))
    return tuple(out)


def run_ends(t: Targets, cols: NDArray[np.integer]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The first and last piece of each run of the pieces ``cols`` (target indices): a maximal sequence of pieces
    consecutive in the targets' order on the same zone, side and wall, each starting where the one before ends."""
    c = np.sort(np.asarray(cols, dtype=np.int64))
    if c.size == 0:
        return c, c
    f, g = c[:-1], c[1:]
    joins = (
        (g - f == 1)
        & (t.zone[f] == t.zone[g])
        & (t.side[f] == t.side[g])
        & (t.wall[f] == t.wall[g])
        & (np.abs(t.s1_m[f] - t.s0_m[g]) <= JOIN_M)
    )
    cut = np.flatnonzero(~joins)
    return c[np.r_[0, cut + 1]], c[np.r_[cut, c.size - 1]]


def coverage_runs(problem: CoverageProblem) -> list[tuple[Run, ...]]:
    """For each row of ``problem`` (a station), the runs of pieces it covers (:func:`run_ends`)."""
    t = problem.targets
    lengths = piece_lengths(t.s0_m, t.s1_m)
    m = problem.by_candidate
    out: list[tuple[Run, ...]] = []
    for i in range(m.shape[0]):
        firsts, lasts = run_ends(t, m.indices[m.indptr[i] : m.indptr[i + 1]])
        runs = []
        for f, la in zip(firsts.tolist(), lasts.tolist()):
            label = (
                f"{t.zone_ids[t.zone[f]]}/{SIDE_NAME[int(t.side[f])]}/wall {t.wall[f]} "
                f"{t.s0_m[f]:.2f}-{t.s1_m[la]:.2f} m"
            )
            runs.append(Run(_pt(t.a[f]), _pt(t.b[la]), la - f + 1, float(lengths[f : la + 1].sum()), label))
        out.append(tuple(runs))
    return out


def field_layers(
    sheet: Mapping[str, Any], frame_of: Mapping[str, str]
) -> tuple[tuple[MapLine, ...], MapPoint | None, tuple[MapPoint, ...], dict[str, int]]:
    """The walking route (one line per leg), its start, the registration targets and each station's place in the
    visiting order, from a field sheet's ``field.json`` dictionary.

    A leg the sheet lists under ``legs_crossing_walls`` (a straight line through a wall where the model has no opening,
    :mod:`planner.field.crossing`) is a line of kind ``through``, drawn in the route layer in its own dash.

    ``frame_of``: station id to frame; a leg is drawn in the frame of the station it walks to, a target in that of the
    first station that sees it. Stations the sheet names but ``frame_of`` lacks are left out.
    """
    order = [str(s) for s in sheet.get("order", [])]
    legs = sheet.get("legs", [])
    through = {int(c["leg"]) for c in sheet.get("legs_crossing_walls", [])}
    route = tuple(
        MapLine(
            f"leg {k}",
            frame_of[sid],
            "through" if k - 1 in through else "route",
            tuple(map(_pt, leg)),
            False,
            f"walk to {sid} (setup {k})" + (THROUGH_NOTE if k - 1 in through else ""),
        )
        for k, (sid, leg) in enumerate(zip(order, legs), 1)
        if sid in frame_of and len(leg) > 1
    )
    if sheet.get("leg_frames"):  # across storeys: each leg's stretch in each frame, the stairs between
        route = _storey_legs(order, legs, sheet["leg_frames"], through, frame_of)
    start = None
    if order and order[0] in frame_of and sheet.get("start_xy") is not None:
        start = MapPoint(
            "start", frame_of[order[0]], *_pt(sheet["start_xy"]), "start", f"start: {sheet.get('start', '')}"
        )
    targets = []
    for t in sheet.get("targets", []):
        seen = [s for s in t.get("seen_by", []) if s in frame_of]
        if seen:
            label = f"{t['id']} {t['kind']} ({t.get('where', '')}), seen by {', '.join(seen)}"
            targets.append(MapPoint(str(t["id"]), frame_of[seen[0]], float(t["x"]), float(t["y"]), t["kind"], label))
    visits = {sid: k for k, sid in enumerate(order, 1)}
    return route, start, tuple(targets), visits


def _storey_legs(
    order: list[str],
    legs: list[Any],
    leg_frames: list[Any],
    through: set[int],
    frame_of: Mapping[str, str],
) -> tuple[MapLine, ...]:
    """A field sheet across storeys: one line per stretch of a leg walked in one frame (drawn in that frame), a stair
    leg (its foot to its head) drawn in both frames it joins."""
    out = []
    for k, (sid, leg, frs) in enumerate(zip(order, legs, leg_frames), 1):
        if sid not in frame_of or len(leg) < 2:
            continue
        kind = "through" if k - 1 in through else "route"
        note = f"walk to {sid} (setup {k})" + (THROUGH_NOTE if k - 1 in through else "")
        run: list[Any] = []
        part = 0
        for t, (p, f) in enumerate(zip(leg, frs)):
            if t and frs[t - 1] != f:
                if len(run) > 1:
                    out.append(MapLine(f"leg {k}.{part}", frs[t - 1], kind, tuple(map(_pt, run)), False, note))
                part += 1
                stair = tuple(map(_pt, [leg[t - 1], p]))
                out += [
                    MapLine(f"leg {k}.{part}.{fr}", fr, kind, stair, False, note + ", stair") for fr in (frs[t - 1], f)
                ]
                part += 1
                run = []
            run.append(p)
        if len(run) > 1:
            out.append(MapLine(f"leg {k}.{part}", frs[-1], kind, tuple(map(_pt, run)), False, note))
    return tuple(out)


def site_map_data(
    site: Site,
    stations: Sequence[Candidate],
    *,
    runs: Sequence[tuple[Run, ...]] | None = None,
    links: Sequence[MapLink] = (),
    field_sheet: Mapping[str, Any] | None = None,
    control: Sequence[MapPoint] = (),
    traverse: Sequence[MapLine] = (),
    rows: Mapping[str, str] | None = None,
    areas: Sequence[tuple[MapArea, ...]] | None = None,
    numbering: StationNumbering | None = None,
) -> SiteMap:
    """The map of a site and its stations, each labelled with its number in ``numbering`` (None: its 1-based place
    in ``stations``, plan order), as every table and figure of the plan numbers it.

    ``runs`` and ``areas``: per station (same order), the wall (:func:`coverage_runs`) and the floor and ceiling it
    covers (None: no such layer); ``links``: registration links between the stations (by id); ``field_sheet``: a field
    sheet's ``field.json`` dictionary (route, start, targets, visiting order; None: no field layers); ``control``,
    ``traverse``: the network check's control points and traverse legs; ``rows``: station id to the HTML id of its row
    in the page's station table.
    """
    frame_of = {s.id: s.frame for s in stations}
    route: tuple[MapLine, ...] = ()
    start: MapPoint | None = None
    targets: tuple[MapPoint, ...] = ()
    visits: dict[str, int] = {}
    if field_sheet is not None:
        route, start, targets, visits = field_layers(field_sheet, frame_of)
    numbering = numbering or StationNumbering.plan_order(stations)
    walls = wall_lines(site)
    frames = dict.fromkeys([z.frame for z in site.zones] + [s.frame for s in stations])
    if any(w.frame == SITE_FRAME for w in walls):
        frames.setdefault(SITE_FRAME)
    return SiteMap(
        title=site.name,
        frames=tuple(frames),
        walls=walls,
        stations=_stations(stations, runs, areas, rows or {}, visits, numbering),
        links=tuple(lk for lk in links if lk.a in frame_of and lk.b in frame_of),
        route=route,
        start=start,
        targets=targets,
        control=tuple(control),
        traverse=tuple(traverse),
        numbering=numbering.legend,
        zones=tuple(z.id for z in site.zones),
        site_frame=next(iter(frames)) if len(frames) == 1 else SITE_FRAME,
    )


def _stations(
    stations: Sequence[Candidate],
    runs: Sequence[tuple[Run, ...]] | None,
    areas: Sequence[tuple[MapArea, ...]] | None,
    rows: Mapping[str, str],
    visits: Mapping[str, int],
    numbering: StationNumbering,
) -> tuple[MapStation, ...]:
    """The stations as the map shows them, each labelled with its number in ``numbering``."""
    return tuple(
        MapStation(
            s.id,
            s.frame,
            float(s.x),
            float(s.y),
            str(numbering.number(s.id)),
            s.zone,
            s.side.value,
            s.kind.value,
            rows.get(s.id, ""),
            visits.get(s.id, 0),
            tuple(runs[k - 1]) if runs is not None else (),
            tuple(areas[k - 1]) if areas is not None else (),
            numbering.number(s.id),
            numbering.label(s.id),
        )
        for k, s in enumerate(stations, 1)
    )
