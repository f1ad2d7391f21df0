"""Planning parameters and the limits derived from them with an instrument.

Defaults are the dissertation's (chapter 4): theta_max = 68 deg, overlap 30 %,
sigma_req = 10 mm, sigma_0 = centring = graphical = 0.5 mm, station on the ground.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

from planner.accuracy import ErrorBudget, max_slant_range_m, sigma_instr_m, tolerance_for_scale_m
from planner.errors import InputError
from planner.instruments import Scanner

DEFAULT_INSTRUMENT = "leica-p30"


@dataclass(frozen=True)
class ClosureTolerance:
    """How well a zone's traverse must close before it is accepted and adjusted.

    ``angular_deg``: largest |sum of angles - (n-2)*180|. The tables print
    angles to 0.001 deg, so rounding alone can reach 0.0005 deg per angle;
    0.01 deg (36") admits that for up to 20 vertices and still catches any
    misprinted angle. ``min_relative_precision``: perimeter / linear
    misclosure must be at least this N (1:N); 1:2000 is the usual plan-traverse
    tolerance and is 5 mm on a 10 m room, well above the 1 mm print rounding.
    """

    angular_deg: float = 0.01
    min_relative_precision: float = 2000.0

    def __post_init__(self) -> None:
        if not math.isfinite(self.angular_deg) or self.angular_deg < 0:
            raise InputError("must be a finite number >= 0", field="angular_tolerance_deg", value=self.angular_deg)
        if not math.isfinite(self.min_relative_precision) or self.min_relative_precision <= 0:
            raise InputError("must be a finite number > 0", field="min_relative_precision", value=self.min_relative_precision)


@dataclass(frozen=True)
class Parameters:
    """What the surveyor asks for; validated on construction.

    ``sigma_req_m`` is the required model accuracy; ``drawing_scale`` (a
    denominator, e.g. 50 for 1:50) records where it came from when it was
    derived from table 1.1. ``max_slant_range_m`` overrides S_max.
    """

    theta_max_deg: float = 68.0
    overlap: float = 0.30
    sigma_req_m: float = 0.010
    drawing_scale: int | None = None
    budget: ErrorBudget = field(default_factory=ErrorBudget)
    instrument_height_m: float = 0.0
    max_slant_range_m: float | None = None

    def __post_init__(self) -> None:
        _finite(self.theta_max_deg, "theta_max_deg")
        if not 0.0 < self.theta_max_deg < 90.0:
            raise InputError("must be in (0, 90) degrees", field="theta_max_deg", value=self.theta_max_deg)
        _finite(self.overlap, "overlap")
        if not 0.0 <= self.overlap < 1.0:
            raise InputError("must be a fraction in [0, 1), e.g. 0.3 for 30 %", field="overlap", value=self.overlap)
        _finite(self.sigma_req_m, "sigma_req_m")
        if self.sigma_req_m <= 0:
            raise InputError("must be > 0", field="sigma_req_m", value=self.sigma_req_m)
        _finite(self.instrument_height_m, "instrument_height_m")
        if self.instrument_height_m < 0:
            raise InputError("must be >= 0", field="instrument_height_m", value=self.instrument_height_m)
        if self.max_slant_range_m is not None:
            _finite(self.max_slant_range_m, "max_slant_range_m")
            if self.max_slant_range_m <= 0:
                raise InputError("must be > 0", field="max_slant_range_m", value=self.max_slant_range_m)

    def with_scale(self, scale: str | int) -> "Parameters":
        """The same parameters with sigma_req taken from drawing-scale table 1.1."""
        from planner.accuracy import parse_scale

        return replace(self, sigma_req_m=tolerance_for_scale_m(scale), drawing_scale=parse_scale(scale))


def _finite(value: Any, name: str) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError("must be a finite number", field=name, value=value)


@dataclass(frozen=True)
class RangeLimit:
    """The slant range S_max in force and how it was obtained."""

    max_slant_range_m: float
    sigma_instr_m: float
    source: str


def resolve_range_limit(params: Parameters, scanner: Scanner) -> RangeLimit:
    """S_max for these parameters and scanner.

    Order: the parameter override; else the scanner preset's fixed value; else
    (3.1) for sigma_instr of (3.2), capped by the datasheet range. Raises
    InfeasibleError when no instrument budget is left (3.2 has no real root).
    """
    s_instr = sigma_instr_m(params.sigma_req_m, params.budget)
    if params.max_slant_range_m is not None:
        return RangeLimit(params.max_slant_range_m, s_instr, "given (max_slant_range_m)")
    if scanner.max_slant_range_m is not None:
        return RangeLimit(scanner.max_slant_range_m, s_instr, f"fixed by instrument preset {scanner.name}")
    derived = max_slant_range_m(scanner, s_instr)
    if scanner.max_range_m is not None and scanner.max_range_m < derived:
        return RangeLimit(scanner.max_range_m, s_instr, f"datasheet range of {scanner.name} ((3.1) gives {derived:.2f} m)")
    return RangeLimit(derived, s_instr, f"derived by (3.1) for {scanner.name} at sigma_req {params.sigma_req_m * 1000:g} mm")
