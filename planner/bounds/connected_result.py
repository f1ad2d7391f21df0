"""The connected plane bound as a result: per zone-side parts (:class:`SideBound`), the whole
(:class:`ConnectedPlaneBound`, computed by :func:`planner.bounds.plane_ring.connected_plane_bound`), and the plan's
result with it (:func:`with_connected_plane_bound`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

from planner.bounds.plane_refine import Refined
from planner.coverage.matrix import CoverageProblem
from planner.solve.result import SolveResult, Status


@dataclass(frozen=True)
class SideBound:
    """One zone-side's share: Farley's part ``farley`` (real), the ring walk over patches ``ring`` (or None when not
    formed), the patch side and the family size it was formed on."""

    zone_side: str
    farley: float
    ring: int | None
    patch_m: float | None
    family: int
    #: the connected cover over refined patches (:mod:`planner.bounds.plane_refine`), when it was run
    refined: Refined | None = None

    @property
    def farley_count(self) -> int:
        """Farley's share rounded up (a whole number of stations)."""
        return math.ceil(self.farley - 1e-6)

    @property
    def value(self) -> int:
        return max(self.farley_count, self.ring or 0, self.refined.bound if self.refined else 0)

    def how(self) -> str:
        """What gave the value: the refined cover (when it beat the others), the ring walk, or (nothing said) Farley's
        share."""
        r = self.refined
        if r is not None and r.bound > max(self.farley_count, self.ring or 0):
            if r.steps == 0:
                return f" (connected cover over {r.smallest_m:.2f}-m patches, no search)"
            return f" (connected cover over refined patches, {r.steps} steps, down to {r.smallest_m:.2f} m)"
        if self.ring is not None and self.ring >= self.farley_count:
            return f" (ring walk, {self.patch_m:.2f}-m patches)"
        return ""


@dataclass(frozen=True)
class ConnectedPlaneBound:
    """The connected plane bound: ``bound`` (None when not applicable, ``note`` says why), per zone-side parts."""

    bound: int | None
    sides: tuple[SideBound, ...] = field(default_factory=tuple)
    time_s: float = 0.0
    note: str = ""

    def summary(self) -> str:
        if self.bound is None:
            return f"connected plane bound: {self.note}"
        parts = ", ".join(f"{s.zone_side} {s.value}{s.how()}" for s in self.sides)
        return (
            f"connected plane bound: {self.bound} stations for any plan connected under the overlap rule, stations "
            f"anywhere ({parts}; {self.time_s:.1f} s)"
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "bound": self.bound,
            "time_s": round(self.time_s, 3),
            "note": self.note,
            "zone_sides": [
                {
                    "zone_side": s.zone_side,
                    "farley": round(s.farley, 6),
                    "ring": s.ring,
                    "patch_m": s.patch_m,
                    "undominated_patches": s.family,
                    "refined": None if s.refined is None else s.refined.to_dict(),
                }
                for s in self.sides
            ],
        }


def with_connected_plane_bound(result: SolveResult, cb: ConnectedPlaneBound) -> SolveResult:
    """``result`` with ``info['connected_plane_bound']`` (None where not formed) and its parts; the scope becomes
    ``plane`` (and the bound the plan's count) when the plan meets it."""
    info = dict(result.info)
    info["connected_plane_bound"] = cb.bound
    info["connected_plane"] = cb.to_dict()
    cert = dict(info.get("certificate") or {})
    cert["connected_plane_bound_from"] = (
        "per zone-side, the largest of its share of Farley's bound, the ring walk over undominated patches "
        "(planner.bounds.plane_ring) and, where run, the connected cover over refined patches "
        "(planner.bounds.plane_refine): every connected plan under the overlap rule, stations anywhere"
    )
    info["certificate"] = cert
    if cb.bound is not None and result.objective is not None and result.objective <= cb.bound + 1e-9:
        info["bound_scope"] = "plane"
        return replace(result, status=Status.OPTIMAL, bound=float(cb.bound), info=info)
    return replace(result, info=info)


def plan_counts(problem: CoverageProblem, selected: tuple[int, ...]) -> dict[int, int]:
    """The plan's stations per zone-side, keyed ``2 zone + side`` as the targets are."""
    t = problem.targets
    out: dict[int, int] = {}
    for i in selected:
        c = problem.candidates[i]
        k = 2 * t.zone_ids.index(c.zone) + (0 if c.side.value == "inside" else 1)
        out[k] = out.get(k, 0) + 1
    return out
