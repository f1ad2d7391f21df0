"""The control traverse of a site, and the network of a plan as surveyed: links, ties, traverse legs.

A surveyor ties every scan to one control network measured by traditional methods (seed 003), so the network of a plan
holds three kinds of measurement (docs/network.md), total-station observations only on the traverse: ``registration``
(two related stations, a relative position), ``tie`` (a station within ``TIE_RANGE_M`` of a control point it sees scans
targets set there: a relative position of sigma m_t) and ``traverse`` (a leg observed with the total station from both
ends, direction and distance).

The traverse is the user's (:func:`read_traverse`) or proposed (:func:`propose_traverse`): the control points, a point
in every door or gate, points round the outline (``RP.``) where the shortest leg paths need them, and legs between
points of one room (or of the ground outside) that see each other within range. A leg never passes through a wall: areas
that no opening joins stay separate networks.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import networkx as nx
import numpy as np
import shapely

from planner.core.checks import no_repeats
from planner.core.errors import InputError
from planner.core.fileio import known_keys, read_json, to_float
from planner.coverage.openings import PASSABLE, opening_segments
from planner.network import proposal
from planner.network.graph import add_link, point_graph, propose_control
from planner.network.survey import DEFAULT_TARGETS, _tie, can_tie
from planner.site.candidate import Candidate
from planner.site.model import SITE_FRAME, ControlPoint, ScanSide, Site


@dataclass(frozen=True)
class ControlTraverse:
    """Traverse points (beside the control points) and the legs observed with the total station."""

    points: tuple[ControlPoint, ...]
    legs: tuple[tuple[str, str], ...]
    proposed: bool
    source: str

    def lines(self) -> list[str]:
        names = {p.name for p in self.points}
        through = sum(u in names or v in names for u, v in self.legs)
        return [
            f"control traverse ({'PROPOSED' if self.proposed else 'given'}, {self.source}): {len(self.legs)} legs, "
            f"{len(self.points)} traverse point(s), {through} leg(s) at a traverse point"
        ]


NO_TRAVERSE = ControlTraverse((), (), False, "none: no total-station observations")


def read_traverse(path: str | Path) -> ControlTraverse:
    """A planned traverse: JSON ``{"points": [{name, x, y}], "legs": [[from, to], ...]}`` in the site frame; legs name
    these points or control points."""
    if str(path) == "none":
        return NO_TRAVERSE
    data = read_json(path)
    if not isinstance(data, dict) or not isinstance(data.get("legs"), list):
        raise InputError("needs an object with a list of legs", file=str(path), field="legs")
    known_keys(data, {"points", "legs"}, file=str(path), row="traverse")
    if not isinstance(data.get("points", []), list):
        raise InputError("must be a list of {name, x, y}", file=str(path), field="points", value=data["points"])
    points = []
    for k, p in enumerate(data.get("points", [])):
        where: dict[str, Any] = dict(file=str(path), row=f"points[{k + 1}]")
        if not isinstance(p, dict) or "name" not in p:
            raise InputError("a point needs name, x, y", **where, value=p)
        known_keys(p, {"name", "x", "y", "frame"}, **where)
        points.append(
            ControlPoint(
                str(p["name"]),
                to_float(p.get("x"), field="x", **where),
                to_float(p.get("y"), field="y", **where),
                frame=str(p.get("frame", SITE_FRAME)),
            )
        )
    legs = []
    for k, leg in enumerate(data["legs"], 1):
        if not (isinstance(leg, list) and len(leg) == 2 and all(isinstance(n, str) for n in leg) and leg[0] != leg[1]):
            raise InputError("a leg is [from, to], two different names", file=str(path), field=f"legs[{k}]", value=leg)
        legs.append((leg[0], leg[1]))
    no_repeats((p.name for p in points), what="traverse point name", field="name", row="points[{}]", file=str(path))
    return ControlTraverse(tuple(points), tuple(legs), False, f"from {path}")


def check_traverse_names(traverse: ControlTraverse, control: Sequence[ControlPoint]) -> None:
    """A traverse point named like a control point would merge into it (the network keys points by name)."""
    known = {c.name for c in control}
    for k, p in enumerate(traverse.points, 1):
        if p.name in known:
            raise InputError(
                "names a control point of the site: the two would merge into one network node; rename "
                "the traverse point (legs may name the control point itself)",
                file=traverse.source.removeprefix("from "),
                row=f"points[{k}]",
                field="name",
                value=p.name,
            )


def propose_traverse(site: Site, control: Sequence[ControlPoint], ts_range_m: float) -> ControlTraverse:
    """Traverse points in the doors and gates, and legs between intervisible points (see the module text)."""
    points = []
    for frame in dict.fromkeys(z.frame for z in site.zones):
        for k, (zi, w, kind, ends) in enumerate(opening_segments(site, frame)):
            if kind in PASSABLE:
                x, y = map(float, ends.mean(axis=0))
                points.append(
                    ControlPoint(f"TP.{site.zones[zi].id}.{w.index}.{k + 1}", x, y, proposed=True, frame=frame)
                )
    ring = _ring_points(site)
    nodes = list(control) + points + ring
    # a proposed leg stays in one room (or outside): spaces are joined only at the traverse points in their
    # doors, so a sight line that slips through the few-cm junction gap where two zones' walls meet
    # (planner.coverage.faces) is no leg
    legs = proposal.legs(site, nodes, ts_range_m)
    kept = proposal.needed(ring, nodes, legs)
    dropped = {r.name for r in ring} - kept
    legs = [(u, v) for u, v in legs if u not in dropped and v not in dropped]
    return ControlTraverse(
        tuple(points + [r for r in ring if r.name in kept]),
        tuple(legs),
        True,
        "control points of each area, a point in every door or gate and round the outline where "
        "needed, legs between points that see each other",
    )


#: traverse points round an outline stand this far out from its corners (on the bisector)
RING_OFFSET_M = 3.0


def _ring_points(site: Site) -> list[ControlPoint]:
    """Candidate traverse points outside each outline (a zone scanned outside), ``RING_OFFSET_M`` out from every corner
    on its bisector, where no zone is: a traverse round the building joins the ground outside."""
    out = []
    grown = [o.polygon.buffer(1.0) for o in site.zones]  # each zone and 1 m round it
    for z in site.zones:
        if z.scan_side is not ScanSide.OUTSIDE:
            continue
        xy = z.xy
        for k in range(len(xy)):
            a, b = xy[k - 1] - xy[k], xy[(k + 1) % len(xy)] - xy[k]
            bis = a / np.hypot(*a) + b / np.hypot(*b)
            if np.hypot(*bis) < 1e-9:
                continue
            for sign in (1.0, -1.0):
                p = xy[k] + sign * RING_OFFSET_M * bis / np.hypot(*bis)
                pt = shapely.Point(*p)
                if not any(o.frame == z.frame and around.contains(pt) for o, around in zip(site.zones, grown)):
                    out.append(
                        ControlPoint(f"RP.{z.id}.{k + 1}", float(p[0]), float(p[1]), proposed=True, frame=z.frame)
                    )
                    break
    return out


def propose_area_control(
    site: Site, stations: Sequence[Candidate], links: Sequence[tuple[str, str]], notes: list[str]
) -> list[ControlPoint]:
    """Control for a scanner survey: three points per registration part (one accessible area in ``site`` mode;
    :func:`planner.network.graph.propose_control`), then one more next to every station that sees none of them within
    ``TIE_RANGE_M`` (seed 003: targets 10-20 m from the station), so every station is tied. A part's points are named
    ``CP<part>.<n>``."""
    reg = nx.Graph(list(links))
    reg.add_nodes_from(s.id for s in stations)
    ctrl = propose_control(site, stations, reg, notes)
    doors = [
        ControlPoint("door", float(e.mean(axis=0)[0]), float(e.mean(axis=0)[1]), frame=f)
        for f in dict.fromkeys(z.frame for z in site.zones)
        for _, _, kind, e in opening_segments(site, f)
        if kind in PASSABLE
    ]
    by_id = {s.id: s for s in stations}
    for k, comp in enumerate(nx.connected_components(reg.subgraph([s.id for s in stations]))):
        n = sum(c.name.startswith(f"CP{k + 1}.") for c in ctrl)
        for sid in sorted(comp):
            st = by_id[sid]
            if any(can_tie(site, st.frame, st.xy, c) for c in ctrl):
                continue
            spot = proposal.best_spot(site, st, ctrl + doors)
            if spot is None:
                notes.append(f"no control spot fits next to {sid}: it is held by its registration links only")
                continue
            n += 1
            ctrl.append(ControlPoint(f"CP{k + 1}.{n}", spot[0], spot[1], proposed=True, frame=st.frame))
    return ctrl


def tie_sigma_to(distance_m: float) -> float:
    """m_t of a station scanning ``DEFAULT_TARGETS`` targets set on a control point ``distance_m`` away (the targets
    coordinated from that point; its own error is in the adjustment)."""
    return _tie(0.0, [max(distance_m, 1.0)] * DEFAULT_TARGETS)


def survey_graph(
    site: Site,
    stations: Sequence[Candidate],
    control: Sequence[ControlPoint],
    traverse: ControlTraverse,
    links: Sequence[tuple[str, str]],
) -> nx.Graph:
    """Stations, control and traverse points; edges ``registration``, ``tie`` and ``traverse`` (``kinds``,
    ``length_m``). Raises on a leg naming no point."""
    g = point_graph(stations, (*control, *traverse.points))
    for u, v in links:
        add_link(g, u, v, "registration")
    for s in stations:
        for c in control:
            if can_tie(site, s.frame, s.xy, c):
                add_link(g, s.id, c.name, "tie")
    for u, v in traverse.legs:
        for n in (u, v):
            if n not in g or g.nodes[n]["kind"] != "control":
                raise InputError("a traverse leg names no control or traverse point", field="traverse", value=n)
        add_link(g, u, v, "traverse")
    return g


def datum(g: nx.Graph, control: Sequence[ControlPoint]) -> tuple[list[str], list[str]]:
    """Points held fixed, and notes. Given control keeps its sigmas (0: fixed). Proposed control: in each network part,
    the first three proposed points of the registration part (accessible area) holding most stations are fixed; every
    other point of the network part is found through the traverse, links and ties."""
    given = [c.name for c in control if not c.proposed and c.sigma_x_m == 0 and c.sigma_y_m == 0]
    if any(not c.proposed for c in control):
        return given, []
    fixed: list[str] = []
    notes = []
    names = {c.name for c in control}
    for comp in nx.connected_components(g):
        ctrl = sorted(n for n in comp if n in names)
        if not ctrl:
            continue
        groups: dict[str, list[str]] = {}
        for c in ctrl:
            groups.setdefault(c.rsplit(".", 1)[0], []).append(c)
        served = {k: sum(1 for c in v for n in g[c] if g.nodes[n]["kind"] == "station") for k, v in groups.items()}
        best = max(sorted(groups), key=lambda k: served[k])
        held = sorted(groups[best], key=lambda c: int(c.rsplit(".", 1)[1]) if c.rsplit(".", 1)[1].isdigit() else 0)[:3]
        fixed += held
        notes.append(
            f"datum of the network part holding {', '.join(sorted(groups))}: {', '.join(held)} held fixed; "
            "its other control points are found through the traverse, links and ties"
        )
    return fixed, notes
