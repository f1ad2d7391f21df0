"""The field sheet's content for a plan: the start, the walking distances, the order with its lower bound, the
registration targets and the field time (:func:`field_plan`); :mod:`planner.field.sheet` writes it.

Errors (one line each): a station that does not stand where its zone and side say, or stands in no walkable place, is a
plan that does not match the site (:class:`~planner.core.errors.InputError`, exit 3); a ``--start`` that names no
station and no point of the walkable area is a usage error (exit 2); a station that no walk joins to the start is
reached by a straight leg through the walls, listed on the sheet (:mod:`planner.field.crossing`), or, with
``strict_walls``, an infeasible route (exit 4), named with its zone and accessible area.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import networkx as nx
import numpy as np
import shapely

from planner.core.errors import InfeasibleError, InputError, UsageError
from planner.coverage.matrix import CoverageProblem
from planner.coverage.relation import Registration
from planner.coverage.sight import Sight, as_sight
from planner.field.certify import Certified, certify
from planner.field.crossing import Crossing, bridge, check_reach, crossings, part_names
from planner.field.order import MODES, SOLUTION_LIMIT, TIME_CAP_S, registration_violations, solve_order
from planner.field.scip_order import NODE_LIMIT
from planner.field.storeys import Flight, StoreyWalk, joined_frames, storey_spaces, storey_walks
from planner.field.targets import STRONG_OVERLAP, Link, Target, propose_targets
from planner.field.timing import FieldTime, field_time
from planner.field.walking import SNAP_M, WalkGraph, WalkSpace, snap_distance, walk_graph, walk_space
from planner.instrument.field_table import FieldProperties
from planner.plan.hours.field_time import field_properties
from planner.plan.plan_dict import StationNumbering
from planner.plan.problem import Problem
from planner.site.candidate import Candidate
from planner.site.model import ScanSide, Site


@dataclass(frozen=True, kw_only=True)
class FieldOptions:
    """How the sheet is made: ``mode`` shortest|registration, ``start`` (a station id, ``x,y``, or None for
    the station nearest the first door or control point), ``closed`` (back to the start), ``session_s``,
    the scan ``setting`` (None: the instrument's default), ``strong_overlap``, the routing's ``solution_limit``
    and the branch-and-cut's ``node_limit`` (counts: the same sheet under any load), ``time_cap_s``, a
    wall-clock cap on both only where the user sets one (None: none), and ``strict_walls``: refuse a plan
    whose stations no walk joins (exit 4) instead of crossing walls (:mod:`planner.field.crossing`)."""

    mode: str = "shortest"
    start: str | None = None
    closed: bool = False
    session_s: float | None = None
    setting: str | None = None
    strong_overlap: float = STRONG_OVERLAP
    solution_limit: int = SOLUTION_LIMIT
    time_cap_s: float | None = TIME_CAP_S
    node_limit: int = NODE_LIMIT
    strict_walls: bool = False

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise UsageError(f"unknown order mode (known: {', '.join(MODES)})", field="--mode", value=self.mode)
        if not (0.0 <= self.strong_overlap <= 1.0):
            raise UsageError("must be a fraction in [0, 1]", field="--strong-overlap", value=self.strong_overlap)
        if self.session_s is not None and not (math.isfinite(self.session_s) and self.session_s > 0):
            raise UsageError("must be a duration > 0", field="--session", value=self.session_s)
        if self.time_cap_s is not None and not (math.isfinite(self.time_cap_s) and self.time_cap_s > 0):
            raise UsageError("must be a number of seconds > 0", field="--time-limit", value=self.time_cap_s)


@dataclass(frozen=True, eq=False, kw_only=True)
class FieldPlan:
    """Everything the sheet shows; ``order`` holds indices into ``stations`` in visiting order."""

    site: Site
    stations: tuple[Candidate, ...]
    order: tuple[int, ...]
    start_xy: tuple[float, float]
    start_label: str
    legs: tuple[tuple[tuple[float, float], ...], ...]  # leg k: the walk to the k-th station of the order
    route_length_m: float
    lower_bound_m: float
    bound_method: str
    nearest_neighbour_m: float
    options: FieldOptions
    time: FieldTime
    links: tuple[Link, ...]
    targets: tuple[Target, ...]
    space: WalkSpace
    instrument_height_m: float
    capped: bool
    registration_ok: bool
    solve_s: float = field(default=0.0)
    certified: Certified | None = field(default=None)
    crossings: tuple[Crossing, ...] = field(default=())  # legs through walls (no opening in the model)
    coverage: CoverageProblem | None = field(default=None)  # the stations' wall pieces, rows in ``stations`` order
    pairs: tuple[tuple[str, str], ...] = field(default=())  # the plan's registration relation (station ids)
    # across storeys (stations in several frames joined by stairs; all empty for one frame):
    spaces: tuple[WalkSpace, ...] = field(default=())  # every frame walked through (``space`` is the first's)
    leg_frames: tuple[tuple[str, ...], ...] = field(default=())  # the frame of each point of each leg
    stair_legs: tuple[tuple[int, Flight], ...] = field(default=())  # (leg index, the flight it climbs or descends)

    @property
    def gap(self) -> float:
        """(route - bound) / route, 0 for an empty route."""
        r = self.route_length_m
        return max(0.0, (r - self.lower_bound_m) / r) if r > 0 else 0.0

    @property
    def numbering(self) -> StationNumbering:
        """Each station's one number and label: walking order (this sheet's visiting order), which plan.json, the
        report and the exports of the same plan record and show too."""
        return StationNumbering.walking(self.stations, [self.stations[k].id for k in self.order])

    def targets_of(self, station_id: str) -> list[str]:
        return [t.id for t in self.targets if station_id in t.seen_by]


def _check_stands(
    site: Site, stations: Sequence[Candidate], spaces: dict[str, WalkSpace], plan_file: str | None
) -> None:
    zones = {z.id: z for z in site.zones}
    for k, s in enumerate(stations, 1):
        polygon, off = zones[s.zone].polygon, snap_distance(spaces[s.frame], s.xy)
        why = ""
        if s.side is ScanSide.INSIDE and not polygon.buffer(1e-6).covers(shapely.Point(s.xy)):
            why = f"stands outside zone {s.zone}, which it scans from inside"
        elif s.side is ScanSide.OUTSIDE and polygon.buffer(-1e-6).contains(shapely.Point(s.xy)):
            why = f"stands inside zone {s.zone}, which it scans from outside"
        elif off > SNAP_M:
            why = (
                f"stands {off:.2f} m from any walkable place (in an obstacle, a no-go area, a wall or outside the site "
                "boundary)"
            )
        if why:
            where = {"file": plan_file, "row": f"stations[{k}]", "field": "station", "value": s.id}
            raise InputError(f"{why}: the plan does not match the site", **where)  # type: ignore[arg-type]


def _start(
    site: Site,
    stations: Sequence[Candidate],
    space: WalkSpace,
    start: str | None,
    walks: Callable[[list[tuple[float, float]]], np.ndarray] | None = None,
) -> tuple[int | None, tuple[float, float], str]:
    """(station index or None, start point, label). ``space``: the first station's frame's walkable area (where a
    start point and the first door lie); ``walks``: the distance matrix of the stations and a point of that
    frame, last (None: walks in ``space``)."""
    ids = [s.id for s in stations]
    if start is not None:
        if start in ids:
            k = ids.index(start)
            return k, stations[k].xy, f"station {start}"
        try:
            x, y = (float(v) for v in start.split(","))
        except ValueError:
            raise UsageError("names no station of the plan and is no point x,y", field="--start", value=start) from None
        if not (math.isfinite(x) and math.isfinite(y)) or snap_distance(space, (x, y)) > SNAP_M:
            raise UsageError(
                "lies outside the walkable area of the site (outside the boundary, in a wall, an obstacle "
                "or a no-go area)",
                field="--start",
                value=start,
            )
        return None, (x, y), f"point {x:g}, {y:g}"
    from planner.coverage.openings import PASSABLE, opening_segments

    doors = [ends for _zi, _z, kind, ends in opening_segments(site, space.frame) if kind in PASSABLE]
    controls = [c for c in site.control_points if c.frame == space.frame]
    anchor: tuple[tuple[float, float], str] | None = None
    if doors:
        mid = doors[0].mean(axis=0)
        anchor = ((float(mid[0]), float(mid[1])), "the first door")
    elif controls:
        anchor = ((controls[0].x, controls[0].y), f"control point {controls[0].name}")
    if anchor is None:
        return 0, stations[0].xy, f"station {ids[0]} (the plan's first)"
    pts = [*(s.xy for s in stations), anchor[0]]
    dist = walk_graph(space, pts).dist if walks is None else walks(pts)
    k = int(np.argmin(dist[-1, :-1]))
    return k, stations[k].xy, f"station {ids[k]} (nearest {anchor[1]})"


def field_plan(
    site: Problem | Site | Sight,
    stations: Sequence[Candidate],
    options: FieldOptions = FieldOptions(),
    props: FieldProperties | None = None,
    plan_file: str | None = None,
    settings: Sequence[str] | None = None,
) -> FieldPlan:
    """Order, route, bound, targets and field time of a plan's ``stations`` (see the module text). ``site``: the
    plan's problem (its sight and registration: the sheet relates the plan's pairs), else a site or sight
    registered at its defaults. ``settings``: each station's scan setting; None: all at ``options.setting``."""
    t0 = time.perf_counter()
    sight = site.sight if isinstance(site, Problem) else as_sight(site)
    registration = site.registration if isinstance(site, Problem) else Registration.of(sight)
    site, st = sight.site, tuple(stations)
    walk = _walk(site, st, plan_file)
    first, start_xy, label = _start(site, st, walk.space, options.start, walk.walks)
    if walk.joined is not None and first is None:
        label += f" ({walk.frame})"  # a point start stands on the storey of the plan's first station
    # nodes: the start first (a station or a point), then the other stations
    node_station = ([first] if first is not None else [-1]) + [k for k in range(len(st)) if k != first]
    g = walk.graph(site, [start_xy if k < 0 else st[k].xy for k in node_station], [s.frame for s in st], node_station)
    if options.strict_walls:
        check_reach(site, st, g, node_station, label, plan_file)
    problem = sight.of_stations(st)
    rel = registration.relation(st, problem)
    at_station = first is not None
    d = bridge(g)  # a straight line through the walls where no walk joins two stations
    cert, ok = _order(d, rel, node_station, at_station, options)
    result = cert.result  # the order the bound certifies
    order = tuple(node_station[n] for n in result.order if node_station[n] >= 0)
    path_nodes = list(result.order) + ([0] if options.closed else [])
    legs, leg_frames, stair_legs = _legs(g, path_nodes, st, first)
    numbers = {n: order.index(k) + 1 for n, k in enumerate(node_station) if k >= 0}
    names = [label if k < 0 else st[k].id for k in node_station]
    parts = part_names(site, g, node_station, st)
    through = crossings(
        site, g, path_nodes, names, [numbers.get(n) for n in range(len(node_station))], parts, int(at_station)
    )
    props = props or field_properties(site)
    reg_order, spaces = order if options.mode == "registration" else None, None if walk.joined is None else walk.spaces
    links, targets = propose_targets(
        site, st, walk.space, props, rel, problem, reg_order, options.strong_overlap, spaces
    )
    if walk.joined is None:
        walked = [sum(math.dist(p, q) for p, q in itertools.pairwise(leg)) for leg in legs][: len(order)]
    else:  # a flight counts its run and its rise: the distances the order was made on
        walked = ([0.0] * at_station + [float(d[a, b]) for a, b in itertools.pairwise(path_nodes)])[: len(order)]
    counts = [sum(1 for t in targets if st[k].id in t.seen_by) for k in order]
    per = None if settings is None else {s.id: v for s, v in zip(st, settings)}
    ft = field_time([st[k].id for k in order], walked, counts, props, options.setting, options.session_s, per)
    return FieldPlan(
        site=site,
        stations=st,
        order=order,
        start_xy=start_xy,
        start_label=label,
        legs=legs,
        route_length_m=result.length_m,
        lower_bound_m=cert.bound_m,
        bound_method=cert.method,
        nearest_neighbour_m=result.nearest_neighbour_m,
        options=options,
        time=ft,
        links=tuple(links),
        targets=tuple(targets),
        space=walk.space,
        instrument_height_m=site.parameters.instrument_height_m,
        capped=result.capped,
        registration_ok=ok,
        solve_s=time.perf_counter() - t0,
        certified=cert,
        crossings=through,
        coverage=problem,
        pairs=tuple((st[u].id, st[v].id) for u, v in rel.edges()),
        spaces=() if walk.joined is None else tuple(walk.spaces.values()),
        leg_frames=leg_frames,
        stair_legs=tuple(stair_legs),
    )


def _order(
    d: np.ndarray, rel: nx.Graph, node_station: list[int], at_station: bool, options: FieldOptions
) -> tuple[Certified, bool]:
    """The visiting order on the walking distances ``d`` (nodes: the start, then the other stations) with its
    certified lower bound, and whether it honours the registration relation ``rel`` of the stations."""
    nbrs = [set() if k < 0 else {node_station.index(u) for u in rel.neighbors(k)} for k in node_station]
    comp = {u: c for c, part in enumerate(nx.connected_components(rel)) for u in part}
    parts = [-1 if k < 0 else comp[k] for k in node_station]
    mode, closed, cap = options.mode, options.closed, options.time_cap_s
    result = solve_order(d, mode, nbrs, parts, at_station, closed, options.solution_limit, cap)
    cert = certify(d, result, mode, nbrs, parts, at_station, closed, options.node_limit, cap)
    return cert, not registration_violations(cert.result.order, nbrs, parts, at_station)


@dataclass(frozen=True)
class _Walk:
    """Where a plan's stations are walked: the first station's ``frame`` and walkable ``space``, every frame's
    ``spaces``, the frames ``joined`` by stairs (None: one frame) and, across storeys, the ``walks`` between
    points (None: in ``space``)."""

    frame: str
    space: WalkSpace
    spaces: dict[str, WalkSpace]
    joined: object | None
    walks: Callable[[list[tuple[float, float]]], np.ndarray] | None

    def graph(
        self, site: Site, xy: list[tuple[float, float]], frames: list[str], node_station: list[int]
    ) -> WalkGraph | StoreyWalk:
        """The walks between the points ``xy`` of the nodes (``node_station``: each node's station, -1 for a
        start point, which stands in the first station's frame; ``frames``: each station's)."""
        if self.joined is None:
            return walk_graph(self.space, xy)
        return storey_walks(site, self.spaces, xy, [self.frame if k < 0 else frames[k] for k in node_station])


def _walk(site: Site, st: tuple[Candidate, ...], plan_file: str | None) -> _Walk:
    """The walkable areas of the stations' frames, each station checked to stand in one, refused where the
    plan has no station or stations stand in frames no stair joins."""
    if not st:
        raise InputError(
            "the plan has no stations: there is nothing to visit", file=plan_file, field="stations", value=0
        )
    frame = st[0].frame
    frames = list(dict.fromkeys(s.frame for s in st))
    joined = joined_frames(site, frames) if len(frames) > 1 and site.stairs else None
    for s in st:
        if s.frame != frame and joined is None:
            raise InfeasibleError(
                f"stands in frame {s.frame!r}, station {st[0].id} in {frame!r}: zones in separate "
                f"frames cannot be walked between (no stair joins them; place them with planner assemble)",
                file=plan_file,
                field="station",
                value=s.id,
            )
    walks: Callable[[list[tuple[float, float]]], np.ndarray] | None = None
    if joined is None:
        spaces = {frame: walk_space(site, frame, [s.xy for s in st])}
    else:  # across storeys (planner.field.storeys): each frame's walks joined by the stairs
        spaces = storey_spaces(site, joined, st)
        frames_of = [s.frame for s in st]

        def walks(pts: list[tuple[float, float]]) -> np.ndarray:
            return storey_walks(site, spaces, pts, [*frames_of, frame][: len(pts)]).dist

    _check_stands(site, st, spaces, plan_file)
    return _Walk(frame, spaces[frame], spaces, joined, walks)


def _legs(
    g: WalkGraph | StoreyWalk, path_nodes: list[int], st: tuple[Candidate, ...], first: int | None
) -> tuple[tuple[tuple[tuple[float, float], ...], ...], tuple[tuple[str, ...], ...], list[tuple[int, Flight]]]:
    """The walk of each leg of the route (the first station's: no walk to it), across storeys also the frame
    of each point of each leg and the flights climbed or descended (leg index, flight)."""
    routes = [_route(g, a, b) for a, b in itertools.pairwise(path_nodes)]
    legs = tuple(tuple(r[0]) for r in routes)
    leg_frames: tuple[tuple[str, ...], ...] = ()
    stair_legs: list[tuple[int, Flight]] = []
    if isinstance(g, StoreyWalk):
        leg_frames = tuple(tuple(r[1]) for r in routes)
        off = 0 if first is None else 1
        stair_legs = [(t + off, f) for t, r in enumerate(routes) for f in r[2]]
        if first is not None:
            leg_frames = ((st[first].frame,),) + leg_frames
    if first is not None:
        legs = ((st[first].xy,),) + legs
    return legs, leg_frames, stair_legs


def _route(g: WalkGraph | StoreyWalk, a: int, b: int) -> tuple[list[tuple[float, float]], list[str], list[Flight]]:
    """The walk from point a to point b of ``g``, across storeys the frame of each of its points and the flights
    it takes; the straight line where no walk joins them."""
    if math.isfinite(g.dist[a, b]):
        return g.route(a, b) if isinstance(g, StoreyWalk) else (g.path(a, b), [], [])
    line = [(float(g.points[k][0]), float(g.points[k][1])) for k in (a, b)]
    return line, [g.frames[a], g.frames[b]] if isinstance(g, StoreyWalk) else [], []
