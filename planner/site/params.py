"""Planning parameters and the limits derived from them with an instrument.

Defaults are the dissertation's (chapter 4): theta_max = 68 deg, overlap 30 %,
sigma_req = 10 mm, sigma_0 = centring = graphical = 0.5 mm, station on the ground.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

from planner.core.checks import finite_number
from planner.core.errors import InputError
from planner.instrument.accuracy import (
    MAX_SIGMA_M,
    ErrorBudget,
    derive_theta_max_deg,
    incidence_limit_deg,
    max_slant_range_m,
    parse_scale,
    sigma_instr_m,
    tolerance_for_scale_m,
)
from planner.instrument.models import Scanner

#: no wall, obstacle or instrument stands higher (m); a larger value is a typo
MAX_HEIGHT_M = 1e4
#: no slant range (and no stand-off) is longer (m): no scanner or total station reaches this far; a longer one is a typo
MAX_RANGE_M = 1e4

DEFAULT_INSTRUMENT = "leica-p30"

#: what :func:`height_ok` asks, as an error says it
HEIGHT_RULE = f"must be a finite height > 0 and <= {MAX_HEIGHT_M:g} m"


def height_ok(h: float) -> bool:
    """A finite height > 0 and <= ``MAX_HEIGHT_M`` (walls, holes, obstacles)."""
    return math.isfinite(h) and 0 < h <= MAX_HEIGHT_M


@dataclass(frozen=True)
class ClosureTolerance:
    """How well a zone's traverse must close before it is accepted and adjusted. ``angular_deg``: largest |sum of angles
    - (n-2)*180| (the default admits the print's rounding to 0.001 deg for up to 20 vertices);
    ``min_relative_precision``: perimeter / linear misclosure must be at least this N (1:N; 1:2000 is the usual
    plan-traverse tolerance)."""

    angular_deg: float = 0.01
    min_relative_precision: float = 2000.0

    def __post_init__(self) -> None:
        if not math.isfinite(self.angular_deg) or self.angular_deg < 0:
            raise InputError("must be a finite number >= 0", field="angular_tolerance_deg", value=self.angular_deg)
        if not math.isfinite(precision := self.min_relative_precision) or precision <= 0:
            raise InputError("must be a finite number > 0", field="min_relative_precision", value=precision)


@dataclass(frozen=True)
class Parameters:
    """What the surveyor asks for; validated on construction. ``sigma_req_m``: the required model accuracy;
    ``drawing_scale`` (a denominator) records where it came from when derived from table 1.1; ``max_slant_range_m``
    overrides S_max. ``incidence_model``: how a view's point error grows with incidence (``none``, ``table``,
    ``soudarissanane``: see :func:`planner.instrument.accuracy.incidence_factor`). ``derive_theta_max``: theta_max
    follows from sigma_req (``theta_max_deg`` then only seeds the closed-form candidates; it switches ``table`` on when
    no model is chosen). ``min_standoff_m``: no station or control point closer to a wall or obstacle edge (a tripod's
    leg spread). ``instrument_height_span_m``: how much higher than IH the tripod may stand (the tolerance circle (3.32)
    is reported for IH..IH + span)."""

    theta_max_deg: float = 68.0
    overlap: float = 0.30
    sigma_req_m: float = 0.010
    drawing_scale: int | None = None
    budget: ErrorBudget = field(default_factory=ErrorBudget)
    instrument_height_m: float = 0.0
    max_slant_range_m: float | None = None
    incidence_model: str = "none"
    derive_theta_max: bool = False
    min_standoff_m: float = 0.4
    instrument_height_span_m: float = 0.4

    def __post_init__(self) -> None:
        _finite(self.theta_max_deg, "theta_max_deg")
        if not 0.0 < self.theta_max_deg < 90.0:
            raise InputError("must be in (0, 90) degrees", field="theta_max_deg", value=self.theta_max_deg)
        _finite(self.overlap, "overlap")
        if not 0.0 <= self.overlap < 1.0:
            raise InputError("must be a fraction in [0, 1), e.g. 0.3 for 30 %", field="overlap", value=self.overlap)
        _within(self.sigma_req_m, "sigma_req_m", MAX_SIGMA_M, zero_ok=False)
        _within(self.instrument_height_m, "instrument_height_m", MAX_HEIGHT_M)
        if self.max_slant_range_m is not None:
            _within(self.max_slant_range_m, "max_slant_range_m", MAX_RANGE_M, zero_ok=False)
        incidence_limit_deg(self.incidence_model)  # refuses an unknown model
        if self.derive_theta_max and self.incidence_model == "none":
            object.__setattr__(self, "incidence_model", "table")
        _within(self.min_standoff_m, "min_standoff_m", MAX_RANGE_M)
        _within(self.instrument_height_span_m, "instrument_height_span_m", MAX_HEIGHT_M)

    def with_scale(self, scale: str | int) -> Parameters:
        """The same parameters with sigma_req taken from drawing-scale table 1.1."""
        return replace(self, sigma_req_m=tolerance_for_scale_m(scale), drawing_scale=parse_scale(scale))


def _finite(value: Any, name: str) -> None:
    if not finite_number(value):
        raise InputError("must be a finite number", field=name, value=value)


def _within(value: Any, name: str, highest: float, *, zero_ok: bool = True) -> None:
    """A finite number >= 0 (> 0 unless ``zero_ok``) and <= ``highest`` metres."""
    _finite(value, name)
    if value < 0 or (value == 0 and not zero_ok) or value > highest:
        raise InputError(f"must be {'>=' if zero_ok else '>'} 0 and <= {highest:g} m", field=name, value=value)


@dataclass(frozen=True)
class RangeLimit:
    """The slant range S_max in force and how it was obtained."""

    max_slant_range_m: float
    sigma_instr_m: float
    source: str


def resolve_range_limit(params: Parameters, scanner: Scanner) -> RangeLimit:
    """S_max for these parameters and scanner: the parameter override, else the scanner's fixed value, else (3.1) for
    sigma_instr of (3.2), capped by the datasheet range. InfeasibleError when no instrument budget is left; InputError
    when the limit is beyond ``MAX_RANGE_M`` (no datasheet range, errors barely growing)."""
    s_instr = sigma_instr_m(params.sigma_req_m, params.budget)
    if params.max_slant_range_m is not None:
        return RangeLimit(params.max_slant_range_m, s_instr, "given (max_slant_range_m)")
    if scanner.max_slant_range_m is not None:
        limit = RangeLimit(scanner.max_slant_range_m, s_instr, f"fixed by instrument preset {scanner.name}")
    else:
        derived = max_slant_range_m(scanner, s_instr)
        if scanner.max_range_m is not None and scanner.max_range_m < derived:
            limit = RangeLimit(
                scanner.max_range_m, s_instr, f"datasheet range of {scanner.name} ((3.1) gives {derived:.2f} m)"
            )
        else:
            limit = RangeLimit(
                derived, s_instr, f"derived by (3.1) for {scanner.name} at sigma_req {params.sigma_req_m * 1000:g} mm"
            )
    if not limit.max_slant_range_m <= MAX_RANGE_M:
        raise InputError(
            f"S_max {limit.max_slant_range_m:.4g} m ({limit.source}) is beyond {MAX_RANGE_M:g} m: give the "
            f"instrument a max_range_m <= {MAX_RANGE_M:g}, or the site max_slant_range_m",
            field="instrument",
            value=scanner.name,
        )
    return limit


#: ranges (m) at which a derived theta_max is printed, besides S_max
THETA_REPORT_RANGES_M: tuple[float, ...] = (25.0, 50.0, 100.0, 150.0, 200.0)


@dataclass(frozen=True)
class ThetaLimit:
    """The incidence limit in force: ``theta_max_deg`` for the coverage test, and where it came from. When derived,
    coverage takes the model's limit and the per-view precision test decides, so the limit falls with range;
    ``by_range`` lists (S, theta_max(S)) for the summary."""

    theta_max_deg: float
    source: str
    by_range: tuple[tuple[float, float], ...] = ()

    def summary(self) -> str:
        if not self.by_range:
            return f"theta_max {self.theta_max_deg:g} deg [{self.source}]"
        cells = ", ".join(f"{th:.1f} deg at {s:g} m" for s, th in self.by_range)
        return f"theta_max derived [{self.source}]: {cells}"


def resolve_theta_limit(params: Parameters, scanner: Scanner, max_slant_range_m: float) -> ThetaLimit:
    """theta_max as given, or derived from sigma_req at a few ranges up to S_max (see :class:`ThetaLimit`)."""
    if not params.derive_theta_max:
        return ThetaLimit(params.theta_max_deg, "given")
    model = params.incidence_model
    ranges = [s for s in THETA_REPORT_RANGES_M if s < max_slant_range_m] + [max_slant_range_m]
    rows = tuple(
        (round(s, 3), derive_theta_max_deg(s, scanner, params.budget, params.sigma_req_m, model)) for s in ranges
    )
    return ThetaLimit(
        min(incidence_limit_deg(model), 89.99), f"{model} model, sigma_req {params.sigma_req_m * 1000:g} mm", rows
    )
