"""A verified plan (:class:`Plan`): the chosen stations, how they were found, their verification and summary."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from planner.core.text import fold_alike, table
from planner.coverage.fingerprint import Pool
from planner.coverage.matrix import CoverageProblem
from planner.plan.hours import Hours
from planner.plan.networks import storey_networks
from planner.plan.options import PlanOptions
from planner.plan.problem import Problem
from planner.plan.surfaces import SurfaceCover
from planner.plan.tripod import TripodDisc
from planner.plan.verify import VerifyReport
from planner.plan.verify_surfaces import SurfaceReport
from planner.site.candidate import Candidate
from planner.site.model import Site
from planner.site.validate import ValidationReport
from planner.solve.result import SolveResult, gap_words, state_words


@dataclass(frozen=True, kw_only=True)
class Plan:
    """A verified plan: the resolved problem it answers, the chosen stations, how they were found, and their
    verification. ``pool``: the size and fingerprint of the coverage problem it was chosen from
    (:func:`planner.coverage.fingerprint.pool_of`; None where the path that made it did not record it), which
    the best plans known are matched on. ``coverage``: the candidate pool's coverage as the run built it
    (:func:`planner.plan.run.build_problem`, before any pricing), and ``surface_cover`` the floor and ceiling
    columns of the same candidates (None: walls only): what the report's method comparison plans on instead of
    building the pool again (None where the path that made the plan did not keep it; neither is compared)."""

    problem: Problem
    result: SolveResult
    stations: tuple[Candidate, ...]
    verification: VerifyReport
    problem_size: dict[str, int]
    log: tuple[str, ...] = ()
    registration: dict[str, int] = field(default_factory=dict)
    tripods: tuple[TripodDisc, ...] = ()
    pool: Pool | None = None
    surfaces: SurfaceReport | None = None
    #: scan settings, set-up + scan time and point spacing (None: a plan of stations alone)
    hours: Hours | None = None
    coverage: CoverageProblem | None = field(default=None, compare=False, repr=False)
    surface_cover: SurfaceCover | None = field(default=None, compare=False, repr=False)

    @property
    def site(self) -> Site:
        return self.problem.site

    @property
    def options(self) -> PlanOptions:
        return self.problem.options

    @property
    def validation(self) -> ValidationReport:
        return self.problem.validation

    @cached_property
    def links(self) -> tuple[tuple[str, str], ...]:
        """The plan's registration pairs (station ids, each pair and the list sorted): its registration's relation
        (:meth:`planner.coverage.relation.Registration.relation`) over its stations' coverage on the station pieces,
        as the field sheet, the network check and the report's map relate them; computed once, on first use."""
        st = self.stations
        if not st:
            return ()
        g = self.problem.registration.relation(st, self.stations_cover)
        return tuple(sorted((min(st[u].id, st[v].id), max(st[u].id, st[v].id)) for u, v in g.edges()))

    @cached_property
    def stations_cover(self) -> CoverageProblem:
        """The coverage of the plan's stations alone on the station pieces
        (:meth:`planner.coverage.sight.Sight.of_stations`, rows in the order of :attr:`stations`), under the plan's
        sight: what its registration pairs are read from and the network check takes; built once, on first use."""
        return self.problem.sight.of_stations(self.stations)

    @property
    def connected(self) -> bool:
        """Every zone-side's stations form one registration bundle."""
        return all(n <= 1 for n in self.registration.values())

    def count_by_side(self) -> dict[str, int]:
        return dict(Counter(s.side.value for s in self.stations))

    def _repr_html_(self) -> str:
        from planner.core.text import summary_html

        return summary_html(self, f"Plan: {len(self.stations)} stations")

    def summary(self) -> str:
        """The plan for the terminal: how it was found, the stations per zone (in the site's order), the limits
        and rules it answers, both bounds with what each holds over, registration, tripod discs and the
        verification; notes of the run that differ only in the names they mention come folded into one line."""
        sides = self.count_by_side()
        head = f"instance {self.site.name}: {self.result.summary(self.time_label)}"
        if self.hours is not None and self.hours.objective == "field-time":  # the count is not what was minimised
            status, scope = self.result.status, self.hours.timing.get("scope", "pool")
            words = gap_words(status, self.hours.timing.get("gap"), "gap to its bound")
            state = f"{state_words(status, scope)} in set-up + scan time"
            head = f"instance {self.site.name}: {self.result.summary(self.time_label, state)}"
            to_bound = f", {words} over the {scope}" if words else ""
            head += f" (objective field-time: set-up + scan {self.hours.setup_scan_s / 3600:.2f} h{to_bound})"
        lines = [
            head,
            self._presolve_line(),
            f"stations: {len(self.stations)} (inside {sides.get('inside', 0)}, outside {sides.get('outside', 0)}); "
            f"candidates {self.problem_size['candidates']:,}, targets {self.problem_size['targets']:,}",
        ]
        lines += table(["zone", "side", "stations"], self._by_zone())
        lines += [self.problem.limits_line(), self.problem.registration_line()]
        lines += fold_alike(self.log, [z.id for z in self.site.zones])
        lines.append(self._accuracy_line())
        lines += self._bound_lines()
        broken = {g: n for g, n in self.registration.items() if n > 1}
        lines.append(
            "registration: every registration group connected under the overlap relation"
            if not broken
            else "registration: not connected: " + ", ".join(f"{g} in {n} parts" for g, n in broken.items())
        )
        lines += [n.line() for n in storey_networks(self.site, self.registration)]
        lines += self._tripod_lines()
        lines.append(self.verification.summary())
        if self.hours is not None:
            lines += self.hours.lines()
        if self.surfaces is not None:
            lines += [self.problem.surfaces.line()] if self.problem.surfaces is not None else []
            lines += self.surfaces.lines()
        return "\n".join(line for line in lines if line)

    def _site_order(self, zone: str, side: str) -> tuple[int, int]:
        """Sort key of a zone-side: the zone's place in the site file, inside before outside."""
        order = {z.id: k for k, z in enumerate(self.site.zones)}
        return order.get(zone, len(order)), 0 if side == "inside" else 1

    def _by_zone(self) -> list[tuple[str, str, int]]:
        """(zone, side, stations) per zone-side with stations, in the site's order."""
        counts = Counter((s.zone, s.side.value) for s in self.stations)
        return [(z, s, n) for (z, s), n in sorted(counts.items(), key=lambda kv: self._site_order(*kv[0]))]

    def _presolve_line(self) -> str:
        """The MILP presolve's counts in one sentence (empty where it did not run)."""
        info = self.result.info.get("presolve")
        if not isinstance(info, dict):
            return ""
        known = (
            "candidates_in",
            "candidates_out",
            "dominated_removed",
            "forced",
            "targets_in",
            "targets_out",
            "duplicate_targets_removed",
            "links",
            "time_s",
        )
        if not all(k in info for k in known[:7]):  # another solver's report: its keys as they are
            return "presolve: " + ", ".join(f"{k.replace('_', ' ')} {v}" for k, v in info.items())
        links = f", {info['links']:,} overlap links among the candidates kept" if "links" in info else ""
        time = f", {info['time_s']:.2f} s" if "time_s" in info else ""
        rest = "".join(f", {k.replace('_', ' ')} {v}" for k, v in info.items() if k not in known)
        return (
            f"presolve: candidates {info['candidates_in']:,} -> {info['candidates_out']:,} "
            f"({info['dominated_removed']:,} dominated, {info['forced']:,} forced into the plan), "
            f"targets {info['targets_in']:,} -> {info['targets_out']:,} "
            f"({info['duplicate_targets_removed']:,} implied by other targets){links}{rest}{time}"
        )

    def _tripod_lines(self) -> list[str]:
        """The tripod discs' radii, then each station's disc (``tripods[k]`` is ``stations[k]``'s) and
        instrument-height tolerance (3.32) as a table in the site's order."""
        if not self.tripods:
            return []
        radii = [d.radius_m for d in self.tripods]
        p = self.site.parameters
        ih, span = p.instrument_height_m, p.instrument_height_span_m
        pairs = sorted(zip(self.stations, self.tripods), key=lambda sd: self._site_order(sd[0].zone, sd[0].side.value))
        rows = [(d.station, s.zone, s.side.value, f"{d.radius_m:.3f}", f"{d.height_tolerance_m:.3f}") for s, d in pairs]
        head = [
            f"tripod discs: radius min {min(radii):.3f} m, median {float(np.median(radii)):.3f} m, max {max(radii):.3f} m"
            + (" (stations recentred)" if self.options.recentre else " (centred on the planned stations)"),
            f"instrument-height tolerance (3.32, IH {ih:g}..{ih + span:g} m) and tripod disc per station:",
        ]
        return head + table(["station", "zone", "side", "disc radius m", "IH tolerance m"], rows)

    def _bound_lines(self) -> list[str]:
        """The bound's scope, then each bound on a line of its own with what it holds over: the pool's (the
        MILP's), the plane's (pricing) and the connected plans' plane bound."""
        r = self.result
        scope = r.scope
        if scope is None:
            return []
        info = r.info
        pool = info.get("pool_bound", r.bound)
        plane = info.get("plane_bound")
        rows = [(f"{pool:g}" if pool is not None else "none", "over the candidate pool (MILP)")]
        assumes = info.get("certificate", {}).get("assumes", "pieces of the target spacing")
        plane_scope = str(info.get("plane_bound_scope", "plane"))  # "plane, k = K" for k views
        where = "over every position in the plane" + plane_scope.removeprefix("plane")
        rows.append(
            (f"{plane:g}", f"{where} (cover LP priced over the coverage regions; {assumes})")
            if plane is not None
            else ("none", f"over the plane ({info.get('plane_off', 'pricing off')})")
        )
        conn = info.get("connected_plane_bound")
        if conn is not None:
            refined = [s["refined"] for s in info.get("connected_plane", {}).get("zone_sides", []) if s.get("refined")]
            how = "ring walk over patches"
            if refined:
                steps = max(int(r.get("steps", 0)) for r in refined)
                how += ", connected cover over refined patches" if steps else ", connected cover over patches"
            rows.append((f"{conn:g}", f"connected plans, over every position in the plane ({how})"))
        head = (
            f"bound scope: {plane_scope} (no plan from any positions in the plane has fewer stations); bounds:"
            if scope == "plane"
            else "bound scope: pool (the plan is proven only over the candidate pool); bounds:"
            if r.status.value == "optimal"
            else "bound scope: pool; bounds:"
        )
        width = max(len(b) for b, _ in rows)
        return [head] + [f"  {b.rjust(width)}  {what}" for b, what in rows]

    @property
    def time_label(self) -> str:
        """What the result's time covers: the solver alone (on how many threads), or the whole tiled run."""
        if self.result.method == "milp-tiles":
            return "whole tiled run: pool, coverage, tiles, bound, stitch and search"
        threads = self.options.milp.threads if self.result.method == "milp" else 1
        return f"solver alone, {threads} thread{'s' if threads > 1 else ''}"

    def _accuracy_line(self) -> str:
        """How views were judged: incidence model, precision mode, stand-off, and theta_max (derived: per range)."""
        p, o = self.site.parameters, self.options
        mode = "off" if not o.precision else "combined" if o.combined else "single"
        theta = self.validation.theta_limit
        th = theta.summary() if theta is not None else f"theta_max {p.theta_max_deg:g} deg"
        return f"accuracy: view error e(S, theta), incidence model {p.incidence_model}, precision {mode}, stand-off {p.min_standoff_m:g} m; {th}"
