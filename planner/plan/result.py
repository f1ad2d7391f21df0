"""A verified plan (:class:`Plan`): the chosen stations, how they were found, their verification and summary."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from planner.coverage.fingerprint import Pool
from planner.plan.options import PlanOptions
from planner.plan.problem import Problem
from planner.plan.tripod import TripodDisc, tripod_heights_line
from planner.plan.verify import VerifyReport
from planner.site.candidate import Candidate
from planner.site.model import Site
from planner.site.validate import ValidationReport
from planner.solve.result import SolveResult


@dataclass(frozen=True, kw_only=True)
class Plan:
    """A verified plan: the resolved problem it answers, the chosen stations, how they were found, and their
    verification. ``pool``: the size and fingerprint of the coverage problem it was chosen from
    (:func:`planner.coverage.fingerprint.pool_of`; None where the path that made it did not record it), which
    the best plans known are matched on."""

    problem: Problem
    result: SolveResult
    stations: tuple[Candidate, ...]
    verification: VerifyReport
    problem_size: dict[str, int]
    log: tuple[str, ...] = ()
    registration: dict[str, int] = field(default_factory=dict)
    tripods: tuple[TripodDisc, ...] = ()
    pool: Pool | None = None

    @property
    def site(self) -> Site:
        return self.problem.site

    @property
    def options(self) -> PlanOptions:
        return self.problem.options

    @property
    def validation(self) -> ValidationReport:
        return self.problem.validation

    @property
    def connected(self) -> bool:
        """Every zone-side's stations form one registration bundle."""
        return all(n <= 1 for n in self.registration.values())

    def count_by_side(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for s in self.stations:
            out[s.side.value] = out.get(s.side.value, 0) + 1
        return out

    def _repr_html_(self) -> str:
        from planner.core.text import summary_html

        return summary_html(self, f"Plan: {len(self.stations)} stations")

    def summary(self) -> str:
        by_zone: dict[tuple[str, str], int] = {}
        for s in self.stations:
            by_zone[(s.zone, s.side.value)] = by_zone.get((s.zone, s.side.value), 0) + 1
        sides = self.count_by_side()
        w = max([10] + [len(z) + 1 for z, _ in by_zone])  # long room names (IFC) keep their column
        lines = [
            f"instance {self.site.name}, method {self.result.method}: {self.result.summary(self.time_label)}",
            f"presolve: {self.result.info['presolve']}" if "presolve" in self.result.info else "",
            f"stations: {len(self.stations)} (inside {sides.get('inside', 0)}, outside {sides.get('outside', 0)}); "
            f"candidates {self.problem_size['candidates']}, targets {self.problem_size['targets']}",
            f"{'zone':<{w}}{'side':<9}{'stations':>9}",
        ]
        lines += [f"{z:<{w}}{s:<9}{n:>9}" for (z, s), n in by_zone.items()]
        lines += [self.problem.limits_line(), self.problem.registration_line()]
        lines += list(self.log)
        lines.append(self._accuracy_line())
        lines.append(self._bound_line())
        broken = {g: n for g, n in self.registration.items() if n > 1}
        lines.append(
            "registration: every registration group connected under the overlap relation"
            if not broken
            else "registration: not connected: " + ", ".join(f"{g} in {n} parts" for g, n in broken.items())
        )
        if self.tripods:
            radii = [d.radius_m for d in self.tripods]
            lines.append(
                f"tripod discs: radius min {min(radii):.3f} m, median {float(np.median(radii)):.3f} m, max {max(radii):.3f} m"
                + (" (stations recentred)" if self.options.recentre else " (centred on the planned stations)")
            )
            lines.append(tripod_heights_line(self.tripods, self.site.parameters))
        lines.append(self.verification.summary())
        return "\n".join(line for line in lines if line)

    def _bound_line(self) -> str:
        """Both bounds, each with what it holds over: the pool's (the MILP's) and the plane's (pricing)."""
        r = self.result
        scope = r.scope
        if scope is None:
            return ""
        info = r.info
        pool = info.get("pool_bound", r.bound)
        plane = info.get("plane_bound")
        pool_s = f"{pool:g} over the candidate pool (MILP)" if pool is not None else "none over the pool"
        plane_s = (
            f"{plane:g} over every position in the plane (cover LP priced over the coverage regions; "
            f"{info.get('certificate', {}).get('assumes', 'pieces of the target spacing')})"
            if plane is not None
            else "no plane bound (pricing off)"
        )
        conn = info.get("connected_plane_bound")
        if conn is not None:
            how = (
                "ring walk over patches, connected cover over refined patches"
                if any(s.get("refined") for s in info.get("connected_plane", {}).get("zone_sides", []))
                else "ring walk over patches"
            )
            plane_s += f"; connected plans: {conn:g} over every position in the plane ({how})"
        head = (
            "bound scope: plane (no plan from any positions in the plane has fewer stations)"
            if scope == "plane"
            else "bound scope: pool (the plan is proven only over the candidate pool)"
            if r.status.value == "optimal"
            else "bound scope: pool"
        )
        return f"{head}; bounds: {pool_s}; {plane_s}"

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
