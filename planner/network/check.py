"""The accuracy check of a plan: station network, a priori adjustment, point errors of every wall piece
(:mod:`planner.network.pieces` gives the point error's formula and the pass rule)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import networkx as nx
import numpy as np

from planner.core.checks import argument
from planner.core.errors import InputError
from planner.coverage.matrix import CoverageProblem
from planner.coverage.relation import Registration
from planner.coverage.sight import Sight, as_sight
from planner.instrument.models import TotalStation, load_instrument
from planner.network.adjustment import ELLIPSE_95, Adjustment, Obs, adjust, relative
from planner.network.chain import registration_sigma_m
from planner.network.graph import Diagnostics, diagnostics, propose_control, station_network
from planner.network.heights import HeightObs, adjust_heights, dh_sigma_m
from planner.network.montecarlo import MonteCarlo, monte_carlo
from planner.network.pieces import accuracy_check
from planner.network.summary import network_summary
from planner.network.survey import SurveyNetwork, registration_links, survey_network
from planner.network.traverse import (
    ControlTraverse,
    check_traverse_names,
    datum,
    propose_area_control,
    propose_traverse,
    survey_graph,
    tie_sigma_to,
)
from planner.site.candidate import Candidate, check_unique_ids, stations_argument
from planner.site.model import ControlPoint, Site

__all__ = ["NetworkReport", "accuracy_check", "registration_sigma_m", "run_network"]
#: the edge kinds the total station observes (direction and distance)
TS_KINDS = frozenset({"sight", "delaunay", "traverse"})


def _distance_sigma_m(ts: TotalStation, length_m: float) -> float:
    return ts.prism_sigma_const_m + ts.prism_sigma_ppm * length_m / 1e6


@dataclass(frozen=True, kw_only=True)
class NetworkReport:
    graph: nx.Graph
    control: tuple[ControlPoint, ...]
    diagnostics: Diagnostics
    adjustments: tuple[Adjustment, ...]
    failures: tuple[str, ...]  # parts that could not be adjusted, with the reason
    station_sigma_m: dict[str, float]  # adjusted position error per station (m)
    check: dict[str, Any]
    monte_carlo: tuple[MonteCarlo, ...] = field(default=())
    notes: tuple[str, ...] = ()
    sigma_h_m: dict[str, float] = field(default_factory=dict)  # height error per station, where heights are given
    survey: SurveyNetwork | None = None  # the network as a scanner survey: registration links, ties, chain accuracy

    @property
    def network_rms_m(self) -> float:
        vals = list(self.station_sigma_m.values())
        return math.sqrt(float(np.mean(np.square(vals)))) if vals else float("nan")

    def to_dict(self) -> dict[str, Any]:
        g = self.graph
        ellipses = {
            p.name: {
                "x": p.x,
                "y": p.y,
                "sigma_x_m": p.sigma_x,
                "sigma_y_m": p.sigma_y,
                "position_error_m": p.position_error,
                "ellipse_a_m": p.ellipse_a,
                "ellipse_b_m": p.ellipse_b,
                "ellipse_azimuth_deg": p.ellipse_azimuth_deg,
                "ellipse95_a_m": p.ellipse_a * ELLIPSE_95,
                "ellipse95_b_m": p.ellipse_b * ELLIPSE_95,
            }
            for adj in self.adjustments
            for p in adj.points
        }
        for name, sh in self.sigma_h_m.items():
            if name in ellipses:
                e = ellipses[name]
                e["sigma_h_m"] = sh
                e["point_error_3d_m"] = math.sqrt(e["position_error_m"] ** 2 + sh**2)  # m_P of seed 003
        return {
            "nodes": [{"id": n, **d} for n, d in g.nodes(data=True)],
            "edges": [
                {"from": u, "to": v, "kinds": sorted(d["kinds"]), "length_m": d["length_m"]}
                for u, v, d in g.edges(data=True)
            ],
            "control": [{"name": c.name, "x": c.x, "y": c.y, "proposed": c.proposed} for c in self.control],
            "diagnostics": asdict(self.diagnostics),
            "stations": ellipses,
            "network_rms_m": self.network_rms_m,
            "adjustments": [
                {
                    "dof": a.dof,
                    "m0": a.m0,
                    "chi2_p": a.chi2_p,
                    "chi2_pass": a.chi2_pass,
                    "observations": len(a.observations),
                    "unknowns": len(a.observations) - a.dof,
                    "unchecked_observations": len(a.unchecked()),
                }
                for a in self.adjustments
            ],
            "failures": list(self.failures),
            "notes": list(self.notes),
            "monte_carlo": [{"runs": m.runs, "rms_m": m.rms, "spread_m": m.spread} for m in self.monte_carlo],
            "accuracy_check": self.check,
            "survey": None if self.survey is None else self.survey.to_dict(),
        }

    def _repr_html_(self) -> str:
        from planner.core.text import summary_html

        return summary_html(self, "Network and accuracy check")

    def summary(self) -> str:
        """The network check for the terminal (:func:`planner.network.summary.network_summary`)."""
        return network_summary(self)


def _heights(g: nx.Graph, ts: TotalStation, control: Sequence[ControlPoint], notes: list[str]) -> dict[str, float]:
    """Station height errors by trigonometric levelling along the total-station lines, and through ties and
    registration links (their sigmas in height too), in every part that holds a control point with a
    height (the 1-D part of the adjustment)."""
    known = {c.name: c.z for c in control if c.z is not None and c.name in g}
    out: dict[str, float] = {}
    if not known:
        notes.append("no control point has a height: plan (2-D) adjustment only")
        return out
    for comp in (sorted(c) for c in nx.connected_components(g)):  # a fixed order: the same numbers every run
        fixed = {n: known[n] for n in comp if n in known}
        if not fixed:
            continue
        base = float(np.mean(list(fixed.values())))
        obs = []
        for u, v, d in g.subgraph(comp).edges(data=True):
            if d["kinds"] & TS_KINDS:
                sd = _distance_sigma_m(ts, d["length_m"])
                obs.append(HeightObs(u, v, 0.0, dh_sigma_m(d["length_m"], 90.0, sd, ts.angle_sigma_arcsec)))
            elif "tie" in d["kinds"]:  # the station's targets on the control point give its height too
                obs.append(HeightObs(u, v, 0.0, tie_sigma_to(d["length_m"])))
            elif "registration" in d["kinds"]:
                obs.append(HeightObs(u, v, 0.0, registration_sigma_m(d["length_m"])))
        approx = {n: base for n in comp if n not in fixed}
        try:
            res = adjust_heights(approx, fixed, obs)
        except InputError as exc:
            notes.append(f"heights of {', '.join(sorted(approx))}: {exc.message}")
            continue
        out.update({n: s for n, s in res.sigma_m.items() if g.nodes[n]["kind"] == "station"})
    return out


def _design_observations(
    g: nx.Graph, ts: TotalStation, control: Sequence[ControlPoint], fixed: list[str] | None = None
) -> tuple[dict[str, tuple[float, float]], list[str], list[Obs]]:
    coords = {n: (d["x"], d["y"]) for n, d in g.nodes(data=True)}
    if fixed is None:
        fixed = [c.name for c in control if c.sigma_x_m == 0 and c.sigma_y_m == 0]
    obs: list[Obs] = []
    sb = ts.angle_sigma_arcsec / 3600.0
    for u, v, d in g.edges(data=True):
        if d["kinds"] & TS_KINDS:
            for a, b in ((u, v), (v, u)):
                if g.nodes[a]["kind"] != "station" and "traverse" not in d["kinds"]:
                    continue  # the total station stands on the scanner stations (on both ends of a traverse leg)
                az = math.degrees(math.atan2(coords[b][1] - coords[a][1], coords[b][0] - coords[a][0]))
                obs.append(Obs("direction", a, b, az, sb))
                obs.append(Obs("distance", a, b, d["length_m"], _distance_sigma_m(ts, d["length_m"])))
        for kind, sigma_of in (("registration", registration_sigma_m), ("tie", tie_sigma_to)):
            if kind in d["kinds"]:
                obs += relative(u, v, coords, sigma_of(d["length_m"]))
    for c in control:
        if c.name in coords and c.name not in fixed and c.sigma_x_m > 0 and c.sigma_y_m > 0:
            obs.append(Obs("x", c.name, None, c.x, c.sigma_x_m))
            obs.append(Obs("y", c.name, None, c.y, c.sigma_y_m))
    return coords, fixed, obs


def run_network(
    site: Site | Sight,
    stations: Sequence[Candidate],
    *,
    total_station: str = "topcon-os-105",
    control: Sequence[ControlPoint] | None = None,
    monte_carlo_runs: int = 0,
    seed: int = 0,
    target_spacing_m: float = 1.0,
    registration: Registration | str | None = None,
    precision: str = "single",
    traverse: ControlTraverse | None = None,
    ts_everywhere: bool = False,
    coverage: CoverageProblem | None = None,
) -> NetworkReport:
    """Build the network of a plan, adjust it a priori, and check the accuracy of every covered piece.

    ``registration``: the plan's (:attr:`planner.plan.problem.Problem.registration`), or a mode, ``zone`` or ``site``
    (None: the site's default), at the site's overlap share; the report also holds the network as a scanner survey
    (:mod:`planner.network.survey`). ``site``: the plan's sight (its resolved problem's), or a site, then seen under its
    own parameters with ``precision``: ``single`` judges each piece by its best view, ``combined`` by all its views (a
    sight carries its own precision mode). ``traverse``: the planned control traverse (default: proposed,
    :mod:`planner.network.traverse`); the total station observes its legs only, stations are held by registration links
    and ties.
    ``ts_everywhere``: a total station on every station sight line instead (:mod:`planner.network.graph`).
    ``coverage``: the stations' coverage on pieces of ``target_spacing_m`` under ``site``'s sight, where built
    already (:attr:`planner.plan.Plan.stations_cover`, rows in the order of ``stations``); None: built here.
    """
    argument(site, (Site, Sight), "site")
    stations_argument(stations)
    if precision not in ("single", "combined"):
        raise InputError("must be single or combined", field="precision", value=precision)
    if not stations:
        raise InputError("a network needs at least one station", field="stations", value=0)
    check_unique_ids(stations)
    ts = load_instrument(total_station)
    if not isinstance(ts, TotalStation):
        raise InputError("is not a total station", field="total_station", value=total_station)
    sight = as_sight(site, combined=precision == "combined")
    site = sight.site
    if coverage is not None and len(coverage.candidates) != len(stations):
        raise ValueError(f"a coverage of {len(coverage.candidates)} rows for {len(stations)} stations")
    problem = sight.of_stations(stations, target_spacing_m) if coverage is None else coverage
    # registration links within each zone-side, or across the site's accessible areas (through openings)
    links = registration_links(sight, stations, registration, problem)
    notes: list[str] = []
    g, ctrl, fixed_names = _network(
        site, stations, list(control or site.control_points), links, ts, traverse, ts_everywhere, notes
    )
    coords, fixed, obs = _design_observations(g, ts, ctrl, fixed_names)
    adjustments, failures, sigma, mcs = _adjust_parts(g, coords, fixed, obs, monte_carlo_runs, seed)
    sigma_h_m = _heights(g, ts, ctrl, notes)
    return NetworkReport(
        graph=g,
        control=tuple(ctrl),
        diagnostics=diagnostics(g),
        adjustments=tuple(adjustments),
        failures=tuple(failures),
        station_sigma_m=sigma,
        check=accuracy_check(site, stations, problem, sigma, sight.scanner, sight.combined),
        monte_carlo=tuple(mcs),
        notes=tuple(notes),
        sigma_h_m=sigma_h_m,
        survey=survey_network(site, stations, registration, links),
    )


def _network(
    site: Site,
    stations: Sequence[Candidate],
    ctrl: list[ControlPoint],
    links: Sequence[tuple[str, str]],
    ts: TotalStation,
    traverse: ControlTraverse | None,
    ts_everywhere: bool,
    notes: list[str],
) -> tuple[nx.Graph, list[ControlPoint], list[str] | None]:
    """The network graph, its control points (given or proposed, traverse points included) and the points
    held fixed (None: the control points without sigmas)."""
    ts_range_m = ts.max_range_prism_m or 1000.0
    if ts_everywhere:
        g = station_network(site, stations, ctrl, links, ts_range_m)
        if not ctrl:
            ctrl = propose_control(site, stations, g, notes)
            g = station_network(site, stations, ctrl, links, ts_range_m)
        return g, ctrl, None
    if not ctrl:  # per registration part (one accessible area in site mode), and next to untied stations
        ctrl = propose_area_control(site, stations, links, notes)
    if traverse is not None:
        check_traverse_names(traverse, ctrl)
    trav = traverse if traverse is not None else propose_traverse(site, ctrl, ts_range_m)
    g = survey_graph(site, stations, ctrl, trav, links)
    fixed_names, datum_notes = datum(g, ctrl)
    notes += trav.lines() + datum_notes
    return g, ctrl + list(trav.points), fixed_names


def _adjust_parts(
    g: nx.Graph,
    coords: dict[str, tuple[float, float]],
    fixed: list[str],
    obs: list[Obs],
    monte_carlo_runs: int,
    seed: int,
) -> tuple[list[Adjustment], list[str], dict[str, float], list[MonteCarlo]]:
    """Each connected part holding a station adjusted on its own: the adjustments, the parts that failed (with
    the reason), each station's position error (m) and the Monte Carlo runs."""
    adjustments, failures, sigma, mcs = [], [], {}, []
    parts = list(nx.connected_components(g))
    part_of = {n: k for k, comp in enumerate(parts) for n in comp}
    obs_of: list[list[Obs]] = [[] for _ in parts]
    for o in obs:  # each part's observations, in their order
        obs_of[part_of[o.at]].append(o)
    for comp, comp_obs in zip(parts, obs_of):
        comp_fixed = [f for f in fixed if f in comp]
        names = {n: coords[n] for n in sorted(comp)}  # a fixed order of the unknowns (not set order)
        if not any(g.nodes[n]["kind"] == "station" for n in comp):
            continue
        try:
            adj = adjust(names, comp_fixed, comp_obs, angle_unit="deg")
        except InputError as exc:
            failures.append(f"{', '.join(sorted(comp))}: {exc.message}")
            continue
        adjustments.append(adj)
        sigma.update({p.name: p.position_error for p in adj.points if g.nodes[p.name]["kind"] == "station"})
        if monte_carlo_runs:
            mcs.append(monte_carlo(names, comp_fixed, comp_obs, runs=monte_carlo_runs, seed=seed, angle_unit="deg"))
    return adjustments, failures, sigma, mcs
