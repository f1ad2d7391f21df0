"""Estimate the memory a planning run needs before building anything, and refuse what will not fit.

The estimate counts, from the site's geometry alone (no candidate, target or pair is built):

- wall pieces: ``ceil(wall length / target spacing)`` per wall and scan side;
- candidates: the grid points of each zone-side region (the meshgrid the pool builds over the region's envelope
  in the frame's axes, then the points inside the region), plus a fixed allowance per wall for the closed-form,
  field, corner-ray and bisector candidates;
- kept pairs: per zone-side, each piece is seen at most by the grid points of the half disc of radius S_max
  (horizontal) in front of it, and never by more than the zone-side's candidates.

Each count is priced at a per-item cost measured on the bundled instances (docs/startup.md); the largest single
array (the meshgrid) is priced too, since it alone can exceed the memory; and the process itself (``BASE_BYTES``).
``scripts/bench/bench_memory.py`` sets the estimate beside the measured peak.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import TYPE_CHECKING

from planner.core.errors import InputError, UsageError

if TYPE_CHECKING:
    from planner.site.model import Site, Zone

#: bytes per wall piece (thirteen parallel arrays, and the verification's finer sampling of it)
TARGET_BYTES = 1_000
#: bytes per candidate (a Candidate object, its id string, its rows in the pool arrays)
CANDIDATE_BYTES = 600
#: bytes per kept candidate-piece pair: both sparse views, the block under test, presolve and pricing (calibrated
#: against the peak of a whole ``planner plan``, docs/startup.md)
PAIR_BYTES = 200
#: bytes per meshgrid point of the pool's grid (two float64 grids, the point array, the inside test)
GRID_POINT_BYTES = 56
#: closed-form, field-sample, corner-ray and bisector candidates allowed per wall
CANDIDATES_PER_WALL = 40
#: bytes of the process before any site is read: the interpreter with numpy, scipy, shapely, networkx and the
#: solvers loaded; without it the estimate of small runs falls far under the peak (docs/benchmarks/memory.md)
BASE_BYTES = 200 * 2**20
#: share of the available memory a run may use when no limit is given
DEFAULT_SHARE = 0.5


@dataclass(frozen=True)
class WorkEstimate:
    """What a planning run would build: counts and the bytes they take (an estimate, see module doc)."""

    targets: int
    candidates: int
    grid_points: int
    pairs: int

    @property
    def bytes(self) -> int:
        return (
            BASE_BYTES
            + self.targets * TARGET_BYTES
            + self.candidates * CANDIDATE_BYTES
            + self.pairs * PAIR_BYTES
            + self.grid_points * GRID_POINT_BYTES
        )

    def describe(self) -> str:
        return (
            f"{_fmt_bytes(self.bytes)} ({self.targets:.3g} wall pieces, {self.candidates:.3g} candidates, "
            f"{self.pairs:.3g} pairs)"
        )


def available_memory_bytes() -> int:
    """MemAvailable from /proc/meminfo, else the physical memory, else 4 GiB."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return int(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return 4 * 2**30


def parse_memory(text: str) -> int:
    """``"2G"``, ``"512M"``, ``"800k"`` or a number of bytes -> bytes (binary multiples); UsageError (exit 2)
    for anything else."""
    units = {"k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}
    t = text.strip().lower().removesuffix("b").removesuffix("i")
    mult = units.get(t[-1:], 1)
    num = t[:-1] if t[-1:] in units else t
    try:
        value = float(num) * mult
    except ValueError:
        raise UsageError(
            "expected a size such as 4G, 512M or a number of bytes", field="--memory-limit", value=text
        ) from None
    if not (math.isfinite(value) and value > 0):
        raise UsageError("must be a size > 0", field="--memory-limit", value=text)
    return int(value)


def estimate_work(site: Site, target_spacing_m: float, grid_spacing_m: float, max_slant_range_m: float) -> WorkEstimate:
    """Count what the coverage build would make (module docstring); S_max's horizontal reach bounds the pairs."""
    targets = candidates = grid = pairs = 0
    for zone in site.zones:
        for side in zone.scan_side.sides:
            n_t = sum(math.ceil(w.length_m / target_spacing_m) for w in zone.walls)
            n_g, area = _grid_count(zone, side.value == "outside", max_slant_range_m, grid_spacing_m)
            n_c = n_g + CANDIDATES_PER_WALL * len(zone.walls)
            in_front = int(min(n_c, math.pi * max_slant_range_m**2 / 2 / grid_spacing_m**2 + CANDIDATES_PER_WALL))
            targets, candidates, grid = targets + n_t, candidates + n_c, grid + area
            pairs += n_t * in_front
    return WorkEstimate(targets, candidates, grid, pairs)


def _grid_count(zone: Zone, outside: bool, max_slant_range_m: float, spacing: float) -> tuple[int, int]:
    """Grid points inside the zone-side region and points of the meshgrid over its envelope (frame axes of the
    zone's first wall, as the pool builds it)."""
    xy = zone.xy
    d = xy[1] - xy[0]
    ux = d / math.hypot(float(d[0]), float(d[1]))
    u, v = (xy - xy[0]) @ ux, (xy - xy[0]) @ [-ux[1], ux[0]]
    pad = max_slant_range_m if outside else 0.0
    span_u = float(u.max() - u.min()) + 2 * pad
    span_v = float(v.max() - v.min()) + 2 * pad
    envelope = (span_u / spacing + 2) * (span_v / spacing + 2)
    region_area = (math.pi * max_slant_range_m**2 + zone.perimeter_m * max_slant_range_m) if outside else zone.area_m2
    return int(min(envelope, region_area / spacing**2 + 1)), int(envelope)


def check_memory(
    site: Site, target_spacing_m: float, grid_spacing_m: float, max_slant_range_m: float, limit_bytes: int | None = None
) -> WorkEstimate:
    """The estimate; InputError (exit 3) where it exceeds ``limit_bytes`` (default: a share of the memory free)."""
    limit = int(DEFAULT_SHARE * available_memory_bytes()) if limit_bytes is None else limit_bytes
    est = estimate_work(site, target_spacing_m, grid_spacing_m, max_slant_range_m)
    if est.bytes > limit:
        raise InputError(
            f"the coverage problem needs about {est.describe()}, over this limit; coarsen "
            f"--target-spacing / --grid-spacing, split the site, or raise --memory-limit",
            file=site.source or None,
            field="--memory-limit",
            value=_fmt_bytes(limit),
        )
    return est


def _fmt_bytes(n: float) -> str:
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if n < 1024 or unit == "PiB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1024
    return f"{n:.1f} PiB"
