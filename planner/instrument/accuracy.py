"""Accuracy model of chapter 2 of the dissertation (docs/method.md section 1).

All lengths are metres, angles degrees unless a name says otherwise (``_arcsec``, ``_mm``). Functions accept numpy
arrays where they take a range or an angle, so coverage tests can call them on whole candidate x target blocks.

References: equations (2.4), (2.5), (2.13)-(2.15), (3.1), (3.2), (3.28)-(3.32) and tables 1.1 and 2.3 of seed 000
(Shoker 2021).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from planner.core.errors import InfeasibleError, InputError

#: arc-seconds per radian (the print rounds it to 206265).
RHO_ARCSEC: float = 180.0 * 3600.0 / math.pi


@dataclass(frozen=True)
class RangeAngleSigma:
    """A distance-and-angle instrument error model: sigma_S = X + Y ppm, sigma_beta."""

    range_sigma_const_m: float
    range_sigma_ppm: float
    angle_sigma_arcsec: float


#: no accuracy term (sigma_req, station position, centring, graphical) is coarser (m): table 1.1 ends at 300 mm
MAX_SIGMA_M = 1.0


@dataclass(frozen=True)
class ErrorBudget:
    """The non-instrument terms of (2.13): station position, centring, graphical."""

    sigma_0_m: float = 0.0005
    centring_m: float = 0.0005
    graphical_m: float = 0.0005

    def __post_init__(self) -> None:
        for name in ("sigma_0_m", "centring_m", "graphical_m"):
            v = getattr(self, name)
            if not math.isfinite(v) or not 0 <= v <= MAX_SIGMA_M:  # 1e300 m overflowed its square
                raise InputError(f"must be a finite number >= 0 and <= {MAX_SIGMA_M:g} m", field=name, value=v)

    @property
    def squared_m2(self) -> float:
        """sigma_0^2 + sigma_c^2 + sigma_g^2 (m^2)."""
        return self.sigma_0_m**2 + self.centring_m**2 + self.graphical_m**2


def sigma_range_m(slant_m: ArrayLike, model: RangeAngleSigma) -> NDArray[np.float64]:
    """Range error sigma_S = X + Y * S / 1e6 (2.4)."""
    s = np.asarray(slant_m, dtype=float)
    return model.range_sigma_const_m + model.range_sigma_ppm * s / 1e6


def sigma_meas_m(slant_m: ArrayLike, model: RangeAngleSigma) -> NDArray[np.float64]:
    """One measurement's error sqrt(sigma_S^2 + (sigma_beta/rho * S)^2) (2.5, 2.15)."""
    s = np.asarray(slant_m, dtype=float)
    angular = model.angle_sigma_arcsec / RHO_ARCSEC * s
    return np.sqrt(sigma_range_m(s, model) ** 2 + angular**2)


def sigma_instr_m(sigma_req_m: float, budget: ErrorBudget) -> float:
    """Allowed instrument error sqrt(sigma_req^2 - (sigma_0^2 + sigma_c^2 + sigma_g^2)) (3.2); an
    InfeasibleError when the non-instrument errors alone use the whole budget."""
    left = sigma_req_m**2 - budget.squared_m2
    if left <= 0.0:
        raise InfeasibleError(
            "no instrument error budget left: required accuracy must exceed "
            f"sqrt(sigma_0^2 + centring^2 + graphical^2) = {math.sqrt(budget.squared_m2) * 1000:.4g} mm",
            field="sigma_req_mm",
            value=sigma_req_m * 1000,
        )
    return math.sqrt(left)


def max_slant_range_m(model: RangeAngleSigma, sigma_instr: float) -> float:
    """Largest slant range whose sigma_meas <= sigma_instr: the positive root of (3.1). S^2 (Y^2/1e12 +
    sigma_beta^2/rho^2) + S (2 X Y / 1e6) + X^2 - sigma_instr^2 = 0."""
    x, y = model.range_sigma_const_m, model.range_sigma_ppm
    a = y**2 / 1e12 + (model.angle_sigma_arcsec / RHO_ARCSEC) ** 2
    b = 2.0 * x * y / 1e6
    c = x**2 - sigma_instr**2
    if c >= 0.0:
        raise InfeasibleError(
            f"the instrument's constant range error {x * 1000:.4g} mm alone exceeds the allowed "
            "instrument error: no range satisfies the required accuracy",
            field="sigma_instr_mm",
            value=sigma_instr * 1000,
        )
    if a == 0.0:  # error independent of range beyond X: unlimited by accuracy
        return math.inf if b == 0.0 else -c / b
    return (-b + math.sqrt(b * b - 4.0 * a * c)) / (2.0 * a)


@dataclass(frozen=True)
class PointError:
    """Point error e and its components along (e_x) and across (e_y) the wall (2.13, 2.14)."""

    e_m: NDArray[np.float64]
    e_x_m: NDArray[np.float64]
    e_y_m: NDArray[np.float64]


def point_error(slant_m: ArrayLike, theta_deg: ArrayLike, model: RangeAngleSigma, budget: ErrorBudget) -> PointError:
    """e = sqrt(sigma_0^2 + sigma_c^2 + sigma_g^2 + sigma_meas^2), e_x = e sin(theta), e_y = e cos(theta)."""
    e = np.sqrt(budget.squared_m2 + sigma_meas_m(slant_m, model) ** 2)
    th = np.radians(np.asarray(theta_deg, dtype=float))
    return PointError(e_m=e, e_x_m=e * np.sin(th), e_y_m=e * np.cos(th))


def combined_sigma(*sigmas: float) -> float:
    """Independent errors add in quadrature: m = sqrt(sum m_i^2) (seed 002, formula 2)."""
    return math.sqrt(sum(s * s for s in sigmas))


def instrument_height_tolerance_m(wall_height_m: float, slant_m: float, ih_low_m: float, ih_high_m: float) -> float:
    """Radius of a station's tolerance circle for tripod heights IH1..IH2 (3.32). Delta_HD = SD/2 * [sqrt(1 - ((h -
    IH2)/SD)^2) - sqrt(1 - ((h - IH1)/SD)^2)]."""
    if not 0 <= ih_low_m <= ih_high_m or slant_m <= 0:
        raise InputError("need 0 <= IH1 <= IH2 and SD > 0", field="instrument_height_m", value=(ih_low_m, ih_high_m))

    def root(ih: float) -> float:
        r = (wall_height_m - ih) / slant_m
        if abs(r) > 1.0:
            raise InputError("wall taller than the slant range", field="wall_height_m", value=wall_height_m)
        return math.sqrt(1.0 - r * r)

    return slant_m / 2.0 * (root(ih_high_m) - root(ih_low_m))


@dataclass(frozen=True)
class IncidenceErrorTable:
    """Measured point error against incidence angle (table 2.3 of the dissertation; Leica P30). ``f_x`` is the error
    along the wall, ``f_y`` across it, both in mm, interpolated linearly over the table; the error grows linearly up to
    ``linear_until_deg``, so that span extrapolates the last segment; beyond it the table says nothing and the call is
    refused."""

    theta_deg: tuple[float, ...] = (0, 10, 20, 30, 40, 50, 60, 68)
    f_x_mm: tuple[float, ...] = (0.00, 1.23, 3.20, 4.43, 5.6, 6.52, 7.17, 7.60)
    f_y_mm: tuple[float, ...] = (8.22, 8.14, 7.55, 6.90, 6.33, 5.12, 3.95, 3.04)
    linear_until_deg: float = 79.0

    def measured_mm(self, theta_deg: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(f_x, f_y) in mm at the given incidence angles."""
        th = np.asarray(theta_deg, dtype=float)
        if np.any(th < 0) or np.any(th > self.linear_until_deg) or not np.all(np.isfinite(th)):
            raise InputError(
                f"incidence angle outside the measured model 0..{self.linear_until_deg:g} deg",
                field="theta_deg",
                value=float(np.max(np.abs(th))),
            )
        return self._interp(th, self.f_x_mm), self._interp(th, self.f_y_mm)

    def _interp(self, th: NDArray[np.float64], values: tuple[float, ...]) -> NDArray[np.float64]:
        xs, ys = np.asarray(self.theta_deg, float), np.asarray(values, float)
        out = np.interp(th, xs, ys)
        slope = (ys[-1] - ys[-2]) / (xs[-1] - xs[-2])
        beyond = th > xs[-1]
        return np.where(beyond, ys[-1] + slope * (th - xs[-1]), out)


#: Table 1.1 (GOST R 56905-2016): largest scale denominator of a row -> (min, max) error in mm.
DRAWING_SCALE_TOLERANCES_MM: tuple[tuple[int, float, float], ...] = (
    (20, 1.0, 2.0),
    (50, 2.0, 5.0),
    (100, 10.0, 20.0),
    (200, 30.0, 50.0),
    (500, 200.0, 300.0),
)


#: a drawing scale as text: ``1:50`` (spaces around the colon allowed) or ``50``, in plain decimal digits
_SCALE = r"(?:1\s*:\s*)?([0-9]+(?:\.[0-9]*)?)"


def parse_scale(text: str | int | float) -> int:
    """Read a drawing scale written ``"1:50"``, ``"50"`` or ``50`` into its denominator. Text takes plain decimal digits
    only: ``1:2_0`` (Python's digit grouping), ``1:5 0`` and ``1:5e1`` are refused, not read as 1:20 and 1:50, as the
    CSV and JSON readers refuse ``3_0``."""
    match = re.fullmatch(_SCALE, text.strip(), re.ASCII) if isinstance(text, str) else None
    if match is not None:
        denominator = float(match.group(1))
    elif isinstance(text, (int, float)) and not isinstance(text, bool):
        denominator = float(text)
    else:
        raise InputError("not a drawing scale like 1:50", field="drawing_scale", value=str(text))
    if not math.isfinite(denominator) or denominator < 1 or denominator != int(denominator):
        raise InputError("scale denominator must be a whole number >= 1", field="drawing_scale", value=str(text))
    return int(denominator)


def tolerance_for_scale_m(scale: str | int | float) -> float:
    """Largest allowed error for a drawing scale (table 1.1, the row's upper value); a scale between two rows
    takes the stricter row, scales smaller than the table's last are refused."""
    n = parse_scale(scale)
    if n > DRAWING_SCALE_TOLERANCES_MM[-1][0]:
        raise InputError("scale outside table 1.1 (1:1 .. 1:500)", field="drawing_scale", value=f"1:{n}")
    coarser = [high for largest, _low, high in DRAWING_SCALE_TOLERANCES_MM if largest <= n]
    return (coarser[-1] if coarser else DRAWING_SCALE_TOLERANCES_MM[0][2]) / 1000.0


#: Incidence models of the view error: none (range only), the measured table 2.3, Soudarissanane et al. 2011.
INCIDENCE_MODELS: tuple[str, ...] = ("none", "table", "soudarissanane")
#: largest incidence the Soudarissanane model is evaluated at (1/cos grows without bound towards 90 deg)
SOUDARISSANANE_MAX_DEG: float = 85.0
#: a view's error may pass sigma_req by this rounding (m)
PRECISION_EPS_M = 1e-12
#: the bisection of :func:`derive_theta_max_deg` stops at this width (deg)
THETA_TOL_DEG = 1e-6


def incidence_limit_deg(model: str) -> float:
    """Largest incidence angle a model speaks for: 79 deg for the table (its linear stretch), 85 for 1/cos, 90 for none."""
    if model == "table":
        return IncidenceErrorTable().linear_until_deg
    if model == "soudarissanane":
        return SOUDARISSANANE_MAX_DEG
    if model == "none":
        return 90.0
    raise InputError(
        f"unknown incidence model (known: {', '.join(INCIDENCE_MODELS)})", field="incidence_model", value=model
    )


def incidence_factor(incidence_deg: ArrayLike, model: str) -> NDArray[np.float64]:
    """How much the instrument term of a view grows with incidence, relative to a perpendicular view. ``table``: the
    measured ratio (table 2.3): at normal incidence the error is f_y(0) across the wall; with incidence an along-wall
    error f_x(theta) appears, so k = sqrt(f_y(0)^2 + f_x(theta)^2) / f_y(0). ``soudarissanane``: 1 / cos(theta) (the
    signal-to-noise ratio falls with cos theta, Soudarissanane et al. 2011), applied to the range term only (see
    :func:`view_error_m`). ``none``: 1. Angles beyond a model's limit are clipped to it (the limit itself is enforced by
    the coverage test)."""
    th = np.clip(np.asarray(incidence_deg, dtype=float), 0.0, incidence_limit_deg(model))
    if model == "table":
        table = IncidenceErrorTable()
        fx, _ = table.measured_mm(th)
        fy0 = table.f_y_mm[0]
        return np.sqrt(fy0**2 + fx**2) / fy0
    if model == "soudarissanane":
        return 1.0 / np.cos(np.radians(th))
    return np.ones_like(th)


def view_error_m(
    slant_m: ArrayLike, incidence_deg: ArrayLike, scanner: RangeAngleSigma, budget: ErrorBudget, model: str = "none"
) -> NDArray[np.float64]:
    """Point error e(S, theta) of one view: (2.13) with the incidence effect on the instrument term. e^2 = sigma_0^2 +
    sigma_c^2 + sigma_g^2 + sigma_meas(S, theta)^2, where for ``table`` sigma_meas(S, theta) = sigma_meas(S) * k(theta)
    and for ``soudarissanane`` the range term sigma_S grows as 1/cos(theta) while the angular term stays. ``none`` is
    (2.13) as printed. The one function coverage, verification, the report and the network check use."""
    s = np.asarray(slant_m, dtype=float)
    if model == "soudarissanane":
        angular = scanner.angle_sigma_arcsec / RHO_ARCSEC * s
        rng = sigma_range_m(s, scanner) * incidence_factor(incidence_deg, model)
        meas2 = rng**2 + angular**2
    else:
        meas2 = (sigma_meas_m(s, scanner) * incidence_factor(incidence_deg, model)) ** 2
    return np.sqrt(budget.squared_m2 + meas2)


def precision_ok(
    slant_m: ArrayLike,
    incidence_deg: ArrayLike,
    scanner: RangeAngleSigma,
    budget: ErrorBudget,
    sigma_req_m: float,
    model: str = "none",
) -> NDArray[np.bool_]:
    """One view meets the required accuracy: e(S, theta) <= sigma_req (single-view precision)."""
    return view_error_m(slant_m, incidence_deg, scanner, budget, model) <= sigma_req_m + PRECISION_EPS_M


def combined_error_m(errors_m: ArrayLike) -> float:
    """Error of a point seen by several independent views: information adds, 1/e^2 = sum 1/e_j^2."""
    info = float(np.sum(1.0 / np.square(np.asarray(errors_m, dtype=float))))
    return math.inf if info == 0.0 else 1.0 / math.sqrt(info)


def derive_theta_max_deg(
    slant_m: float, scanner: RangeAngleSigma, budget: ErrorBudget, sigma_req_m: float, model: str = "table"
) -> float:
    """Largest incidence at which a view at slant range S still meets sigma_req (bisection on e(S, theta)): the
    model's limit when even that incidence meets it, 0 when a perpendicular view at S already fails."""
    hi = incidence_limit_deg(model)
    ok = lambda th: bool(precision_ok(slant_m, th, scanner, budget, sigma_req_m, model))  # noqa: E731
    if ok(hi):
        return hi
    if not ok(0.0):
        return 0.0
    lo = 0.0
    while hi - lo > THETA_TOL_DEG:
        mid = (lo + hi) / 2.0
        lo, hi = (mid, hi) if ok(mid) else (lo, mid)
    return lo


def max_slant_for_view_m(
    incidence_deg: ArrayLike, scanner: RangeAngleSigma, budget: ErrorBudget, sigma_req_m: float, model: str = "none"
) -> NDArray[np.float64]:
    """Largest slant range S with e(S, theta) <= sigma_req, per incidence (0 where not even S = 0 does). e grows with S
    at any incidence, so the views meeting sigma_req at incidence theta are those with S <= this value: the boundary of
    the precision part of a coverage region. With k = k(theta), the range term k_r (X + Y S) and the angular term k_a
    (sigma_beta / rho) S (table: k_r = k_a = k; Soudarissanane: k_r = k, k_a = 1; none: 1) give the positive root of
    (3.1) generalised: S^2 (k_r^2 Y^2 + k_a^2 b^2) + 2 S k_r^2 X Y + k_r^2 X^2 - (sigma_req^2 - sigma_0^2 - sigma_c^2 -
    sigma_g^2) = 0."""
    k = incidence_factor(np.atleast_1d(np.asarray(incidence_deg, dtype=float)), model)
    k_a = np.ones_like(k) if model == "soudarissanane" else k
    x, y = scanner.range_sigma_const_m, scanner.range_sigma_ppm / 1e6
    b = scanner.angle_sigma_arcsec / RHO_ARCSEC
    m = sigma_req_m**2 - budget.squared_m2
    qa, qb, qc = k**2 * y**2 + k_a**2 * b**2, 2.0 * k**2 * x * y, k**2 * x**2 - m
    with np.errstate(invalid="ignore", divide="ignore"):
        root = (-qb + np.sqrt(np.maximum(qb**2 - 4.0 * qa * qc, 0.0))) / (2.0 * qa)
    return np.where(qc <= 0.0, np.maximum(root, 0.0), 0.0)
